"""Tests of dyntorsion.beyond."""
