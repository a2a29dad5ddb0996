"""A user's own histories, loads, seed forms and end sets on the command line.

``--plugin FILE_OR_MODULE`` imports a Python file (its folder goes on the module path,
so that worker processes import it too) or an importable module before the options are
read: the classes it defines with a ``kind`` register themselves, and the end sets it
passes to :func:`dyntorsion.model.ends.register` join :data:`~dyntorsion.model.ends.ENDS`.
``--history KIND:name=value,...`` and ``--load KIND:name=value,...`` then build any
registered kind from its constructor's keywords (:func:`build`)."""

from __future__ import annotations

import importlib
import inspect
import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = ["PluginError", "plugins_in", "load_plugins", "parse_kind", "build"]


class PluginError(ValueError):
    """A plugin that cannot be imported, or that raised while it was imported."""


def plugins_in(argv: Sequence[str]) -> list[str]:
    """The values of every ``--plugin X`` and ``--plugin=X`` in ``argv``."""
    out = []
    for i, arg in enumerate(argv):
        if arg == "--plugin" and i + 1 < len(argv):
            out.append(argv[i + 1])
        elif arg.startswith("--plugin="):
            out.append(arg.split("=", 1)[1])
    return out


def load_plugins(specs: Sequence[str]) -> list[Any]:
    """Import each plugin (a ``.py`` file or a module name); PluginError naming the plugin
    and the option for one that cannot be found or raises on import."""
    modules = []
    for spec in specs:
        path = Path(spec)
        try:
            if spec.endswith(".py") or path.is_file():
                if not path.is_file():
                    raise FileNotFoundError(f"no such file {spec!r}")
                folder = str(path.resolve().parent)
                if folder not in sys.path:
                    sys.path.insert(0, folder)
                    # spawned worker processes import the plugin's classes by name too
                    old = os.environ.get("PYTHONPATH")
                    os.environ["PYTHONPATH"] = folder + (os.pathsep + old if old else "")
                name = path.stem
            else:
                name = spec
            modules.append(importlib.import_module(name))
        except Exception as err:  # the plugin's own error, whatever it is
            raise PluginError(
                f"--plugin {spec}: cannot import it ({type(err).__name__}: {err})"
            ) from err
    return modules


def _number(text: str) -> Any:
    """A value of ``name=value``: a number, numbers separated by ';' (a tuple), or text."""
    if ";" in text:
        return tuple(_number(v) for v in text.split(";") if v)
    try:
        return float(text)  # "2" is 2.0, as in a key written from Python
    except ValueError:
        return text


def parse_kind(text: str, option: str) -> tuple[str, dict[str, Any]]:
    """``KIND:name=value,...`` as (kind, keywords); ValueError naming ``option``."""
    kind, _, rest = text.partition(":")
    keywords = {}
    for item in filter(None, rest.split(",")):
        name, eq, value = item.partition("=")
        if not eq or not name:
            raise ValueError(f"{option} {text!r}: write KIND:name=value,... (got {item!r})")
        keywords[name.strip()] = _number(value.strip())
    return kind, keywords


def build(
    registry: Mapping[str, type], what: str, text: str, option: str, defaults: Mapping = {}
) -> Any:
    """The object of ``KIND:name=value,...`` from ``registry``: ``defaults`` fill the
    constructor's keywords the text does not give (when the constructor takes them).
    ValueError naming the option, the registered kinds or the constructor's keywords."""
    kind = text.partition(":")[0]
    if kind not in registry:
        raise ValueError(
            f"{option} {text!r}: no {what} of kind {kind!r}; registered: "
            f"{', '.join(sorted(registry))} (--plugin FILE adds a user's own)"
        )
    kind, keywords = parse_kind(text, option)
    cls = registry[kind]
    params = inspect.signature(cls).parameters
    unknown = sorted(set(keywords) - set(params))
    if unknown:
        raise ValueError(
            f"{option} {text!r}: {kind} takes no {', '.join(unknown)}; its keywords: "
            f"{', '.join(params)}"
        )
    keywords = {**{k: v for k, v in defaults.items() if k in params}, **keywords}
    try:
        return cls(**keywords)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{option} {text!r}: {err}") from None
