"""Sampling quality per sample: an estimated epsilon(s) from the Voronoi cell.

The paper's guarantees hold for epsilon-samples: every point x of M has a
sample within ``epsilon * f(x)``, f the local feature size (distance to the
medial axis), with ``epsilon <= 0.25 / (k - d)`` (Theorem 2) or
``epsilon <= 0.25 / sqrt(k - d)`` (Theorems 3, 4, 10, 11).  Neither M nor f
is known, but each sample's Voronoi cell carries estimates of both; this is
the idea of Dey and Giesen's undersampling detection ("Detecting
undersampling in surface reconstruction", 2001): at a well-sampled sample the
Voronoi cell is *long and thin* -- long along the normal (it reaches the
medial axis: the poles of Amenta and Bern lie near it) and thin along the
tangent plane (it ends about half a sample spacing away).  Dey and Giesen call
the two extents *height* h(p) (distance to the pole) and *radius* r(p)
(farthest point of the cell inside the cocone) and flag p as undersampled
when r(p) > rho * h(p).

What is computed, per sample s (no new geometry; numpy only)
-------------------------------------------------------------
height h(s), the local feature size estimate
    The distance from s to its nearest *finite* pole.  In codimension
    k - d >= 2 these are the k - d poles of Algorithm 1 (``rec.pole_index``).
    In codimension 1 Algorithm 1 keeps only the farthest Voronoi vertex p+; the
    Amenta-Bern *negative pole* p- (the farthest vertex v of the cell with
    ``(v - s) . (p+ - s) < 0``, on the other side of the surface) is added,
    so that the medial axis on both sides counts.  Codimension here is that of
    the samples' affine hull, where Algorithm 1 ran: a surface in a 3-flat of
    R^4 is a hypersurface of the flat (until session 40 it got one side only,
    and its epsilon came out 3.5 times smaller than the same surface's in R^3).
    A pole at infinity (a sample on the convex hull) does not count.  NaN when
    no finite pole exists.
radius r(s), the local spacing
    The radius of the cell within the tangent plane: the largest distance from
    s of a point of ``V_s ∩ (s + AT_s)``.  Along a unit tangent direction u the
    cell ends at ``min_q |q - s|^2 / (2 (q - s) . u)`` over the Delaunay
    neighbours q (bounding points included) with ``(q - s) . u > 0`` (the
    bisector of s and q).  r(s) is the maximum over ``directions(d)``: +-u for
    d = 1 (exact), 16 evenly spaced directions for d = 2 (within 2% of the
    exact radius: cos(pi/16) = 0.98), a fixed set for d >= 3.  This is Dey and
    Giesen's cocone radius for a cocone of angle 0, so it needs no search over
    cell edges and is cheap.  It is about half the distance to the farthest
    neighbour along the surface, and it becomes large where the samples leave
    a gap (the cell is wide there) and on the boundary of an open scan.
epsilon(s) = r(s) / h(s)
    The estimated epsilon at s: the farthest point of M whose nearest sample is
    s is about r(s) away, and f(s) is about h(s).  ``1 / epsilon`` is Dey and
    Giesen's aspect ratio of the cell (height over width).  These are estimates:
    h overestimates f where a pole is not on the medial axis (undersampling
    moves the poles), so epsilon is a lower bound in the worst places, and
    noise of size comparable to the spacing makes cells short (large epsilon).
    In codimension >= 2 on nearly flat data (a planar curve in R^3) the poles
    lie somewhere along the medial axis, and h can be a few times f.

The cost is one pass over the Delaunay edges (and, in codimension 1, over the
(simplex, vertex) incidences), with per-sample maxima by ``np.maximum.at``
(no sorting): 20 s at 300,000 torus samples before that change, a few
seconds after (see ``benchmarks/bench_viewer.py``, which times it).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..delaunay.faces import enumerate_faces
from ..result import Reconstruction

#: Number of tangent directions tried per sample for d = 2.
N_DIRECTIONS_2D = 16


def thresholds(k: int, d: int) -> dict[str, float]:
    """The paper's bounds on epsilon for codimension ``k - d``.

    Returns
    -------
    dict
        ``{"theorem 2": 0.25 / (k - d), "theorems 3, 4, 10, 11": 0.25 / sqrt(k - d)}``
        (equal in codimension 1).
    """
    c = max(int(k) - int(d), 1)
    return {"theorem 2": 0.25 / c, "theorems 3, 4, 10, 11": 0.25 / float(np.sqrt(c))}


@dataclass(frozen=True)
class SamplingQuality:
    """Estimated sampling quality of every sample.

    Attributes
    ----------
    epsilon : ndarray of shape (n,)
        ``radius / height`` (NaN where the height is unknown).
    height : ndarray of shape (n,)
        Distance to the nearest finite pole (local feature size estimate).
    radius : ndarray of shape (n,)
        Radius of the Voronoi cell within the tangent plane (local spacing).
    thresholds : dict of str to float
        :func:`thresholds` for this codimension.
    seconds : float
        Time the computation took.
    """

    epsilon: np.ndarray
    height: np.ndarray
    radius: np.ndarray
    thresholds: dict[str, float]
    seconds: float

    @property
    def aspect(self) -> np.ndarray:
        """Dey-Giesen aspect ratio of each cell, height / radius (= 1 / epsilon)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.height / self.radius

    def beyond(self, bound: float) -> np.ndarray:
        """Boolean mask of the samples whose epsilon exceeds ``bound`` (NaN: False)."""
        return np.nan_to_num(self.epsilon, nan=-np.inf) > bound


