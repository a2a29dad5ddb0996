"""The tests of dyntorsion, in folders that mirror the package's; tests/site checks the
docs, the examples, the install and the layout of the repository."""
