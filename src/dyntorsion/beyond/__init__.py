"""Beyond the paper: why buckling is delayed.

* :mod:`.linear_stability` -- the linearised lateral motion of the twisted, spinning rod
  (eq L2) and its slow passage through the critical twist;
* :mod:`.passage` -- the compiled march of that passage;
* :mod:`.predictions` -- one scene's onset predicted by the linear theory, and the fast
  estimate that paces a sweep.

Built on sections 2-6; it imports none of the studies, the store or the application.
"""
