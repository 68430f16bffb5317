"""Analyses of a result: they measure M_S, they never build it.

* :mod:`.topology`: closedness, vertex links, Z/2 Betti numbers, Euler
  characteristic, orientability, components.
* :mod:`.quality`: the estimated sampling quality epsilon per sample.
* :mod:`.theorems`: Theorems 2 and 10 on the built-in manifolds.
* :mod:`.compare`: M_S against a mesh's faces, Hausdorff distances.
* :mod:`.complexdiff`: two complexes, simplex by simplex.

May import: numpy, scipy, :mod:`crustview.core.delaunay`,
:mod:`crustview.core.samples`, :mod:`crustview.core.util`, and the pipeline's
:mod:`~crustview.core.result`, :mod:`~crustview.core.steps` and
:mod:`~crustview.core.errors`.  Never the
robust extension (:mod:`crustview.core.robust`), the pipeline's
:mod:`~crustview.core.reconstruct`, nor the viewer (scene, render, qt)
(``tests/test_core_boundaries.py``).
"""
