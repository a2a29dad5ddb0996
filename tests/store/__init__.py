"""Tests of dyntorsion.store."""
