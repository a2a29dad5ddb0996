"""Tests of dyntorsion.genalpha."""
