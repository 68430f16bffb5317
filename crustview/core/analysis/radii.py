"""Sampling radii of a reconstruction: per sample (the local spacing) and per simplex (enclosing balls).

The features analysis (:mod:`.features`) measures loops, rims and gaps in
these units; the robust extension's caps (:mod:`crustview.core.robust.cells`)
compare faces by them.
"""

from __future__ import annotations

import numpy as np

from ..util.nearest import nearest_distances

try:
    from . import _spacing
except ImportError:  # pragma: no cover - the extension is optional
    _spacing = None


def local_spacing(points: np.ndarray, simplices: np.ndarray | None = None) -> np.ndarray:
    """The local sampling radius h of every sample.

    With ``simplices`` (M_S), h(s) is the largest enclosing radius of the
    simplices at s (:func:`enclosing_radii`): about the farthest a point of
    the reconstruction near s gets from every sample, which is what an
    epsilon-sample bounds (h <= eps LFS).
    It stays right where the sampling is anisotropic (long thin triangles:
    dense along a ring, sparse across it), where the nearest-neighbour
    distance sees only the dense direction.  Samples in no simplex, and
    calls without ``simplices``, get the nearest-neighbour distance.
    """
    n = len(points)
    if n < 2:
        return np.ones(n)
    if simplices is not None and len(simplices):
        cover = enclosing_cover(points, simplices)
        bare = np.flatnonzero(cover <= 0)
        if len(bare) == 0:  # every sample covered: no nearest-neighbour distance is needed
            return cover
        dist = nearest_distances(points)[bare]
        if (dist <= 0).any():  # a duplicate: its fallback is the median over every sample
            return np.where(cover > 0, cover, local_spacing(points))
        cover[bare] = dist
        return cover
    dist = nearest_distances(points)
    return np.where(dist > 0, dist, np.median(dist[dist > 0]) if (dist > 0).any() else 1.0)


def enclosing_cover(points: np.ndarray, simplices: np.ndarray, compiled: bool = True) -> np.ndarray:
    """The largest :func:`enclosing_radii` of the simplices at each sample, 0 at a sample in none.

    The compiled ``_spacing.cover`` computes it on two threads; its
    circumradii solve the same Gram system by Cramer's rule instead of
    LAPACK, so they agree with the numpy code (``compiled=False``, the
    reference) to rounding, not bit for bit.
    """
    points = np.ascontiguousarray(points, dtype=float)
    simplices = np.ascontiguousarray(simplices, dtype=np.int64)
    n = len(points)
    if compiled and _spacing is not None and points.ndim == 2 and simplices.ndim == 2 and simplices.shape[1] >= 2:
        return np.frombuffer(_spacing.cover(points, points.shape[1], simplices, simplices.shape[1]), dtype=float).copy()
    r = enclosing_radii(points, simplices)
    cover = np.zeros(n)
    np.maximum.at(cover, simplices.ravel(), np.repeat(r, simplices.shape[1]))
    return cover


def enclosing_radii(points: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Radius of the smallest ball around each simplex.

    For a triangle: its circumradius when no angle is obtuse, else half its
    longest edge (an obtuse sliver's circumradius grows without bound, its
    enclosing ball does not).  For other simplices: half the longest edge, a
    lower bound within a factor sqrt(2d / (d + 1)) of it.
    """
    d = simplices.shape[1] - 1
    p = points[simplices]
    edges = [np.linalg.norm(p[:, i] - p[:, j], axis=1) for i in range(d + 1) for j in range(i + 1, d + 1)]
    half = np.max(edges, axis=0) / 2 if edges else np.zeros(len(simplices))
    if d != 2:
        return half
    a, b, c = np.sort(np.stack(edges, axis=1), axis=1).T
    obtuse = c * c >= a * a + b * b
    return np.where(obtuse, half, circumradii(points, simplices))


def circumradii(points: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Circumradius of every simplex (its circumsphere within its own affine hull)."""
    p0 = points[simplices[:, 0]]
    a = points[simplices[:, 1:]] - p0[:, None, :]  # (s, d, k)
    g = np.einsum("sik,sjk->sij", a, a)
    rhs = 0.5 * np.einsum("sii->si", g)
    try:
        lam = np.linalg.solve(g, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        lam = np.einsum("sij,sj->si", np.linalg.pinv(g), rhs)
    c = np.einsum("si,sik->sk", lam, a)
    return np.linalg.norm(c, axis=1)
