"""Tests of dyntorsion.app."""
