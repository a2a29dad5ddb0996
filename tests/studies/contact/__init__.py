"""Tests of dyntorsion.studies.contact."""
