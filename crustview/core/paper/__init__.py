"""The paper: Algorithms 1-3 of *Reconstruction of Submanifolds of Euclidean Space* as printed.

* :mod:`.normals`: Algorithm 1, the poles and the approximate normal planes AN_s.
* :mod:`.candidates`: Algorithm 2, the candidate complex T_S with the two
  cocone tests; :mod:`.literal` is the paper's literal orientation test, and
  :mod:`.conemin`, :mod:`.dualcells` and :mod:`.exactmin` the geometry of
  the cocone score over each face's dual Voronoi cell.
* :mod:`.extraction`: Algorithm 3 as printed (``prune-sharp``,
  ``resolve-nonmanifold``), a recorded sequence of steps; :mod:`.facets` the
  facet table and opposite vectors its rules read.

The documented interpretations of the paper (``docs/algorithm.md``) live
here beside the code they decide.

May import: numpy, scipy, :mod:`crustview.core.delaunay` (face lists and the
compiled kernels), :mod:`crustview.core.util`, and the pipeline's
:mod:`~crustview.core.result`, :mod:`~crustview.core.steps` and
:mod:`~crustview.core.errors`.  Never the
robust extension (:mod:`crustview.core.robust`) nor the pipeline's
:mod:`~crustview.core.reconstruct` (``tests/test_core_boundaries.py``).
"""
