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
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import Delaunay
from scipy.spatial import QhullError

from .errors import QhullFailure

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


def delaunay(work: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """Delaunay simplices of ``work`` followed by ``bounds``.

    Returns
    -------
    simplices : ndarray of shape (t, r + 1)
        Vertex indices (samples first, then bounding points).

    Raises
    ------
    QhullFailure
        With Qhull's one-line reason.
    """
    allpts = np.vstack([work, bounds])
    try:
        tri = Delaunay(allpts, qhull_options="Qbb Qc Qz Q12" if work.shape[1] <= 4 else "Qbb Qc Qz Qx Q12")
    except QhullError as exc:  # pragma: no cover - depends on Qhull's mood
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else "unknown error"
        raise QhullFailure(f"Qhull could not triangulate the points: {first}") from None
    return np.ascontiguousarray(tri.simplices, dtype=np.int64)


def circumcenters(pts: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Circumcentres of full-dimensional simplices.

    Parameters
    ----------
    pts : ndarray of shape (n, r)
    simplices : ndarray of shape (t, r + 1)

    Returns
    -------
    ndarray of shape (t, r)
        For (near-)degenerate simplices the least-squares centre.
    """
    p = pts[simplices]
    p0 = p[:, 0, :]
    a = p[:, 1:, :] - p0[:, None, :]
    b = 0.5 * (a**2).sum(axis=2)
    det = np.linalg.det(a)
    scale = np.abs(a).max(axis=(1, 2)) ** a.shape[1]
    ok = np.abs(det) > 1e-14 * np.maximum(scale, 1e-300)
    out = np.empty_like(p0)
    if ok.any():
        out[ok] = np.linalg.solve(a[ok], b[ok][..., None])[..., 0]
    for i in np.flatnonzero(~ok):
        out[i] = np.linalg.lstsq(a[i], b[i], rcond=None)[0]
    return out + p0


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
