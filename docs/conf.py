"""Sphinx configuration of the dyntorsion replication site."""

import sys
from pathlib import Path

from dyntorsion import __version__

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "dyntorsion"
author = "The dyntorsion developers"
release = version = __version__
# the footer: the version on every page, no copyright line without a holder
copyright = f"the dyntorsion developers · version {__version__} · MIT licence"
html_show_sphinx = False
# MathJax is served from the build (sphinx-mathjax-offline bundles MathJax 3): no
# page loads anything from the network.
extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "offline_mathjax",  # sphinx-mathjax-offline, parallel-safe (docs/_ext)
]
myst_enable_extensions = ["dollarmath", "amsmath"]
# notebooks always run: the jupyter cache would not see changes to src/
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 1800
exclude_patterns = ["_build", "_ext", "jupyter_execute", "**.ipynb_checkpoints", "site_check.py"]
html_theme = "alabaster"
html_title = f"dyntorsion {__version__}"
html_static_path = ["_static"]
html_css_files = ["site.css"]
# the body as wide as a 1280 px screen allows, so the equations fit
html_theme_options = {"page_width": "1240px", "sidebar_width": "220px", "font_size": "16px"}
# Markdown that cells display (the glance tables) is MyST: maths, tables, links to pages
nb_render_markdown_format = "myst"
autodoc_member_order = "bysource"
autodoc_typehints = "description"
# defaults as written in the source (``source=inspect.getsource``, not a repr)
autodoc_preserve_defaults = True


def _alt_text(app, doctree, docname):
    """Every image gets alt text: its figure's caption, else the title of its section."""
    from docutils import nodes

    for img in doctree.findall(nodes.image):
        if img.get("alt") and img["alt"] != img.get("uri"):
            continue
        parent, caption = img.parent, None
        while parent is not None and caption is None:
            if isinstance(parent, nodes.figure):
                caption = next(iter(parent.findall(nodes.caption)), None)
            parent = parent.parent if caption is None else parent
        if caption is None:
            section = img.parent
            while section is not None and not isinstance(section, nodes.section):
                section = section.parent
            title = section.next_node(nodes.title) if section is not None else None
            img["alt"] = f"Plot: {title.astext() if title is not None else docname}"
        else:
            img["alt"] = caption.astext()


def _factory_defaults(app, what, name, obj, options, signature, return_annotation):
    """A dataclass field made by a factory shows the factory (``rod=Rod.paper()``), not
    Python's placeholder ``<factory>``."""
    import dataclasses
    import re

    if not signature or "<factory>" not in signature or not dataclasses.is_dataclass(obj):
        return None
    for f in dataclasses.fields(obj):
        if f.default_factory is not dataclasses.MISSING:
            made = getattr(f.default_factory, "__qualname__", "<lambda>")
            made = "…" if "<" in made else f"{made}()"
            signature = re.sub(rf"\b{f.name}=<factory>", f"{f.name}={made}", signature)
    return signature, return_annotation


def setup(app):
    app.connect("doctree-resolved", _alt_text)
    app.connect("autodoc-process-signature", _factory_defaults)
