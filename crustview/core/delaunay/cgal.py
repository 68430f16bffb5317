"""Delaunay triangulations with CGAL: tetrahedra in R^3, full cells in R^4 and R^5.

Why CGAL for k = 3
------------------
``CGAL::Delaunay_triangulation_3`` inserts a point range after a spatial
sort, with exact predicates (filtered, exact on demand) and symbolic
perturbation for cospherical points.  On surface samples it is 15-60x faster
than Qhull (100,000 torus points: about 1 s against 30 s), and Qhull grows
faster than linearly there.  In general position both give the same
tetrahedra; on exactly cospherical input each resolves the degeneracy its own
way (both valid Delaunay triangulations).  The far bounding points of
:mod:`.triangulation` are inserted with the samples, as for Qhull.

Two ways to CGAL
----------------
1. crustview's own small extension :mod:`crustview.core.delaunay._delaunay3`
   (``_delaunay3.cpp``, built at install time against Debian's header-only
   ``libcgal-dev``): it triangulates a float64 buffer with the GIL released
   and hands the finite tetrahedra back as one int32 buffer that numpy wraps
   without a copy.  This is the path that makes the backend fast.
2. The ``cgal`` wheel's SWIG bindings, when the extension could not be built
   (no compiler or no CGAL headers).  Getting the cells out is then the
   expensive part, described below.

Both build the same triangulation (same kernel, same insertion), so they
return the same tetrahedra.

R^4 and R^5
-----------
crustview's second extension :mod:`crustview.core.delaunay._delaunay_d`
(``_delaunay_d.cpp``) runs CGAL's dD ``Delaunay_triangulation`` with the
dimension fixed at compile time (``Epick_d<Dimension_tag<4>>``, resp. 5):
filtered exact predicates, symbolic perturbation, Hilbert-sorted insertion.
On a 10,000-point Klein bottle in R^4 it builds the same 2.7 million
4-simplices as Qhull 3-5x faster; with a run-time dimension (GUDHI, the
wheel) CGAL measured no faster than Qhull.  There is no wheel route here:
without the extension Qhull runs.

Getting the cells out of the wheel
----------------------------------
The SWIG bindings hand out cells one Python object at a time (about 1 us per
call, several calls per cell).  The bulk way is CGAL's own stream output,
``write_to_file``: the dimension, the n vertices (17 significant digits, so
each coordinate reads back bit for bit), the cells as four vertex numbers
(0 = the infinite vertex, i = the i-th vertex written) and then the
neighbours.  We write it to a RAM-backed temporary file when there is one,
read the vertices, map them back to our rows by exact coordinates, and parse
only the cell block, in chunks, with numpy's C integer parser.
"""

from __future__ import annotations

import os
import tempfile

import numpy as np

from ..util.rows import index_dtype

#: Bytes of the cell block parsed per chunk (bounds the parser's memory).
CHUNK_BYTES = 1 << 25


def native_available() -> bool:
    """Whether crustview's own CGAL extension (:mod:`._delaunay3`) was built."""
    try:
        from . import _delaunay3  # noqa: F401
    except ImportError:
        return False
    return True


def native_d_available() -> bool:
    """Whether crustview's dD CGAL extension (:mod:`._delaunay_d`, R^4 and R^5) was built."""
    try:
        from . import _delaunay_d  # noqa: F401
    except ImportError:
        return False
    return True


def wheel_available() -> bool:
    """Whether the ``cgal`` wheel (``CGAL.CGAL_Triangulation_3``) can be imported."""
    try:
        from CGAL import CGAL_Triangulation_3  # noqa: F401
    except ImportError:
        return False
    return True


def cgal_available() -> bool:
    """Whether any CGAL path (the extension or the wheel) is installed."""
    return native_available() or wheel_available()


def cgal_route() -> str | None:
    """``"extension"``, ``"wheel"`` or ``None``: which CGAL path :func:`delaunay_3d` takes."""
    if native_available():
        return "extension"
    if wheel_available():
        return "wheel"
    return None


def _temp_dir() -> str | None:
    """A RAM-backed directory (``/dev/shm``) when writable, else the default."""
    shm = "/dev/shm"
    if os.path.isdir(shm) and os.access(shm, os.W_OK):
        return shm
    return None


def delaunay_3d(points: np.ndarray, neighbors: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray | None]:
    """Delaunay tetrahedra of points in R^3 with CGAL.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
        Distinct points not all on one plane.
    neighbors : bool
        Also return the neighbour table (see :func:`delaunay_3d_native`);
        None through the wheel, which cannot give it.

    Returns
    -------
    simplices : ndarray of shape (t, 4)
        Finite tetrahedra as row indices into ``points`` (orientation not
        normalised, as with Qhull); int32 below 2^31 points.

    Raises
    ------
    RuntimeError
        If CGAL's triangulation is not 3-dimensional or lost a vertex
        (duplicates), or its output cannot be read back.
    ImportError
        If neither the extension nor the wheel is installed.
    """
    if native_available():
        return delaunay_3d_native(points, neighbors)
    simplices = delaunay_3d_wheel(points)
    return (simplices, None) if neighbors else simplices


