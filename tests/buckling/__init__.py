"""Tests of dyntorsion.buckling."""
