"""``sphinx-mathjax-offline`` declared safe for parallel builds: it only points
``mathjax_path`` at the bundled MathJax and copies those files when the build has
finished, so reading and writing pages in several processes (``sphinx-build -j``, each
process executing its own notebooks) cannot race on it.  The package itself does not say,
and Sphinx then reads every page serially."""

import importlib

_offline = importlib.import_module("sphinx-mathjax-offline")


def setup(app):
    _offline.setup(app)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
