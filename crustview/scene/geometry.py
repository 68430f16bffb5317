"""Geometry of the layers in R^k (numpy only, no drawing).

Everything here returns plain arrays in ambient coordinates; the render
adapters project them with the scene's :class:`~crustview.scene.Projection`.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np


def data_box(points: np.ndarray, margin: float = 0.15) -> tuple[np.ndarray, np.ndarray]:
    """Axis-aligned box around ``points`` grown by ``margin`` x the largest extent."""
    lo = points.min(axis=0)
    hi = points.max(axis=0)
    pad = margin * float(np.max(hi - lo) or 1.0)
    return lo - pad, hi + pad


def clip_segments(a: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Clip segments ``a[i] -> b[i]`` in R^k to the box ``[lo, hi]``.

    Liang-Barsky, vectorised.  Returns ``(a', b', keep)``: the clipped end
    points of the segments that meet the box and the boolean mask of those.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    d = b - a
    t0 = np.zeros(len(a))
    t1 = np.ones(len(a))
    with np.errstate(divide="ignore", invalid="ignore"):
        for p, q in ((-d, a - lo), (d, hi - a)):
            r = q / p
            parallel = p == 0
            outside = parallel & (q < 0)
            t0 = np.where(outside.any(axis=1), 2.0, t0)
            enter = (p < 0) & ~parallel
            leave = (p > 0) & ~parallel
            t0 = np.maximum(t0, np.where(enter, r, -np.inf).max(axis=1))
            t1 = np.minimum(t1, np.where(leave, r, np.inf).min(axis=1))
    keep = t0 <= t1
    return (a + t0[:, None] * d)[keep], (a + t1[:, None] * d)[keep], keep


def local_spacing(points: np.ndarray, neighbours: int = 2) -> np.ndarray:
    """Mean distance of each point to its ``neighbours`` nearest other samples."""
    from scipy.spatial import cKDTree

    m = min(neighbours + 1, len(points))
    dist, _ = cKDTree(points).query(points, k=m)
    dist = np.atleast_2d(dist)
    if m < 2:
        return np.ones(len(points))
    return dist[:, 1:].mean(axis=1)


# -- normal-plane glyphs -----------------------------------------------------
def normal_glyphs(points: np.ndarray, normals: np.ndarray, scale: np.ndarray, sides: int = 16):
    """Glyphs of the normal planes AN_s.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    normals : ndarray of shape (n, k, c)
        Orthonormal basis (columns) of each normal plane, c = k - d.
    scale : ndarray of shape (n,)
        Glyph radius per sample.
    sides : int
        Polygon sides of a disc (c = 2).

    Returns
    -------
    verts : ndarray of shape (v, k)
    lines : ndarray of shape (l, 2)
        Segments (c = 1, or the c axes for c >= 3); empty for discs.
    polys : ndarray of shape (p, sides)
        Disc polygons (c = 2); empty otherwise.
    """
    n, k, c = normals.shape
    scale = np.asarray(scale, float).reshape(n, 1)
    empty_l = np.zeros((0, 2), dtype=np.int64)
    if c == 2:
        t = np.linspace(0, 2 * np.pi, sides, endpoint=False)
        circle = np.stack([np.cos(t), np.sin(t)])  # (2, sides)
        ring = np.einsum("nkc,cs->nsk", normals, circle) * scale[:, :, None]
        verts = (points[:, None, :] + ring).reshape(-1, k)
        polys = np.arange(n * sides, dtype=np.int64).reshape(n, sides)
        return verts, empty_l, polys
    # c == 1: one segment through s; c >= 3: c axes through s
    ends = np.concatenate(
        [
            points[:, None, :] - normals.transpose(0, 2, 1) * scale[:, :, None],
            points[:, None, :] + normals.transpose(0, 2, 1) * scale[:, :, None],
        ],
        axis=1,
    )  # (n, 2c, k)
    verts = ends.reshape(-1, k)
    base = (np.arange(n) * 2 * c)[:, None]
    lines = np.stack([base + np.arange(c), base + c + np.arange(c)], axis=-1).reshape(-1, 2)
    return verts, lines.astype(np.int64), np.zeros((0, sides), dtype=np.int64)


# -- simplices -----------------------------------------------------------------
def simplex_triangles(d: int) -> np.ndarray:
    """Local vertex triples of the boundary triangles of a d-simplex (d >= 2)."""
    return np.array(list(combinations(range(d + 1), 3)), dtype=np.int64)


def shrink_simplices(pts: np.ndarray, simplices: np.ndarray, factor: float) -> np.ndarray:
    """Vertices of each simplex moved towards its centroid.

    Returns an array of shape ``(m * (d + 1), dim)``: simplex ``j``'s vertex
    ``a`` is row ``j * (d + 1) + a``.
    """
    v = pts[simplices]  # (m, d+1, dim)
    c = v.mean(axis=1, keepdims=True)
    return (c + factor * (v - c)).reshape(-1, pts.shape[1])


def facets(simplices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All (d-1)-faces of a d-complex.

    Returns
    -------
    faces : ndarray of shape (f, d)
        Unique sorted faces.
    incidence : ndarray of shape (m, d + 1)
        ``faces`` row of each simplex's face opposite to vertex ``a``.
    """
    from ..core.util.rows import unique_rows  # one int64 key per row: np.unique(axis=0) is ~10x slower

    m, dp1 = simplices.shape
    s = np.sort(simplices, axis=1)
    sub = np.stack([np.delete(s, a, axis=1) for a in range(dp1)], axis=1)  # (m, d+1, d)
    faces, inv = unique_rows(sub.reshape(-1, dp1 - 1))
    return faces, inv.reshape(m, dp1)


def face_counts(incidence: np.ndarray, alive: np.ndarray, n_faces: int) -> np.ndarray:
    """Number of alive simplices at each face."""
    return np.bincount(incidence[alive].ravel(), minlength=n_faces)


def simplices_at_face(simplices: np.ndarray, face) -> np.ndarray:
    """Rows of ``simplices`` that contain every vertex of ``face``."""
    mask = np.ones(len(simplices), dtype=bool)
    for v in face:
        mask &= (simplices == v).any(axis=1)
    return np.flatnonzero(mask)


def find_rows(table: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Index in ``table`` of each row of ``rows`` (-1 when absent); rows sorted."""
    table = np.sort(np.asarray(table), axis=1)
    rows = np.sort(np.atleast_2d(rows), axis=1)
    if len(table) == 0:
        return np.full(len(rows), -1)
    width = table.shape[1]
    kt = np.ascontiguousarray(table).view(np.dtype((np.void, table.dtype.itemsize * width))).ravel()
    kr = np.ascontiguousarray(rows.astype(table.dtype)).view(kt.dtype).ravel()
    order = np.argsort(kt)
    pos = np.searchsorted(kt[order], kr)
    pos = np.clip(pos, 0, len(kt) - 1)
    hit = kt[order][pos] == kr
    return np.where(hit, order[pos], -1)
