"""dyntorsion."""
