"""The built-in test manifolds and their point samples.

* :mod:`.sampling`: charts, :class:`~.sampling.TestManifold` and its
  sampler (rejection on the volume element, farthest-point thinning).
* :mod:`.manifolds`: the catalogue, ``MANIFOLDS`` and ``get_manifold``,
  built on :mod:`.sampling` (one way: the sampler knows no manifold).

May import: numpy, scipy and :mod:`crustview.core.errors`.
"""
