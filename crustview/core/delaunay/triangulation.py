"""Delaunay triangulation and Voronoi vertices (robust Qhull wrapper).

Unbounded Voronoi cells
-----------------------
Samples on the convex hull have unbounded Voronoi cells.  We add a small set
of *far bounding points* before calling Qhull: the ``2r`` vertices of a
cross-polytope and the ``2^r`` cube corners (for ``r <= 5``), scaled to radius
:data:`BOUND_RADIUS` times the data radius.  Every sample's cell is then a
bounded polytope, so poles of hull samples are finite Voronoi vertices lying
along the outward normal cone (which is narrow for a dense sample, so the
pole direction is what the unbounded cell's direction at infinity would be),
and every dual cell used by Algorithm 2 is bounded.  Delaunay simplices that
touch a bounding point are kept (their circumcentres are Voronoi vertices of
samples) but no face containing a bounding point is ever a candidate.

Voronoi vertices are the circumcentres of the Delaunay simplices, computed
directly (``scipy.spatial.Voronoi`` would recompute the same hull).

Backends
--------
In R^3 (working dimension 3) the triangulation comes from CGAL's
``Delaunay_triangulation_3`` (see :mod:`.cgal`: exact predicates;
through crustview's own extension 20-30x faster than Qhull on surface
samples, through the ``cgal`` wheel's text export about half of that).  In
R^4 and R^5 it comes from CGAL's dD ``Delaunay_triangulation`` with the
dimension fixed at compile time, through crustview's second extension (3-5x
faster than Qhull on a 10,000-point Klein bottle; with a run-time dimension,
as GUDHI uses it, CGAL measured no faster: 36 s against 41 s).  Elsewhere,
and when the extensions were not built, it comes from Qhull
(``scipy.spatial.Delaunay``); in R^2 Qhull takes milliseconds.  Both get
the samples *and* the far bounding points, and the joggle of
:mod:`crustview.core.prepare` happens before either, so the bounded-cell
design is the same for both.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import Delaunay, QhullError

from ..errors import QhullFailure
from ..util.rows import index_dtype

#: Radius of the far bounding points relative to the data radius (which is 1
#: in working coordinates).
BOUND_RADIUS = 4.0


def bounding_points(r: int, radius: float = BOUND_RADIUS) -> np.ndarray:
    """Far points around the unit ball in R^r, shape (b, r).

    Cross-polytope vertices plus (for ``r <= 5``) normalised cube corners.
    """
    eye = np.eye(r)
    pts = [eye, -eye]
    if r <= 5:
        corners = np.array(list(itertools.product((-1.0, 1.0), repeat=r)))
        pts.append(corners / np.sqrt(r))
    out = np.vstack(pts) * radius
    # a tiny deterministic twist keeps them out of special position w.r.t. the data
    rng = np.random.default_rng(12345)
    return out + rng.uniform(-1e-3, 1e-3, size=out.shape) * radius


#: Working dimensions CGAL's dD extension (:mod:`._delaunay_d`) handles.
CGAL_D_DIMENSIONS = (4, 5)

#: Names accepted by :func:`delaunay`'s ``backend``.
BACKENDS = ("auto", "qhull", "cgal")


def backend_for(r: int) -> str:
    """The backend ``"auto"`` picks in working dimension ``r``."""
    from .cgal import cgal_available, native_d_available

    if r == 3 and cgal_available() or r in CGAL_D_DIMENSIONS and native_d_available():
        return "cgal"
    return "qhull"


def backend_label(r: int) -> str:
    """What ``"auto"`` runs in working dimension ``r``, in words (for reports and the viewer)."""
    if backend_for(r) == "cgal" and r in CGAL_D_DIMENSIONS:
        return f"CGAL dD Delaunay_triangulation, Epick_d<{r}> (crustview extension)"
    if backend_for(r) == "cgal":
        from .cgal import cgal_route

        via = "crustview extension" if cgal_route() == "extension" else "cgal wheel"
        return f"CGAL Delaunay_triangulation_3 ({via})"
    return "Qhull (scipy.spatial.Delaunay)"


def delaunay(
    work: np.ndarray, bounds: np.ndarray, backend: str = "auto", neighbors: bool = False
) -> np.ndarray | tuple[np.ndarray, np.ndarray | None]:
    """Delaunay simplices of ``work`` followed by ``bounds``.

    Parameters
    ----------
    work : ndarray of shape (n, r)
    bounds : ndarray of shape (b, r)
    backend : {"auto", "qhull", "cgal"}
        ``"auto"``: CGAL for r = 3 (extension or wheel) and r = 4, 5
        (extension) when installed, Qhull otherwise.  ``"cgal"`` needs
        3 <= r <= 5 (and the extension for r >= 4).  If CGAL cannot return a full triangulation
        (it cannot happen after duplicate merging), Qhull runs instead.
    neighbors : bool
        Also return the neighbour table (see below).

    Returns
    -------
    simplices : ndarray of shape (t, r + 1)
        Vertex indices (samples first, then bounding points); int32 below
        2^31 vertices (half the memory of int64 at a million samples).
    neighbors : ndarray of shape (t, r + 1) or None
        Only with ``neighbors=True``: ``[i, j]`` is the simplex across the
        facet of ``i`` opposite its ``j``-th vertex, -1 across the hull.
        None when the backend cannot give it (CGAL through the wheel).

    Raises
    ------
    QhullFailure
        With Qhull's one-line reason.
    """
    allpts = np.vstack([work, bounds])
    if backend not in BACKENDS:
        raise ValueError(f"unknown Delaunay backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if backend == "auto":
        backend = backend_for(allpts.shape[1])
    if backend == "cgal":
        r = allpts.shape[1]
        if r != 3 and r not in CGAL_D_DIMENSIONS:
            raise ValueError(f"the CGAL backend works in R^3 to R^5 only; got points in R^{r}")
        from .cgal import delaunay_3d, delaunay_d

        try:
            return delaunay_3d(allpts, neighbors) if r == 3 else delaunay_d(allpts, neighbors)
        except RuntimeError:  # duplicates or a flat set: never after prepare_points
            pass
    try:
        tri = Delaunay(allpts, qhull_options="Qbb Qc Qz Q12" if work.shape[1] <= 4 else "Qbb Qc Qz Qx Q12")
    except QhullError as exc:  # pragma: no cover - depends on Qhull's mood
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else "unknown error"
        raise QhullFailure(f"Qhull could not triangulate the points: {first}") from None
    simp = np.ascontiguousarray(tri.simplices, dtype=index_dtype(len(allpts)))
    if neighbors:
        return simp, np.ascontiguousarray(tri.neighbors, dtype=index_dtype(len(simp)))
    return simp


#: Simplices per block in :func:`circumcenters` (bounds its temporary memory).
CIRCUM_BLOCK = 1 << 17


def circumcenters(pts: np.ndarray, simplices: np.ndarray, spare: int = 0) -> np.ndarray:
    """Circumcentres of full-dimensional simplices.

    Computed by the extension :mod:`._centres` (on two threads, about 12x
    faster) when it was built and gives the numpy code's bits (checked once
    per process, :func:`native_centres_ok`), else by :func:`circumcenters_numpy`.
    Both give the same values, bit for bit; simplices whose determinant test
    fails are solved by least squares in numpy either way.

    Parameters
    ----------
    pts : ndarray of shape (n, r)
    simplices : ndarray of shape (t, r + 1)
    spare : int
        Rows of room after the centres: the result is then the first t rows of a (t + spare, r) array,
        its ``base``, which :meth:`~crustview.core.prepare.PreparedPoints.lift_appended` fills in place
        (the Voronoi vertices at infinity follow the centres) instead of copying.

    Returns
    -------
    ndarray of shape (t, r)
    """
    r = pts.shape[1]
    if not 2 <= r <= 5 or len(simplices) == 0 or not native_centres_ok():
        centres = circumcenters_numpy(pts, simplices)
        if spare <= 0:
            return centres
        room = np.empty((len(centres) + spare, r))
        room[: len(centres)] = centres
        return room[: len(centres)]
    return _circumcenters_native(pts, simplices, spare)


def _circumcenters_native(pts: np.ndarray, simplices: np.ndarray, spare: int = 0) -> np.ndarray:
    from ..util.parallel import WORKERS

    pts = np.ascontiguousarray(pts, dtype=np.float64)
    simp = np.ascontiguousarray(simplices)
    if simp.dtype not in (np.int32, np.int64):
        simp = simp.astype(np.int64)
    out = np.empty((len(simp) + max(spare, 0), pts.shape[1]))[: len(simp)]  # untouched room: no page faults
    bad = np.zeros(len(simp), dtype=np.uint8)
    _native_centres.circumcentres(pts, simp, pts.shape[1], simp.itemsize, out, bad, min(WORKERS, 2))
    fix = np.flatnonzero(bad)
    if len(fix):
        out[fix] = circumcenters_numpy(pts, simp[fix])
    return out


try:  # the compiled circumcentres (see _centres.cpp); numpy does the same without it
    from . import _centres as _native_centres
except ImportError:  # pragma: no cover - the extension is optional
    _native_centres = None

_NATIVE_OK: list[bool] = []


def native_centres_ok() -> bool:
    """Whether :mod:`._centres` is built and gives :func:`circumcenters_numpy`'s bits here (checked once).

    numpy's ``einsum`` chooses its summation order by build and CPU; the
    extension follows the order numpy uses today, and this check keeps the
    numpy code whenever the two differ, on random simplices in R^2 to R^5.
    """
    if not _NATIVE_OK:
        ok = _native_centres is not None
        rng = np.random.default_rng(2024)
        for r in range(2, 6) if ok else ():
            pts = rng.normal(size=(64, r))
            simp = np.array([rng.permutation(64)[: r + 1] for _ in range(256)], dtype=np.int32)
            ok = ok and np.array_equal(_circumcenters_native(pts, simp), circumcenters_numpy(pts, simp))
        _NATIVE_OK.append(bool(ok))
    return _NATIVE_OK[0]


def circumcenters_numpy(pts: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Circumcentres of full-dimensional simplices, in numpy (the reference of :func:`circumcenters`).

    Parameters
    ----------
    pts : ndarray of shape (n, r)
    simplices : ndarray of shape (t, r + 1)

    Returns
    -------
    ndarray of shape (t, r)
        For (near-)degenerate simplices the least-squares centre.

    Notes
    -----
    The centre ``c`` solves ``2 (p_i - p_0) . (c - p_0) = |p_i - p_0|^2``.
    The small systems are solved by Gaussian elimination with partial
    pivoting written over whole arrays (one array per matrix entry), which
    is many times faster than a batched LAPACK call on millions of r x r
    systems; blocks of :data:`CIRCUM_BLOCK` simplices bound the memory.
    """
    from ..util.parallel import chunks, run_in_order

    r = pts.shape[1]
    out = np.empty((len(simplices), r))

    def block_centres(sl: slice) -> None:
        block = simplices[sl]
        p0 = np.take(pts, block[:, 0], axis=0)
        a = [np.take(pts, block[:, i + 1], axis=0) - p0 for i in range(r)]  # rows a_i, each (t, r)
        b = [0.5 * np.einsum("tr,tr->t", ai, ai) for ai in a]
        scale = np.max([np.abs(ai).max(axis=1) for ai in a], axis=0) ** r
        x, det = _solve_rows([[ai[:, j].copy() for j in range(r)] for ai in a], b)
        ok = np.abs(det) > 1e-14 * np.maximum(scale, 1e-300)
        cen = np.stack(x, axis=1)
        for i in np.flatnonzero(~ok):
            mat = np.stack(a, axis=1)[i]
            cen[i] = np.linalg.lstsq(mat, np.array([bi[i] for bi in b]), rcond=None)[0]
        out[sl] = cen + p0

    for _ in run_in_order(block_centres, chunks(len(simplices), CIRCUM_BLOCK)):
        pass
    return out


