"""Voronoi cells for display: clipped polytopes and the planar diagram."""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError

from .geometry import clip_segments


def _unique_planes(eq: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Drop repeated hyperplanes (coplanar simplicial facets of a hull)."""
    key = np.round(eq / tol**0.5, 0)
    _, idx = np.unique(key, axis=0, return_index=True)
    return eq[np.sort(idx)]


def clipped_cell(vertices: np.ndarray, site: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """The convex cell spanned by ``vertices`` intersected with a box.

    Parameters
    ----------
    vertices : ndarray of shape (v, k)
        Voronoi vertices of one cell (the cell is their convex hull).
    site : ndarray of shape (k,)
        The sample of the cell (an interior point).
    lo, hi : ndarray of shape (k,)
        The clipping box; it must contain ``site``.

    Returns
    -------
    verts : ndarray of shape (w, k)
        Vertices of the clipped polytope.
    edges : ndarray of shape (e, 2)
        Its edges (pairs of rows of ``verts``).
    triangles : ndarray of shape (t, 3)
        A triangulation of its boundary when k = 3, of its 2-faces when
        k = 4 (drawn as translucent patches), empty otherwise.

    Returns ``None`` when the cell is degenerate.
    """
    k = len(site)
    try:
        hull = ConvexHull(vertices, qhull_options="QJ" if len(vertices) <= k + 1 else "")
        eq = _unique_planes(hull.equations)
        box = np.vstack(
            [
                np.hstack([-np.eye(k), lo[:, None]]),  # -x + lo <= 0
                np.hstack([np.eye(k), -hi[:, None]]),  # x - hi <= 0
            ]
        )
        planes = np.vstack([eq, box])
        # the site must be strictly inside every plane
        inner = site.copy()
        slack = planes[:, :k] @ inner + planes[:, k]
        if np.any(slack >= 0):
            inner = 0.999 * inner + 0.001 * vertices.mean(axis=0)
        hs = HalfspaceIntersection(planes, inner)
        verts = hs.intersections
        verts = verts[np.all(np.isfinite(verts), axis=1)]
        verts = np.unique(np.round(verts, 12), axis=0)
        if len(verts) <= k:
            return None
        hull2 = ConvexHull(verts)
    except (QhullError, ValueError):
        return None
    eq2 = _unique_planes(hull2.equations)
    scale = float(np.max(np.ptp(verts, axis=0)) or 1.0)
    active = np.abs(verts @ eq2[:, :k].T + eq2[:, k]) < 1e-7 * scale  # (w, planes)
    shared = active.astype(np.int32) @ active.T.astype(np.int32)
    i, j = np.nonzero(np.triu(shared >= k - 1, 1))
    edges = np.stack([i, j], axis=1)
    if k == 3:
        tris = hull2.simplices
    elif k == 4:
        tris = two_face_triangles(verts, active)
    else:
        tris = np.zeros((0, 3), dtype=np.int64)
    if k == 2:
        order = hull2.vertices
        edges = np.stack([order, np.roll(order, -1)], axis=1)
    return verts, edges.astype(np.int64), np.asarray(tris, dtype=np.int64)


def two_face_triangles(verts: np.ndarray, active: np.ndarray) -> np.ndarray:
    """Fan triangulations of the 2-faces of a 4-polytope.

    Parameters
    ----------
    verts : ndarray of shape (w, 4)
        Its vertices.
    active : ndarray of shape (w, f) of bool
        Which facet planes each vertex lies on.

    A 2-face is where two facets meet in three or more vertices; its
    vertices are put in order around their centroid in the face's plane.
    """
    on = active.astype(np.int32)
    shared = on.T @ on  # vertices common to each pair of facets
    a, b = np.nonzero(np.triu(shared >= 3, 1))
    seen: set[tuple[int, ...]] = set()
    tris: list[np.ndarray] = []
    for fa, fb in zip(a, b):
        idx = np.flatnonzero(active[:, fa] & active[:, fb])
        key = tuple(idx)
        if key in seen:
            continue
        seen.add(key)
        p = verts[idx]
        c = p.mean(axis=0)
        _, sv, vt = np.linalg.svd(p - c, full_matrices=False)
        if len(sv) < 2 or sv[1] < 1e-9 * max(sv[0], 1e-300):
            continue  # not a polygon
        xy = (p - c) @ vt[:2].T
        ring = idx[np.argsort(np.arctan2(xy[:, 1], xy[:, 0]))]
        tris.append(np.stack([np.full(len(ring) - 2, ring[0]), ring[1:-1], ring[2:]], axis=1))
    return np.vstack(tris).astype(np.int64) if tris else np.zeros((0, 3), dtype=np.int64)


def planar_voronoi_edges(
    delaunay_simplices: np.ndarray, centres: np.ndarray, n_samples: int, lo: np.ndarray, hi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Voronoi edges of the samples' cells in R^2, clipped to a box.

    Each Delaunay edge with a sample end point, shared by two triangles, is
    dual to the Voronoi edge between their circumcentres.

    Returns
    -------
    a, b : ndarray of shape (e, 2)
        End points of the clipped edges.
    """
    tri = np.asarray(delaunay_simplices)
    e = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]])
    owner = np.tile(np.arange(len(tri)), 3)
    e = np.sort(e, axis=1)
    keep = e[:, 0] < n_samples
    e, owner = e[keep], owner[keep]
    order = np.lexsort((e[:, 1], e[:, 0]))
    e, owner = e[order], owner[order]
    same = np.all(e[1:] == e[:-1], axis=1)
    a = centres[owner[:-1][same]]
    b = centres[owner[1:][same]]
    a, b, _ = clip_segments(a, b, lo, hi)
    return a, b
