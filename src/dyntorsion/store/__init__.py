"""Records with provenance: keys, content hashes, code fingerprints, leases between
concurrent sweeps and the worker processes that fill a store.  The store knows no physics:
it imports nothing of the paper's sections.
"""