def directions(d: int) -> np.ndarray:
    """Unit directions in R^d at which the cell's tangential extent is measured, shape (m, d)."""
    if d == 1:
        return np.array([[1.0], [-1.0]])
    if d == 2:
        a = np.arange(N_DIRECTIONS_2D) * (2 * np.pi / N_DIRECTIONS_2D)
        return np.c_[np.cos(a), np.sin(a)]
    # +-axes, +-diagonals of pairs, and fixed pseudo-random directions
    eye = np.eye(d)
    pairs = [eye[i] * si + eye[j] * sj for i in range(d) for j in range(i + 1, d) for si in (1, -1) for sj in (1, -1)]
    rnd = np.random.default_rng(0).normal(size=(8 * d, d))
    u = np.vstack([eye, -eye, np.array(pairs), rnd])
    return u / np.linalg.norm(u, axis=1, keepdims=True)


def delaunay_edges(simplices: np.ndarray) -> np.ndarray:
    """Unique edges ``(a, b)``, ``a < b``, of a table of simplices, lexicographically sorted.

    The 1-faces of :func:`~crustview.core.delaunay.faces.enumerate_faces` with every vertex counted
    (bounding points included): for int32 simplices its compiled radix sort,
    a fraction of the time and memory of sorting one key per edge instance.
    """
    s = np.asarray(simplices)
    m = int(s.max()) + 1 if s.size else 1
    return enumerate_faces(s, m, 1)[0]


#: Simplices per block in :func:`pole_height`.
QUALITY_BLOCK = 1 << 18
#: (sample, neighbour) rows per block in :func:`cell_radius`.
QUALITY_ROWS = 1 << 20


def cell_radius(
    points: np.ndarray,
    neighbours: np.ndarray,
    edges: np.ndarray,
    tangents: np.ndarray,
    step: Callable[[float], None] | None = None,
) -> np.ndarray:
    """Radius of each sample's Voronoi cell within its tangent plane.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    neighbours : ndarray of shape (m, k)
        Every Delaunay vertex (samples first, then bounding points).
    edges : ndarray of shape (e, 2)
        Delaunay edges, indices into ``neighbours``.
    tangents : ndarray of shape (n, k, d)
        Orthonormal tangent bases.
    step : callable(fraction), optional
        Called after each block of rows (it may raise to cancel).

    Returns
    -------
    ndarray of shape (n,)
    """
    n, _, d = tangents.shape
    a, b = edges[:, 0], edges[:, 1]
    s_all = np.concatenate([a, b])
    q_all = np.concatenate([b, a])
    keep = s_all < n  # rows (sample, neighbour); bounding points own no row
    s_all, q_all = s_all[keep], q_all[keep]
    dirs = directions(d).T.astype(np.float32)
    # per direction, the largest value over each sample's rows (0 where none
    # is positive: the cell is unbounded that way, and r(s) is infinite below)
    best = np.zeros((dirs.shape[1], n), dtype=np.float32)
    for lo in range(0, len(s_all), QUALITY_ROWS):  # blocks: temporaries stay small, cancel is checked
        s, q = s_all[lo : lo + QUALITY_ROWS], q_all[lo : lo + QUALITY_ROWS]
        v = neighbours[q] - points[s]
        sq = np.einsum("ij,ij->i", v, v)
        vt = np.einsum("ik,ikd->id", v, tangents[s])  # tangential coordinates of q - s
        # 1 / (distance to the bisector of s and q along u) = 2 (q - s).u / |q - s|^2; the cell ends
        # at the largest such value over q (none > 0: unbounded), and r(s) = max over u of 1 / it
        inv = (vt * (2.0 / np.maximum(sq, 1e-300))[:, None]).astype(np.float32) @ dirs
        for j in range(inv.shape[1]):
            np.maximum.at(best[j], s, inv[:, j])
        if step is not None:
            step(min(1.0, (lo + QUALITY_ROWS) / max(len(s_all), 1)))
    worst = best.min(axis=0).astype(np.float64)
    with np.errstate(divide="ignore"):
        return np.where(worst > 0, 1.0 / worst, np.inf)


