"""The records of runs past self-contact kept in ``data/contact`` and ``data/bench``: one
module per record, each run as ``python -m dyntorsion.studies.contact.<module>`` (the
``make`` targets of ``data/README.md``), writing its record atomically and resuming it.

Each record carries its provenance (:func:`dyntorsion.store.fingerprint.script_provenance`:
the module's code digest, the roots of the package code it runs and their fingerprint),
which :func:`~dyntorsion.store.fingerprint.why_stale` checks on the pages and in the tests.
The PyElastica half of the plectoneme comparison imports ``elastica`` (the ``bench`` extra)
and stays in ``benchmarks/`` beside the timing benchmarks.
"""