def delaunay_3d_native(points: np.ndarray, neighbors: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """:func:`delaunay_3d` through crustview's extension :mod:`._delaunay3`.

    With ``neighbors``, also returns the (t, 4) neighbour table: entry
    ``[i, j]`` is the tetrahedron across the facet of ``i`` opposite its
    vertex ``j``, -1 across the convex hull (Qhull's convention).
    """
    from . import _delaunay3

    pts = _coordinates(points, (3,))
    return _unpack(_delaunay3.tetrahedra(pts, neighbors), pts, neighbors)


def delaunay_d(points: np.ndarray, neighbors: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Delaunay full cells of points in R^4 or R^5 with CGAL's dD code (:mod:`._delaunay_d`).

    Parameters
    ----------
    points : ndarray of shape (n, r), r in {4, 5}
        Distinct points spanning R^r.
    neighbors : bool
        Also return the (t, r + 1) neighbour table (as :func:`delaunay_3d_native`).

    Returns
    -------
    simplices : ndarray of shape (t, r + 1)
        Finite full cells as row indices into ``points``; int32 below 2^31 points.

    Raises
    ------
    RuntimeError
        If the triangulation is not full-dimensional or lost a vertex.
    ImportError
        If the extension was not built.
    """
    from . import _delaunay_d

    pts = _coordinates(points, (4, 5))
    return _unpack(_delaunay_d.full_cells(pts, pts.shape[1], neighbors), pts, neighbors)


def _coordinates(points: np.ndarray, dims: tuple[int, ...]) -> np.ndarray:
    """Contiguous float64 rows of one of the dimensions ``dims``, or ValueError."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] not in dims:
        want = " or ".join(f"(n, {d})" for d in dims)
        raise ValueError(f"expected points of shape {want}, got {pts.shape}")
    return pts


def _unpack(result: tuple, pts: np.ndarray, neighbors: bool) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Numpy views of an extension's (dimension, vertices, cells, neighbours, sizes) tuple."""
    dim, nverts, cells, nbrs, itemsize, nitemsize = result
    r = pts.shape[1]
    if dim != r or nverts != len(pts):
        raise RuntimeError(f"CGAL built a {dim}-dimensional triangulation with {nverts} of {len(pts)} vertices")
    simplices = np.frombuffer(cells, dtype=np.int32 if itemsize == 4 else np.int64).reshape(-1, r + 1)
    if not neighbors:
        return simplices
    return simplices, np.frombuffer(nbrs, dtype=np.int32 if nitemsize == 4 else np.int64).reshape(-1, r + 1)


def delaunay_3d_wheel(points: np.ndarray) -> np.ndarray:
    """:func:`delaunay_3d` through the ``cgal`` wheel (text export, slower)."""
    from CGAL.CGAL_Kernel import Point_3
    from CGAL.CGAL_Triangulation_3 import Delaunay_triangulation_3

    pts = np.ascontiguousarray(points, dtype=np.float64)
    tri = Delaunay_triangulation_3()
    tri.insert([Point_3(x, y, z) for x, y, z in pts.tolist()])
    if tri.dimension() != 3 or tri.number_of_vertices() != len(pts):
        raise RuntimeError(
            f"CGAL built a {tri.dimension()}-dimensional triangulation with "
            f"{tri.number_of_vertices()} of {len(pts)} vertices"
        )
    with tempfile.TemporaryDirectory(prefix="crustview-", dir=_temp_dir()) as tmp:
        path = os.path.join(tmp, "tri.txt")
        tri.write_to_file(path, 17)
        del tri
        with open(path, "rb") as fh:
            written, cells = _read_triangulation(fh)
    perm = _match_rows(written, pts).astype(index_dtype(len(pts)))
    keep = (cells != 0).all(axis=1)
    finite = cells[keep]
    del cells, keep
    finite -= 1
    return perm[finite]


def _read_triangulation(fh) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """Vertices (n, 3) and cells (m, 4) of CGAL's ASCII ``Triangulation_3`` output."""
    dim = int(fh.readline())
    n = int(fh.readline())
    if dim != 3:
        raise RuntimeError(f"CGAL wrote a {dim}-dimensional triangulation")
    written = np.loadtxt(fh, max_rows=n, dtype=np.float64, ndmin=2)
    m = int(fh.readline())
    cells = np.empty((m, 4), dtype=index_dtype(n + 1))
    got, rest = 0, b""
    while got < m:
        chunk = fh.read(CHUNK_BYTES)
        if not chunk:
            break
        chunk = rest + chunk
        cut = chunk.rfind(b"\n") + 1
        if cut == 0:
            rest = chunk
            continue
        body, rest = chunk[:cut], chunk[cut:]
        vals = np.fromstring(body, dtype=np.int64, sep=" ")
        rows = vals[: (len(vals) // 4) * 4].reshape(-1, 4)[: m - got]
        cells[got : got + len(rows)] = rows
        got += len(rows)
    if got < m or written.shape != (n, 3):
        raise RuntimeError("CGAL's triangulation output was cut short")
    return written, cells


def _match_rows(written: np.ndarray, points: np.ndarray) -> np.ndarray:
    """``perm`` with ``written[i] == points[perm[i]]`` (exact coordinates).

    Sorting by the first coordinate alone is enough when it has no ties
    (checked on the whole rows afterwards); otherwise all coordinates are
    sorted lexicographically.
    """
    if written.shape != points.shape:
        raise RuntimeError("CGAL wrote a different number of vertices")
    ow = np.argsort(written[:, 0], kind="stable")
    op = np.argsort(points[:, 0], kind="stable")
    if not np.array_equal(written[ow], points[op]):
        ow = np.lexsort(written.T[::-1])
        op = np.lexsort(points.T[::-1])
        if not np.array_equal(written[ow], points[op]):
            raise RuntimeError("CGAL's vertices do not read back to the input points")
    perm = np.empty(len(points), dtype=np.int64)
    perm[ow] = op
    return perm