def pole_height(rec: Reconstruction, step: Callable[[float], None] | None = None) -> np.ndarray:
    """Distance from each sample to its nearest finite pole (see the module docstring).

    ``step(fraction)`` is called after each block of simplices (it may raise to cancel).
    """
    n = rec.n
    t = len(rec.delaunay_simplices)
    idx = rec.pole_index
    finite = (idx >= 0) & (idx < t)
    pos = rec.voronoi_vertices[np.where(finite, idx, 0)]  # (n, c, k)
    dist = np.linalg.norm(pos - rec.points[:, None, :], axis=2)
    h = np.where(finite, dist, np.inf).min(axis=1) if idx.shape[1] else np.full(n, np.inf)
    # a hypersurface of the samples' affine hull (a surface in a 3-flat of R^4 too: Algorithm 1 ran in the
    # flat, one pole per sample) has the medial axis on both sides of it within the hull
    if rec.subspace_dim - rec.d == 1:
        sign = np.ones(n)
        if idx.shape[1]:
            # orient each normal towards p+ (Algorithm 1 may store either sign)
            ref = rec.voronoi_vertices[np.where(idx[:, 0] >= 0, idx[:, 0], 0)] - rec.points
            sign = np.sign(np.einsum("ij,ij->i", ref, rec.normals[:, :, 0]))
            sign[sign == 0] = 1.0
        # the negative pole: the farthest Voronoi vertex on the other side, by
        # squared length (sqrt is monotonic: the root of the largest square is
        # the largest length), in blocks of simplices so temporaries stay small
        far2 = np.full(n, -np.inf)
        simp = rec.delaunay_simplices
        r = simp.shape[1]
        for lo in range(0, t, QUALITY_BLOCK):
            flat = simp[lo : lo + QUALITY_BLOCK].ravel()
            keep = np.flatnonzero(flat < n)
            owner = flat[keep]
            u = rec.voronoi_vertices[lo + keep // r] - rec.points[owner]
            side = np.einsum("ij,ij->i", u, rec.normals[owner, :, 0]) * sign[owner]
            behind = side < 0
            np.maximum.at(far2, owner[behind], (u[behind] * u[behind]).sum(axis=1))
            if step is not None:
                step(min(1.0, (lo + QUALITY_BLOCK) / max(t, 1)))
        behind_any = np.isfinite(far2)  # -inf: no Voronoi vertex on the other side
        h = np.minimum(h, np.where(behind_any, np.sqrt(np.where(behind_any, far2, 0.0)), np.inf))
    return np.where(np.isfinite(h), h, np.nan)


def sampling_quality(
    rec: Reconstruction,
    progress: Callable[[float], None] | None = None,
    cancel: object | None = None,
) -> SamplingQuality:
    """Estimated epsilon, height and radius of every sample of ``rec``.

    Parameters
    ----------
    rec : Reconstruction
        Any reconstruction (only the Delaunay, poles and bases are used; the
        extraction mode does not matter).
    progress : callable(fraction), optional
        Called between and inside the three passes (edges, radius, height).
    cancel : object with ``is_set()``, optional
        Checked between blocks; raises :class:`~crustview.core.errors.Cancelled`.

    Returns
    -------
    SamplingQuality

    Examples
    --------
    >>> import numpy as np
    >>> from crustview.core import reconstruct
    >>> t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    >>> q = sampling_quality(reconstruct(np.c_[np.cos(t), np.sin(t)], d=1))
    >>> bool(np.allclose(q.epsilon, np.tan(np.pi / 60), rtol=0.02))
    True
    """
    from ..errors import Cancelled

    def part(lo: float, hi: float) -> Callable[[float], None]:
        def step(fraction: float) -> None:
            if cancel is not None and cancel.is_set():
                raise Cancelled("sampling quality cancelled")
            if progress is not None:
                progress(lo + (hi - lo) * fraction)

        return step

    t0 = time.perf_counter()
    part(0.0, 0.0)(0.0)
    edges = delaunay_edges(rec.delaunay_simplices)
    radius = cell_radius(rec.points, rec.delaunay_points, edges, rec.tangents, step=part(0.25, 0.6))
    height = pole_height(rec, step=part(0.6, 1.0))
    part(1.0, 1.0)(1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        eps = radius / height
    eps = np.where(np.isfinite(eps), eps, np.nan)
    return SamplingQuality(eps, height, radius, thresholds(rec.k, rec.d), time.perf_counter() - t0)


def summary(rec: Reconstruction, quality: SamplingQuality | None = None) -> dict:
    """Counts of samples beyond the paper's epsilon bounds, for the report.

    Returns
    -------
    dict
        ``{"epsilon_median", "epsilon_p90", "epsilon_max", "undetermined",
        "thresholds": {name: bound}, "beyond": {name: count},
        "beyond_share": {name: fraction}, "seconds"}``; ``undetermined`` counts
        samples without a finite pole.  JSON-serialisable.
    """
    q = sampling_quality(rec) if quality is None else quality
    ok = q.epsilon[np.isfinite(q.epsilon)]
    n = max(len(q.epsilon), 1)
    beyond = {name: int(q.beyond(b).sum()) for name, b in q.thresholds.items()}
    return {
        "epsilon_median": float(np.median(ok)) if len(ok) else None,
        "epsilon_p90": float(np.percentile(ok, 90)) if len(ok) else None,
        "epsilon_max": float(ok.max()) if len(ok) else None,
        "undetermined": int(len(q.epsilon) - len(ok)),
        "thresholds": dict(q.thresholds),
        "beyond": beyond,
        "beyond_share": {name: c / n for name, c in beyond.items()},
        "seconds": float(q.seconds),
    }


def feature_epsilon(epsilon: np.ndarray, vertices: np.ndarray) -> dict[str, float | None]:
    """The estimated epsilon where a feature is: over its samples (a loop, a rim, a gap's two sides).

    A feature is supported by the sample where the sample resolves it; the issue's question "what is the
    estimated epsilon there" is answered by the samples the feature runs through.  The median is the
    feature's typical value (one noisy cell, whose short pole makes its estimate large, does not set it);
    the maximum is its coarsest sample, where a loop or rim is least resolved.

    Parameters
    ----------
    epsilon : ndarray of shape (n,)
        :attr:`SamplingQuality.epsilon` (NaN where a sample has no finite pole).
    vertices : ndarray of int
        The feature's samples (``Feature.vertices``), each counted once (a loop as the basis search found it
        ends where it began); indices outside ``epsilon`` are ignored.

    Returns
    -------
    dict
        ``{"epsilon": median, "epsilon_max": maximum}`` over the feature's samples with a finite estimate;
        both None when none has one.

    Examples
    --------
    >>> feature_epsilon(np.array([0.1, 0.2, np.nan, 0.4]), np.array([0, 1, 2, 3, 9]))
    {'epsilon': 0.2, 'epsilon_max': 0.4}
    """
    v = np.unique(np.asarray(vertices, dtype=np.int64).ravel())  # a closed walk repeats its first sample
    v = v[(v >= 0) & (v < len(epsilon))]
    e = np.asarray(epsilon, dtype=float)[v]
    e = e[np.isfinite(e)]
    if len(e) == 0:
        return {"epsilon": None, "epsilon_max": None}
    return {"epsilon": float(np.median(e)), "epsilon_max": float(e.max())}
