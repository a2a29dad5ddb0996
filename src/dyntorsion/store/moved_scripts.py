"""Record-writing scripts that moved into the package or were edited where they stay.

Each entry is ``old file name -> (the module it became, or its path in the checkout where
it stays; the sha256 of the script's last version as a script; the digest of its code
since)``, the digest being :func:`dyntorsion.store.fingerprint._digest`'s: the syntax tree
without docstrings, comments and imports.  A committed record that carries the old
script's sha256 was computed by the code the digest pins (the move changed only imports
and the paths of ``data/``): :func:`dyntorsion.store.fingerprint.why_stale` keeps it
current while that code, and the code its roots reach, is unchanged, and calls it stale
after any edit of that code.  A record written since names its module and digest itself
and needs no entry here.
"""

from __future__ import annotations

__all__ = ["MOVED_SCRIPTS"]

MOVED_SCRIPTS: dict[str, tuple[str, str, str]] = {
    "pyelastica_plectoneme.py": (
        "benchmarks/pyelastica_plectoneme.py",
        "83b6ef6882f56415a463feafb0ba209595d57304728c65fd83f4b9eadd9f7653",
        "e8f8dc8d52b030017f1c7d83cc92f7cac651d331bc245dc24bea8a2667238906",
    ),
}
