"""dyntorsion: dynamic torsional buckling of elastic rods.

A replication of *Dynamic torsional buckling: prebuckling waves and delayed
instability*: the body-frame Cosserat rod (section 2), the generalised-alpha
method in space and time (section 3), rod shapes (section 4), prebuckling
torsional waves (section 5) and delayed buckling (section 6).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ._version import __version__
from .model.rod import Rod

if TYPE_CHECKING:
    from .buckling.scene import Scene

__all__ = ["Rod", "Scene", "__version__", "run_scene"]


def __getattr__(name: str) -> Any:
    """``Scene``, imported from the buckling layer on first use (as :func:`run_scene` is)."""
    if name == "Scene":
        from .buckling.scene import Scene

        return Scene
    raise AttributeError(f"module 'dyntorsion' has no attribute {name!r}")


def run_scene(scene: Scene, rtol: float | None = None, **options: Any) -> dict[str, Any]:
    """Run one buckling scene (section 6) and detect its onset.

    Without ``rtol``: :func:`dyntorsion.buckling.scene.run_scene` on the scene's own grid.
    With ``rtol`` (a relative tolerance in (0, 1]): the scene's grid is replaced by the
    cheapest rung of the fidelity ladder whose estimated errors of t_c and kappa3 (the
    rungs' differences and the solver check's change) meet it,
    :func:`dyntorsion.studies.tolerance.onset_within` (``options``: its ``max_cells``,
    ``store``, ``compute``, ``reading``: continuous time by default); the dict then holds
    ``t_c``, ``t_c_error``, ``kappa3``, ``kappa3_error``, the grid (``rung``, ``n_cells``,
    ``dt``), ``met``, every rung run and the solver check.  (The buckling layer cannot
    import the studies that choose the grid, so the choice is made here, above both.)
    """
    if rtol is None:
        if options:
            raise TypeError(f"run_scene: {sorted(options)} need rtol")
        from .buckling.scene import run_scene as run

        return run(scene)
    from .studies.tolerance import onset_within

    return onset_within(scene, rtol, **options).as_dict()