def _solve_rows(mat: list[list[np.ndarray]], rhs: list[np.ndarray]) -> tuple[list[np.ndarray], np.ndarray]:
    """Solve many small systems ``mat x = rhs`` given entry by entry.

    ``mat[i][j]`` and ``rhs[i]`` are arrays of shape (t,).  Gaussian
    elimination with partial pivoting; returns the solution components and
    the determinants.  Singular systems give non-finite or arbitrary values
    (callers test the determinant).
    """
    r = len(rhs)
    mat = [row[:] for row in mat]
    rhs = rhs[:]
    det = np.ones_like(rhs[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        for col in range(r):
            if col < r - 1:
                piv = np.argmax(np.stack([np.abs(mat[i][col]) for i in range(col, r)]), axis=0) + col
                for q in range(col + 1, r):
                    swap = piv == q
                    if not swap.any():
                        continue
                    det[swap] = -det[swap]
                    for j in range(col, r):
                        top = mat[col][j][swap]
                        mat[col][j][swap] = mat[q][j][swap]
                        mat[q][j][swap] = top
                    top = rhs[col][swap]
                    rhs[col][swap] = rhs[q][swap]
                    rhs[q][swap] = top
            pivot = mat[col][col]
            det *= pivot
            for i in range(col + 1, r):
                f = mat[i][col] / pivot
                for j in range(col + 1, r):
                    mat[i][j] -= f * mat[col][j]
                rhs[i] -= f * rhs[col]
        x = [np.empty(0)] * r
        for i in range(r - 1, -1, -1):
            acc = rhs[i].copy()
            for j in range(i + 1, r):
                acc -= mat[i][j] * x[j]
            x[i] = acc / mat[i][i]
    return x, det


def vertex_simplices(simplices: np.ndarray, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR incidence vertex -> simplices.

    Returns
    -------
    indptr : ndarray of shape (n_vertices + 1,)
    indices : ndarray
        ``indices[indptr[v]:indptr[v+1]]`` are the simplices containing ``v``.
    """
    flat = simplices.ravel()
    order = np.argsort(flat, kind="stable")
    counts = np.bincount(flat, minlength=n_vertices)
    indptr = np.concatenate([[0], np.cumsum(counts)])
    return indptr, order // simplices.shape[1]
