"""Sphinx configuration of the dyntorsion replication site."""

from importlib.metadata import version as _version

project = "dyntorsion"
author = "The dyntorsion developers"
release = _version("dyntorsion")
extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
myst_enable_extensions = ["dollarmath", "amsmath"]
# notebooks always run: the jupyter cache would not see changes to src/
nb_execution_mode = "force"
nb_execution_raise_on_error = True
nb_execution_timeout = 1800
exclude_patterns = ["_build", "jupyter_execute", "**.ipynb_checkpoints"]
html_theme = "alabaster"
html_title = "dyntorsion"
autodoc_member_order = "bysource"
autodoc_typehints = "description"
