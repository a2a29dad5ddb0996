"""Tests of dyntorsion.model."""
