"""Plumbing shared by the whole core: no geometry, no algorithm.

* :mod:`.rows`: integer row keys and unique rows.
* :mod:`.memory`: garbage collection paused over big builds, memory handed back.
* :mod:`.parallel`: chunks on a thread pool, results in order.
* :mod:`.second_core`: work that may be needed, begun at once in a helper process.
* :mod:`.hullframe`: coordinates in the affine hull of a sample that spans a proper flat of R^k (a
  hypersurface of the flat is labelled there), and the features measured there lifted back.
* ``_surface`` (compiled, optional): a triangle complex's edge table and the integer counts of its
  topology report, for :mod:`crustview.core.paper.facets`, :mod:`crustview.core.analysis.cotree` and
  :mod:`crustview.core.analysis.topology`.

May import: numpy and the standard library only.
"""
