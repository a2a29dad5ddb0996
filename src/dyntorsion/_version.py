"""The package's version, defined here once: pyproject.toml reads it (``dynamic``),
``dyntorsion --version`` prints it, every record and every page of the site carry it, and
a test holds CITATION.cff to it."""

__version__ = "0.2.0"

__all__ = ["__version__"]
