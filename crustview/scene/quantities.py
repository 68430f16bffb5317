"""Per-sample quantities the points layer can be coloured by."""

from __future__ import annotations

import numpy as np

from ..core.result import Reconstruction


def subspace_angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest principal angle (radians) between column spaces, batched.

    ``a`` and ``b`` have shape ``(n, k, m)`` with orthonormal columns.  The
    angle between two m-planes equals the one between their complements, so
    tangent bases give the normal-plane error too.
    """
    s = np.linalg.svd(np.einsum("nki,nkj->nij", a, b), compute_uv=False)
    return np.arccos(np.clip(s.min(axis=1), -1.0, 1.0))


def normal_error(rec: Reconstruction, true_tangents: np.ndarray) -> np.ndarray:
    """Angle (degrees) between estimated and true normal plane of each sample.

    ``true_tangents`` has shape ``(n_in, k, d)`` over the *input* rows.
    """
    truth = np.asarray(true_tangents, float)[rec.point_input]
    q, _ = np.linalg.qr(truth)  # tolerate non-orthonormal input bases
    return np.degrees(subspace_angle(q, rec.tangents))


#: Kinds of pole in :func:`pole_kinds`.
POLE_FINITE, POLE_INFINITE, POLE_NONE = 0, 1, -1


def pole_kinds(rec: Reconstruction) -> np.ndarray:
    """What each entry of ``rec.pole_index`` is, shape ``(n, k - d)``.

    ``POLE_FINITE`` (0): a Voronoi vertex (circumcentre of a Delaunay
    simplex).  ``POLE_INFINITE`` (1): the vertex at infinity of a sample on
    the convex hull; ``rec.voronoi_vertices`` holds a drawable representative
    of it after the circumcentres.  ``POLE_NONE`` (-1): no pole, the
    direction is orthogonal to the samples' affine hull (flat input).
    """
    idx = np.asarray(rec.pole_index)
    t = len(rec.delaunay_simplices)
    return np.where(idx < 0, POLE_NONE, np.where(idx >= t, POLE_INFINITE, POLE_FINITE))


def hull_samples(rec: Reconstruction) -> np.ndarray:
    """Boolean mask of the samples whose first pole is a vertex at infinity."""
    if rec.pole_index.shape[1] == 0:
        return np.zeros(rec.n, dtype=bool)
    return pole_kinds(rec)[:, 0] == POLE_INFINITE


def pole_direction(rec: Reconstruction, i: int, j: int) -> np.ndarray:
    """Unit vector from sample ``i`` towards its ``j``-th pole."""
    v = rec.voronoi_vertices[int(rec.pole_index[i, j])] - rec.points[i]
    return v / max(float(np.linalg.norm(v)), 1e-300)


def pole_distance(rec: Reconstruction, spacing: np.ndarray) -> np.ndarray:
    """Distance from each sample to its first pole, in units of its local spacing.

    NaN where the first pole is a vertex at infinity (hull samples) or missing.
    """
    kind = pole_kinds(rec)[:, 0]
    first = rec.voronoi_vertices[np.where(kind == POLE_NONE, 0, rec.pole_index[:, 0])]
    dist = np.linalg.norm(first - rec.points, axis=1) / np.maximum(spacing, 1e-300)
    return np.where(kind == POLE_FINITE, dist, np.nan)


def estimate_dimension(points: np.ndarray, neighbours: int = 12, share: float = 0.9) -> int:
    """A default for d: local PCA on nearest neighbours.

    For a subsample of points, the smallest m whose top-m local variances hold
    ``share`` of the total, taking the median over points; clamped to
    ``1..k-1``.  It is only the suggestion shown when asking for d.
    """
    from scipy.spatial import cKDTree

    x = np.asarray(points, float)
    n, k = x.shape
    if n < 3 or k < 2:
        return 1
    rng = np.random.default_rng(0)
    idx = rng.choice(n, size=min(n, 300), replace=False)
    m = min(neighbours + 1, n)
    _, nb = cKDTree(x).query(x[idx], k=m)
    dims = []
    for row in nb:
        p = x[row] - x[row].mean(axis=0)
        ev = np.linalg.svd(p, compute_uv=False) ** 2
        frac = np.cumsum(ev) / max(ev.sum(), 1e-300)
        dims.append(int(np.searchsorted(frac, share) + 1))
    return int(np.clip(np.median(dims), 1, k - 1))
