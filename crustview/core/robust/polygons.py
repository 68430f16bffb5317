"""Planar polygons for ear clipping: a hole's rim in its best-fit plane, ears, triangle shape.

Used by :mod:`crustview.core.robust.fill_hole` to close a surface hole by ears: the rim
is projected to the plane of its two main directions; if that polygon is
simple, ear clipping there always succeeds (two ears theorem).
"""

from __future__ import annotations

import numpy as np


def plane_polygon(p: np.ndarray) -> np.ndarray | None:
    """Points ``p`` (m, k) of a closed loop in their best-fit plane, (m, 2); None if not a simple polygon."""
    c = p - p.mean(axis=0)
    _, _, vt = np.linalg.svd(c, full_matrices=False)
    q = c @ vt[:2].T
    m = len(p)
    # every pair of edges i < j that share no vertex, all at once (the float operations of
    # _segments_cross, column by column)
    i, j = np.triu_indices(m, k=2)
    keep = ~((i == 0) & (j == m - 1))
    i, j = i[keep], j[keep]
    a, b = q[i], q[(i + 1) % m]
    e, f = q[j], q[(j + 1) % m]

    def cross(o: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return (u[:, 0] - o[:, 0]) * (v[:, 1] - o[:, 1]) - (u[:, 1] - o[:, 1]) * (v[:, 0] - o[:, 0])

    crossing = (cross(e, f, a) * cross(e, f, b) < 0) & (cross(a, b, e) * cross(a, b, f) < 0)
    return None if crossing.any() else q


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def _segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> bool:
    """Whether the open segments ab and cd cross (proper intersection)."""
    d1, d2 = _cross(c, d, a), _cross(c, d, b)
    d3, d4 = _cross(a, b, c), _cross(a, b, d)
    return d1 * d2 < 0 and d3 * d4 < 0


def orientation(poly: np.ndarray) -> float:
    """+1.0 for a counter-clockwise polygon (m, 2), -1.0 for a clockwise one (signed area, summed in order)."""
    nxt = np.roll(poly, -1, axis=0)
    area = 0.5 * sum((poly[:, 0] * nxt[:, 1] - poly[:, 1] * nxt[:, 0]).tolist())
    return 1.0 if area >= 0 else -1.0


def is_ear(q: np.ndarray, idx: list[int], t: int, sign: float | None = None) -> bool:
    """Whether vertex idx[t] of the polygon q[idx] is an ear (convex, nothing inside).

    The cross products are the same float operations as :func:`_cross`,
    done on whole columns.  ``sign`` is :func:`orientation` of ``q[idx]``
    when the caller has it.
    """
    m = len(idx)
    poly = q[idx]
    if sign is None:
        sign = orientation(poly)
    a, b, c = poly[t - 1], poly[t], poly[(t + 1) % m]
    if sign * _cross(a, b, c) <= 0:
        return False
    others = np.ones(m, dtype=bool)
    others[[t - 1 if t > 0 else m - 1, t, (t + 1) % m]] = False
    p = poly[others]
    inside = np.ones(len(p), dtype=bool)
    for o, e in ((a, b), (b, c), (c, a)):
        inside &= sign * ((e[0] - o[0]) * (p[:, 1] - o[1]) - (e[1] - o[1]) * (p[:, 0] - o[0])) >= 0
    return not inside.any()


def min_angle(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """Smallest angle of the triangle abc (radians)."""
    out = np.pi
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = q - p, r - p
        den = float(np.linalg.norm(u) * np.linalg.norm(v))
        if den == 0:
            return 0.0
        out = min(out, float(np.arccos(np.clip(u @ v / den, -1, 1))))
    return out
