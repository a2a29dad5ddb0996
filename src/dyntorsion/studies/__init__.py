"""Many scenes at once: sweeps, their presets, pacing and the fidelity ladder, the cached
linear predictions, the consistency map of the paper's dynamic claims and the traces that
compare theory with simulation.  Each reads and writes records through :mod:`dyntorsion.store`.
"""

from . import kinds as kinds  # registers the record kinds' code roots with the store
