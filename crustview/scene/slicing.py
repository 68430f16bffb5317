"""Cross-sections of a simplicial complex in R^k by a hyperplane (Qt-free).

The hyperplane is ``{x : x . u = c}``.  A d-simplex whose vertices lie on
both sides meets it in a (d-1)-dimensional polytope: a point (d = 1), a
segment (d = 2), a triangle or a quadrilateral (d = 3, split into two
triangles).  The cross-section of S^3 by a hyperplane is a 2-sphere, of a
surface a set of closed curves.
"""

from __future__ import annotations

import numpy as np

#: Vertex pairs of a tetrahedron's edges.
_TET_EDGES = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])


def _crossing(x: np.ndarray, s: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Points where segments x[a] -> x[b] cross zero of the signed distances s (row-wise)."""
    sa, sb = s[a], s[b]
    t = sa / np.where(sa - sb == 0, 1.0, sa - sb)
    return x[a] + t[:, None] * (x[b] - x[a])


def slice_complex(points: np.ndarray, simplices: np.ndarray, u: np.ndarray, c: float) -> tuple[np.ndarray, np.ndarray]:
    """The cross-section of ``simplices`` by the hyperplane ``x . u = c``.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (m, d + 1)
        d = 1, 2 or 3.
    u : ndarray of shape (k,)
        Unit normal of the hyperplane.
    c : float
        Its offset.

    Returns
    -------
    vertices : ndarray of shape (p, k)
        Points of the cross-section (on the hyperplane).
    cells : ndarray of shape (q, d)
        Its (d-1)-cells as rows of indices into ``vertices`` (points,
        segments or triangles); empty with shape (0, d) when nothing is cut.
    """
    points = np.asarray(points, dtype=float)
    simplices = np.asarray(simplices, dtype=np.int64)
    d = simplices.shape[1] - 1
    s_all = points @ np.asarray(u, dtype=float) - float(c)
    s = s_all[simplices]  # (m, d+1)
    pos = s >= 0
    cut = pos.any(axis=1) & ~pos.all(axis=1)
    simp, s, pos = simplices[cut], s[cut], pos[cut]
    k = points.shape[1]
    if len(simp) == 0:
        return np.zeros((0, k)), np.zeros((0, d), dtype=np.int64)
    x = points[simp]  # (q, d+1, k)
    rows = np.arange(len(simp))
    if d == 1:
        v = _crossing(x.reshape(-1, k), s.ravel(), rows * 2, rows * 2 + 1)
        return v, np.arange(len(v))[:, None]
    if d == 2:
        # the lone vertex (on its own side) and the two edges from it
        lone = np.where(pos.sum(axis=1) == 1, np.argmax(pos, axis=1), np.argmax(~pos, axis=1))
        o1, o2 = (lone + 1) % 3, (lone + 2) % 3
        flat, sf = x.reshape(-1, k), s.ravel()
        a = _crossing(flat, sf, rows * 3 + lone, rows * 3 + o1)
        b = _crossing(flat, sf, rows * 3 + lone, rows * 3 + o2)
        v = np.vstack([a, b])
        q = len(simp)
        return v, np.stack([np.arange(q), np.arange(q) + q], axis=1)
    if d != 3:
        raise ValueError(f"slices are drawn for d <= 3, got d = {d}")
    flat, sf = x.reshape(-1, k), s.ravel()
    ea, eb = _TET_EDGES[:, 0], _TET_EDGES[:, 1]
    crosses = pos[:, ea] != pos[:, eb]  # (q, 6)
    verts, cells = [], []
    base = 0
    n_pos = pos.sum(axis=1)
    # one vertex alone: a triangle through its three edges
    one = (n_pos == 1) | (n_pos == 3)
    if one.any():
        r = np.flatnonzero(one)
        e = np.argwhere(crosses[r])[:, 1].reshape(-1, 3)
        pts = _crossing(flat, sf, (r[:, None] * 4 + ea[e]).ravel(), (r[:, None] * 4 + eb[e]).ravel())
        verts.append(pts)
        cells.append(base + np.arange(len(pts)).reshape(-1, 3))
        base += len(pts)
    # two and two: a quadrilateral through four edges, in cyclic order, as two triangles
    two = n_pos == 2
    if two.any():
        r = np.flatnonzero(two)
        e = np.argwhere(crosses[r])[:, 1].reshape(-1, 4)  # edges in _TET_EDGES order
        pts = _crossing(flat, sf, (r[:, None] * 4 + ea[e]).ravel(), (r[:, None] * 4 + eb[e]).ravel())
        pts = pts.reshape(-1, 4, k)
        # edges (01|23 split etc.) come out as [e0, e1, e2, e3]; the cycle is e0, e1, e3, e2
        quad = pts[:, [0, 1, 3, 2]]
        m = len(quad)
        verts.append(quad.reshape(-1, k))
        idx = base + 4 * np.arange(m)[:, None]
        cells.append(np.vstack([idx + [0, 1, 2], idx + [0, 2, 3]]))
        base += 4 * m
    return np.vstack(verts), np.vstack(cells).astype(np.int64)
