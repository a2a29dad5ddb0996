"""Sphinx configuration of the dyntorsion replication site."""

import os
import sys
from pathlib import Path

from dyntorsion import __version__
from dyntorsion._numba import NOTICE_VARIABLE

# the notebooks' kernels inherit it: no page shows the one-time compile notice of the build
os.environ[NOTICE_VARIABLE] = "0"

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
    "sphinx.ext.viewcode",  # each API entry links to its source, highlighted, on the site
    "offline_mathjax",  # sphinx-mathjax-offline, parallel-safe (docs/_ext)
]
# a name a module imports is linked from its own module's source only (followed into the
# importing module, viewcode linked e.g. linear_stability.Tensors to an anchor no page has)
viewcode_follow_imported_members = False
myst_enable_extensions = ["dollarmath", "amsmath"]
# notebooks always run: the jupyter cache would not see changes to src/
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 1800
exclude_patterns = [
    "_build",
    "_ext",
    "jupyter_execute",
    "**.ipynb_checkpoints",
    "site_check.py",
    "site_budget.py",
    "site_selftest.py",
]
# sphinx-book-theme: "on this page" and the site's outline on the left, one column on a
# phone; its fonts, icons and scripts are files of the build (no CDN), and
# nothing links out to a repository, Binder or a download service
html_theme = "sphinx_book_theme"
html_title = f"dyntorsion {__version__}"
html_static_path = ["_static"]
html_css_files = ["site.css"]
html_theme_options = {
    "home_page_in_toc": True,
    "show_toc_level": 2,
    "toc_title": "On this page",
    "use_download_button": False,
    "use_fullscreen_button": False,
    "use_repository_button": False,
    "use_source_button": False,
    "use_issues_button": False,
    "use_edit_page_button": False,
    "launch_buttons": {},
    "navigation_with_keys": False,
    "show_navbar_depth": 1,
    "footer_content_items": ["copyright"],
    # the page's outline goes to the left, above the site's: a second sidebar on the
    # right would leave the article too narrow for the figures' smallest text
    "secondary_sidebar_items": [],
}
html_sidebars = {
    "**": ["navbar-logo.html", "search-button-field.html", "page-toc.html", "sbt-sidebar-nav.html"]
}
# light only: the figures are drawn on white
html_context = {"default_mode": "light"}
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


#: the docstrings of Python's own types: a module constant (a float, a tuple) would show
#: its type's ("Convert a string or number to a floating point number, if possible.")
_BUILTIN_DOCS = {
    t.__doc__ for t in (float, int, str, tuple, list, dict, set, frozenset, bool, complex, bytes)
}


def _no_builtin_docstring(app, what, name, obj, options, lines):
    """An object documented by its type's built-in docstring gets none (its ``#:`` comment,
    if any, is the documentation); the site check fails on a built-in docstring left in."""
    if what in ("data", "attribute") and type(obj).__doc__ in _BUILTIN_DOCS:
        doc = type(obj).__doc__.strip().splitlines()
        if [ln.strip() for ln in lines if ln.strip()][: len(doc)] == [
            ln.strip() for ln in doc if ln.strip()
        ][: len(doc)]:
            lines.clear()


def _keep_glue(app, exception):
    """Copy the glued values of every executed page (myst-nb writes them beside the build,
    shared by all builds) into the build, ``_glue/<page>.glue.json``: the site check reads
    them to find one glue key shown with two values on two pages."""
    import shutil

    if exception is not None or app.builder.format != "html":
        return
    source = Path(app.outdir).parent / "jupyter_execute"
    target = Path(app.outdir) / "_glue"
    shutil.rmtree(target, ignore_errors=True)
    for doc in app.env.found_docs:
        glued = source / f"{doc}.glue.json"
        if glued.is_file():
            (target / doc).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(glued, target / f"{doc}.glue.json")


def _drop_dangling_viewcode_links(app, exc):
    """Remove the ``[docs]`` and ``[source]`` links of sphinx.ext.viewcode whose anchor no
    page has.  viewcode tags a module's names by where they are bound, so a kernel module
    imported by another (``passage`` by ``linear_stability``) got ``[docs]`` links to
    ``linear_stability.Tensors``, and a property (``Rod.isotropic``) a ``[source]`` link to
    an anchor its source page lacks; ``make site-check`` reports any link that dangles."""
    import re
    from pathlib import Path

    if exc is not None or app.builder.format != "html":
        return
    out = Path(app.outdir).resolve()
    ids: dict[Path, set[str]] = {}

    def has(target: Path, anchor: str) -> bool:
        if target not in ids:
            text = target.read_text(encoding="utf-8") if target.is_file() else ""
            ids[target] = set(re.findall(r'id="([^"]+)"', text))
        return anchor in ids[target]

    link = re.compile(
        r'<a class="(?:viewcode-back|reference internal)" href="([^"#]+)#([^"]+)">'
        r'(?:\[docs\]|<span class="viewcode-link"><span class="pre">\[source\]</span></span>)</a>'
    )
    for page in out.rglob("*.html"):
        text = page.read_text(encoding="utf-8")

        def keep(m, page=page):
            return m.group(0) if has((page.parent / m.group(1)).resolve(), m.group(2)) else ""

        new = link.sub(keep, text)
        if new != text:
            page.write_text(new, encoding="utf-8")


def setup(app):
    app.connect("autodoc-process-docstring", _no_builtin_docstring)
    app.connect("build-finished", _keep_glue)
    app.connect("build-finished", _drop_dangling_viewcode_links)
    app.connect("doctree-resolved", _alt_text)
    app.connect("autodoc-process-signature", _factory_defaults)
