"""Tests of dyntorsion.beyond.contact."""
