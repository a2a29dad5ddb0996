"""Tests of dyntorsion.waves."""
