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
    "contact_budget.py": (
        "dyntorsion.studies.contact.contact_budget",
        "f0629d52e332707120ec0faaf2b4e6fb47ed2605e2c1371fc959be4ebc5ca3fb",
        "5aa50ce59a623cff57cda2802069a2482923b8fb5af0a8dcc53e86377de0ddff",
    ),
    "contact_convergence.py": (
        "dyntorsion.studies.contact.contact_convergence",
        "823efd3eee1d778fc20669ffb8cfa9ca9845f17b641db75810bde95ecd3fcc4d",
        "821322974a870c504794dbbf50099d387c753f32a6b6bdb88b3e3140142d0484",
    ),
    "contact_roundoff.py": (
        "dyntorsion.studies.contact.contact_roundoff",
        "404dbfb96fd6945134fe34dcc456af9903efdd802f67f3a0d2352ff9a061fe53",
        "3bddaebba8fbb8b766682c6bf36f41ee682c542fc059b2a68930724be5648170",
    ),
    "contact_six_seconds.py": (
        "dyntorsion.studies.contact.contact_six_seconds",
        "d1bdf5a539fb3b2007696ba75d53817da81632fe5a5bbc38726a63a906d456d2",
        "e45882c23226cc560e1c41a3aa70e49a15dcbe525ba4e63f2beebcf492ac8058",
    ),
    "fig07_continued.py": (
        "dyntorsion.studies.contact.fig07_continued",
        "4bded2a3869d557b827d68ed0ccfe57dada474fb75f6e0af2e5b72992067b86f",
        "906444ec8c5dc1fe8d6971a3ce63780b95799189937c72c4cd7e601de7f0c354",
    ),
    "plectoneme_bounds.py": (
        "dyntorsion.studies.contact.plectoneme_bounds",
        "4178fd9eccf92317bd3c163c42cbebd3abeb0c1d52db5b94d3f1de8cf8dfa099",
        "15795c9362a25413cb1d6344ec55b28e633e2edf807aece4633ad0eea048442e",
    ),
    "plectoneme_dyntorsion.py": (
        "dyntorsion.studies.contact.plectoneme_dyntorsion",
        "7ccc92e940313c495541d8a1133c8b0c115cbae902d8b2fb5cbb81872c9e34f8",
        "78ad9bd2792049d93ae3f91cc37d890c0663ce88d1ba95d34c4a6fbe80f392fc",
    ),
    "plectoneme_plateau.py": (
        "dyntorsion.studies.contact.plectoneme_plateau",
        "f35933b67a90865c1bee3f5c4aa6aca7ea81e33ae3378ac5662a1a9bf246fc53",
        "2d4b2ead35acb527db6dcdb59e7548809b826d959cbd2da45892cce50d53d4d9",
    ),
    "plectoneme_tension.py": (
        "dyntorsion.studies.contact.plectoneme_tension",
        "be52779b39c66b450e1ac25414f1e092b3171d6f260d8490bbeb814961c89786",
        "a58687834db7d1418a5cd77ce483efd1a7384a5b6bfd00607d2178ec689d7d94",
    ),
    "pyelastica_plectoneme.py": (
        "benchmarks/pyelastica_plectoneme.py",
        "83b6ef6882f56415a463feafb0ba209595d57304728c65fd83f4b9eadd9f7653",
        "e8f8dc8d52b030017f1c7d83cc92f7cac651d331bc245dc24bea8a2667238906",
    ),
    "plectoneme_matched.py": (
        "benchmarks/plectoneme_matched.py",
        "f922413d8edad626731616ec444a2d727c6fba67ef7f457cbd600f3243d5dc0d",
        "8cf4673dfdca264ed44974c8a7e8d0c6884e5a3bdc62001763ad83c4b5febb06",
    ),
}
