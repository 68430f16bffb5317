"""The Delaunay triangulation in R^k and the compiled kernels.

* :mod:`.triangulation`: ``delaunay`` (picks a backend: CGAL in R^3 to R^5,
  Qhull elsewhere), the far bounding points, circumcentres (Voronoi vertices).
* :mod:`.cgal`: the CGAL routes (this package's extensions ``_delaunay3`` and
  ``_delaunay_d``, or the ``cgal`` wheel) and which one runs.
* :mod:`.faces`: every Delaunay d-face and the simplices around it.
* C++ sources, built by ``setup.py`` into extension modules here, each
  optional (numpy does the same without them): ``_delaunay3.cpp`` and
  ``_delaunay_d.cpp`` (CGAL, sharing ``_cgal_buffers.h``), and our own kernels
  ``_faces.cpp`` (the face lists), ``_centres.cpp`` (the circumcentres,
  bit for bit as numpy computes them), ``_poles.cpp`` (Algorithm 1's greedy
  rounds, used by :mod:`crustview.core.paper.normals`) and ``_segments.cpp``
  (the codimension-1 cocone ends, used by
  :mod:`crustview.core.paper.candidates`).

May import: numpy, scipy, the optional ``cgal`` wheel,
:mod:`crustview.core.util` and :mod:`crustview.core.errors`; nothing else of
crustview.
"""
