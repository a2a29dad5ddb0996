"""How the command line answers a fault: one line saying what went wrong, which file or
parameter, and what to do (:func:`describe`), and an exit status by kind."""

from __future__ import annotations

__all__ = ["describe", "blank_value", "EXIT_INPUT", "EXIT_FAILED", "EXIT_BUG", "EXIT_INTERRUPTED"]

#: exit status of a refused input, of a failed computation or unusable store, of a bug
EXIT_INPUT, EXIT_FAILED, EXIT_BUG, EXIT_INTERRUPTED = 2, 1, 3, 130


def describe(err: BaseException) -> tuple[str, int]:
    """One line for a package error (what, which file or parameter, what to do) and the
    exit status."""
    from concurrent.futures import BrokenExecutor

    from ..genalpha import ConvergenceError
    from ..store.results import CorruptResultError, StaleResultError
    from ..store.workers import MissingResultError

    lines = [ln.strip() for ln in str(err).splitlines() if ln.strip()]
    text = (
        " ".join(lines)
        if len(lines) < 2
        else f"{lines[0]} ({lines[1]}{', ...' if len(lines) > 3 else ''}); {lines[-1]}"
    )
    if isinstance(err, ValueError | TypeError):
        return text, EXIT_INPUT
    if isinstance(err, StaleResultError | CorruptResultError | MissingResultError):
        return text, EXIT_FAILED
    if isinstance(err, ConvergenceError):
        return f"{text}; refine --dt or change the Newton options", EXIT_FAILED
    if isinstance(err, ConnectionError | BrokenExecutor):
        return text, EXIT_FAILED
    if isinstance(err, OSError):
        return _os_error(err, text), EXIT_FAILED
    if isinstance(err, MemoryError):
        return f"out of memory ({text or 'no detail'}); raise --dt or lower --t-end", EXIT_FAILED
    return (
        f"internal error {type(err).__name__}: {text}; rerun with --debug and report it",
        EXIT_BUG,
    )


def blank_value(argv: list[str]) -> str | None:
    """The refusal of an option given an empty or blank value (``--store ''`` would
    otherwise mean the working directory, ``--ellipse ''`` the default circle), or None."""
    for i, tok in enumerate(argv):
        name, eq, value = tok.partition("=")
        if tok.startswith("--") and eq and not value.strip():
            return f"{name}={value!r} is empty; give a value or leave the option out"
        if not tok.strip():
            name = argv[i - 1] if i and argv[i - 1].startswith("-") else "an argument"
            return f"{name}={tok!r} is empty; give a value or leave the option out"
    return None


def _os_error(err: OSError, text: str) -> str:
    """What a failed file operation means for the store: the path and what to do."""
    from pathlib import Path

    where = Path(err.filename) if err.filename else None
    if where is not None and isinstance(err, FileExistsError | NotADirectoryError):
        for folder in (where, *where.parents):
            if folder.is_symlink() and not folder.exists():
                return f"{folder} is a broken symbolic link, not a folder; give --store a folder"
            if folder.is_file():
                return f"{folder} is a file, not a folder; give --store a folder"
    what = err.strerror or text
    return (
        f"{what}{f': {where}' if where else ''}; check that the path exists, is writable and "
        "the disk has space (--store or $DYNTORSION_DATA)"
    )
