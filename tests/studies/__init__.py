"""Tests of dyntorsion.studies."""
