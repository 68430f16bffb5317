"""The paper's Theorems 2 and 10 checked on a reconstruction of a built-in manifold.

For a built-in manifold M the truth is known, so the guarantees can be
measured instead of assumed:

* **local feature size** f(x), the distance from x to the medial axis of M.
  :data:`LFS_FORMS` gives it in closed form where it has one (circle, sphere,
  S^3: 1; torus: its tube radius; Clifford torus: 1/sqrt 2; ellipse and
  ellipsoid: the distance to their planar medial axis).  Elsewhere the
  *reach* (the smallest f over M) is used as a **lower bound** of f; it is
  computed numerically by Federer's formula
  ``reach = inf_{x != y} |y - x|^2 / (2 dist(y - x, T_x M))`` over a dense
  sample with its true tangents (:func:`numeric_reach`).  With the reach,
  epsilon below is an *upper* bound of the true epsilon and the Theorem 2
  bound computed from it is looser than the true one: a violation found is
  real, a pass says less.
* **true local epsilon** eps(s): the largest ``|p - s| / f(p)`` over the
  points p of M whose nearest sample is s.  M is sampled densely (about
  :data:`DENSE` points per dimension); the maximum over the dense points is
  a lower estimate, within ``covering / f`` of the true one, where
  ``covering`` (reported) is the largest distance from a point of M to the
  dense set, estimated on fresh random points.
* **Theorem 2**: for an eps-sample with ``eps <= 0.25 / (k - d)`` the angle
  between AN_s and the true normal plane N_s is at most
  ``asin(2 eps sqrt(k - d))``.  Checked per sample with its local eps(s)
  (a local reading, stricter than the theorem) and with the global
  ``eps = max_s eps(s)`` (the theorem as stated).
* **Theorem 10**: for ``eps < 0.25 / sqrt(k - d)`` every point of M_S lies
  within ``2.65 eps f`` of M.  Points are spread on every simplex of M_S;
  their distance to M is the normal component of the offset to the nearest
  dense point of M (second-order accurate), and f is taken at that point.

numpy and scipy only.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.spatial import cKDTree

from ..result import Reconstruction
from ..samples.manifolds import get_manifold
from ..samples.sampling import TestManifold
from .compare import dense_samples

#: Dense points of M per sample spacing, roughly, by intrinsic dimension.
DENSE = {1: 200_000, 2: 400_000, 3: 1_500_000}
#: Theorem 10's constant.
THEOREM10_FACTOR = 2.65
#: Points of the dense set used by :func:`numeric_reach`, by intrinsic dimension.
REACH_POINTS = {1: 6_000, 2: 8_000, 3: 12_000}

LfsFunction = Callable[[np.ndarray], np.ndarray]


def _constant(value: float) -> LfsFunction:
    return lambda p: np.full(len(p), float(value))


def distance_to_filled_ellipse(q: np.ndarray, a: float, b: float, samples: int = 4096) -> np.ndarray:
    """Distance in the plane from points ``q`` (m, 2) to the filled ellipse x²/a² + y²/b² <= 1.

    ``b`` may be 0 (a segment).  Outside, the nearest boundary point is found
    on a dense parametrisation and refined by Newton steps on the angle.
    """
    q = np.asarray(q, dtype=float)
    inside = (q[:, 0] / a) ** 2 + (q[:, 1] / b) ** 2 <= 1.0 if b > 0 else np.zeros(len(q), dtype=bool)
    t = np.linspace(0.0, 2 * np.pi, samples, endpoint=False)
    ring = np.c_[a * np.cos(t), b * np.sin(t)]
    _, j = cKDTree(ring).query(q)
    th = t[j]
    for _ in range(6):  # minimise |(a cos th, b sin th) - q|^2 over th
        c, s = np.cos(th), np.sin(th)
        ex, ey = a * c - q[:, 0], b * s - q[:, 1]
        g = -a * s * ex + b * c * ey
        h = a * a * s * s + b * b * c * c - a * c * ex - b * s * ey
        th = th - g / np.where(np.abs(h) > 1e-12, h, 1e-12)
    dist = np.hypot(a * np.cos(th) - q[:, 0], b * np.sin(th) - q[:, 1])
    return np.where(inside, 0.0, dist)


def _ellipse_lfs(p: np.ndarray) -> np.ndarray:
    # semi-axes 1 and 0.5: the medial axis is the segment |x| <= (a^2 - b^2) / a = 0.75 of the x-axis
    return distance_to_filled_ellipse(p[:, :2], 0.75, 0.0)


def _ellipsoid_lfs(p: np.ndarray) -> np.ndarray:
    # semi-axes a > b > c: the medial axis is the filled ellipse in z = 0 with
    # semi-axes (a^2 - c^2) / a and (b^2 - c^2) / b (the exterior has none: convex)
    a, b, c = 1.0, 0.8, 0.6
    planar = distance_to_filled_ellipse(p[:, :2], (a * a - c * c) / a, (b * b - c * c) / b)
    return np.hypot(planar, p[:, 2])


#: Closed-form local feature size of the built-ins that have one, with how it is known.
LFS_FORMS: dict[str, tuple[LfsFunction, str]] = {
    "circle": (_constant(1.0), "1 (the medial axis is the centre)"),
    "sphere": (_constant(1.0), "1 (the medial axis is the centre)"),
    "s3": (_constant(1.0), "1 (the medial axis is the centre)"),
    "torus": (_constant(0.45), "0.45, the tube radius (core circle; the z-axis is >= 0.55 away)"),
    "clifford-torus": (_constant(1 / math.sqrt(2)), "1/sqrt 2 (the medial axis is the two coordinate 2-planes)"),
    "ellipse": (_ellipse_lfs, "distance to the segment |x| <= 0.75 of the x-axis (the medial axis)"),
    "ellipsoid": (_ellipsoid_lfs, "distance to the filled ellipse of the medial axis in z = 0"),
}


def dense_points(manifold: TestManifold, m: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``m`` i.i.d. points of M uniform in d-volume and their orthonormal tangent bases.

    Returns
    -------
    points : ndarray of shape (m, k)
    tangents : ndarray of shape (m, k, d)
    """
    params, charts, pts = manifold._draw(m, np.random.default_rng(seed), False)
    return pts, manifold.tangents_at(params, charts)


def normal_offset(v: np.ndarray, tangents: np.ndarray) -> np.ndarray:
    """Length of the component of ``v`` (m, k) orthogonal to the tangent bases (m, k, d)."""
    t = np.einsum("mk,mkd->md", v, tangents)
    return np.sqrt(np.maximum(np.einsum("mk,mk->m", v, v) - np.einsum("md,md->m", t, t), 0.0))


def numeric_reach(points: np.ndarray, tangents: np.ndarray, chunk: int = 400) -> float:
    """Federer's reach ``inf |y - x|^2 / (2 dist(y - x, T_x))`` over pairs of a dense sample.

    Parameters
    ----------
    points : ndarray of shape (m, k)
        Points of M (all pairs are used: keep m at a few thousand).
    tangents : ndarray of shape (m, k, d)
        True orthonormal tangent bases at ``points``.

    Returns
    -------
    float
        An estimate from above: pairs that are not in the sample cannot lower it.
    """
    best = math.inf
    for lo in range(0, len(points), chunk):
        x, t = points[lo : lo + chunk], tangents[lo : lo + chunk]
        v = points[None, :, :] - x[:, None, :]  # (c, m, k)
        sq = np.einsum("cmk,cmk->cm", v, v)
        tv = np.matmul(v, t)  # (c, m, d); numpy's einsum had no faster path for it (about 3x slower here)
        nrm = np.sqrt(np.maximum(sq - np.einsum("cmd,cmd->cm", tv, tv), 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(nrm > 1e-12 * np.maximum(sq, 1e-300), sq / (2.0 * nrm), np.inf)
        best = min(best, float(ratio.min()))
    return best


@lru_cache(maxsize=32)
def reach_of(name: str) -> float:
    """Numerical reach of the built-in ``name`` (:func:`numeric_reach`, cached)."""
    m = get_manifold(name)
    pts, tan = dense_points(m, REACH_POINTS.get(m.d, 20_000), seed=1)
    return numeric_reach(pts, tan)


def lfs_function(name: str) -> tuple[LfsFunction, bool, str]:
    """The local feature size of the built-in ``name``.

    Returns
    -------
    lfs : callable
        Points (m, k) of M to f at them, shape (m,).
    exact : bool
        True for a closed form; False when ``lfs`` is the constant reach (a lower bound).
    how : str
        One sentence saying which.
    """
    if name in LFS_FORMS:
        fn, how = LFS_FORMS[name]
        return fn, True, f"closed form: {how}"
    r = reach_of(name)
    return (
        _constant(r),
        False,
        (
            f"no closed form: the reach {r:.4g} (Federer's formula on a dense sample) "
            "is used as a lower bound of f, so ε is an upper bound"
        ),
    )


def true_tangents_at(points: np.ndarray, dense: np.ndarray, dense_tangents: np.ndarray) -> np.ndarray:
    """Tangent bases of the nearest dense point of M to each of ``points`` (m, k)."""
    return dense_tangents[cKDTree(dense).query(points)[1]]


def principal_angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest principal angle (radians) between the column spaces of (n, k, m) orthonormal bases."""
    s = np.linalg.svd(np.einsum("nki,nkj->nij", a, b), compute_uv=False)
    return np.arccos(np.clip(s.min(axis=1), -1.0, 1.0))


def theorem2_bound(eps: np.ndarray, codim: int) -> np.ndarray:
    """``asin(2 eps sqrt(k - d))`` in radians; pi/2 where the argument exceeds 1 (no bound)."""
    return np.arcsin(np.clip(2.0 * np.asarray(eps, float) * math.sqrt(codim), 0.0, 1.0))


@dataclass
class TheoremChecks:
    """Theorems 2 and 10 measured on one reconstruction of a built-in.

    Attributes
    ----------
    manifold : str
    lfs_exact : bool
        Whether f is in closed form (else the reach, a lower bound of f).
    lfs_how : str
    epsilon : ndarray of shape (n,)
        True local epsilon of each sample (NaN: no dense point is nearest to it).
    normal_error : ndarray of shape (n,)
        Angle (radians) between AN_s and the true normal plane.
    bound : ndarray of shape (n,)
        Theorem 2's bound with the local epsilon, radians.
    epsilon_global : float
        ``max eps(s)``: S is an epsilon-sample for this epsilon.
    covering : float
        Largest distance from a point of M to the dense set (estimated).
    ms_distance : ndarray of shape (m,)
        Largest distance to M over the points spread on each simplex of M_S.
    ms_ratio : ndarray of shape (m,)
        Largest ``distance / (eps_global f)`` on each simplex (Theorem 10: <= 2.65).
    ms_step : float
        Grid step of the points spread on M_S.
    seconds : float
    """

    manifold: str
    k: int
    d: int
    lfs_exact: bool
    lfs_how: str
    epsilon: np.ndarray
    normal_error: np.ndarray
    bound: np.ndarray
    epsilon_global: float
    covering: float
    ms_distance: np.ndarray
    ms_ratio: np.ndarray
    ms_step: float
    seconds: float
    dense: int = 0
    notes: list[str] = field(default_factory=list)

    @property
    def codim(self) -> int:
        return self.k - self.d

    @property
    def violations(self) -> np.ndarray:
        """Samples whose normal error exceeds Theorem 2's bound with their local epsilon."""
        return np.flatnonzero(self.normal_error > self.bound)

    @property
    def global_bound(self) -> float:
        """Theorem 2's bound with the global epsilon, radians."""
        return float(theorem2_bound(self.epsilon_global, self.codim))

    @property
    def precondition_fails(self) -> np.ndarray:
        """Samples whose local epsilon exceeds 0.25 / (k - d), Theorem 2's precondition."""
        return np.flatnonzero(np.nan_to_num(self.epsilon, nan=np.inf) > 0.25 / self.codim)

    def summary(self) -> dict:
        """JSON-serialisable counts and extremes (angles in degrees)."""
        c = self.codim
        gb = self.global_bound
        ratio = self.ms_ratio[np.isfinite(self.ms_ratio)]
        return {
            "manifold": self.manifold,
            "k": self.k,
            "d": self.d,
            "lfs": self.lfs_how,
            "lfs_exact": self.lfs_exact,
            "dense_points": self.dense,
            "covering": self.covering,
            "epsilon_max": self.epsilon_global,
            "epsilon_median": float(np.nanmedian(self.epsilon)),
            "theorem2": {
                "epsilon_limit": 0.25 / c,
                "precondition_holds": bool(self.epsilon_global <= 0.25 / c),
                "samples_beyond_limit": int(len(self.precondition_fails)),
                "max_error_deg": float(np.degrees(np.nanmax(self.normal_error))),
                "median_error_deg": float(np.degrees(np.nanmedian(self.normal_error))),
                "global_bound_deg": float(np.degrees(gb)),
                "beyond_global_bound": int((self.normal_error > gb).sum()),
                "beyond_local_bound": int(len(self.violations)),
                "violating_samples": [int(i) for i in self.violations[:50]],
            },
            "theorem10": {
                "epsilon_limit": 0.25 / math.sqrt(c),
                "precondition_holds": bool(self.epsilon_global < 0.25 / math.sqrt(c)),
                "max_distance": float(self.ms_distance.max()) if len(self.ms_distance) else None,
                "max_ratio": float(ratio.max()) if len(ratio) else None,
                "factor": THEOREM10_FACTOR,
                "simplices_beyond": int((ratio > THEOREM10_FACTOR).sum()),
                "grid_step": self.ms_step,
            },
            "seconds": self.seconds,
            "notes": list(self.notes),
        }


def _group_max(owner: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    out = np.full(n, -np.inf)
    np.maximum.at(out, owner, values)
    return np.where(np.isfinite(out), out, np.nan)


def _query(tree: cKDTree, pts: np.ndarray, report: Callable[[float], None], chunk: int = 100_000):
    """``tree.query(pts)`` in chunks, calling ``report(fraction)`` after each (it may raise to stop)."""
    dist = np.empty(len(pts))
    idx = np.empty(len(pts), dtype=np.intp)
    for lo in range(0, len(pts), chunk):
        dist[lo : lo + chunk], idx[lo : lo + chunk] = tree.query(pts[lo : lo + chunk])
        report(min(1.0, (lo + chunk) / max(len(pts), 1)))
    return dist, idx


def check_theorems(
    rec: Reconstruction,
    manifold: TestManifold | str,
    tangents: np.ndarray | None = None,
    *,
    dense: int | None = None,
    seed: int = 0,
    progress: Callable[[str, float], None] | None = None,
    cancel=None,
) -> TheoremChecks:
    """Measure Theorems 2 and 10 on ``rec``, a reconstruction of samples of ``manifold``.

    Parameters
    ----------
    rec : Reconstruction
        Its points must lie on the manifold (noise-free samples).
    manifold : TestManifold or str
    tangents : ndarray of shape (n_in, k, d), optional
        True tangents over the *input* rows (``Sample.tangents``); default the
        tangents of the nearest dense point of M.
    dense : int, optional
        Dense points of M; default :data:`DENSE` for the dimension.
    seed : int
    progress : callable, optional
        ``progress(stage, fraction)``, called between and during the stages.
    cancel : object with ``is_set()``, optional
        When it becomes set, :class:`~crustview.core.errors.Cancelled` is raised at the next check.

    Returns
    -------
    TheoremChecks
    """
    from ..errors import Cancelled

    def report(stage: str, fraction: float) -> None:
        if cancel is not None and cancel.is_set():
            raise Cancelled("theorem check cancelled")
        if progress is not None:
            progress(stage, fraction)

    t0 = time.perf_counter()
    report("dense sample of M", 0.0)
    m = get_manifold(manifold) if isinstance(manifold, str) else manifold
    if (m.k, m.d) != (rec.k, rec.d):
        raise ValueError(f"{m.name} is a {m.d}-manifold in R^{m.k}; the reconstruction has d={rec.d}, k={rec.k}")
    lfs, exact, how = lfs_function(m.name)
    pts, tan = dense_points(m, dense or DENSE.get(m.d, 1_500_000), seed)
    report("local feature size", 0.0)
    f = lfs(pts)
    dist, owner = _query(cKDTree(rec.points), pts, lambda x: report("true epsilon", x))
    eps = _group_max(owner, dist / f, rec.n)
    report("covering radius", 0.0)
    probe, _ = dense_points(m, 20_000, seed + 1)
    covering = float(cKDTree(pts).query(probe)[0].max())
    report("normal error", 0.0)
    if tangents is None:
        true_t = true_tangents_at(rec.points, pts, tan)
    else:
        true_t = np.linalg.qr(np.asarray(tangents, float)[rec.point_input])[0]
    err = principal_angle(true_t, rec.tangents)
    c = m.k - m.d
    bound = theorem2_bound(np.nan_to_num(eps, nan=np.inf), c)
    eps_g = float(np.nanmax(eps))
    report("distance of M_S to M", 0.0)
    ms_d, ms_r, step = _ms_distance(rec, pts, tan, f, eps_g)
    report("done", 1.0)
    notes = []
    if not exact:
        notes.append("f is the reach (a lower bound): ε is an upper bound and the Theorem 2 bound a loose one")
    missing = int(np.isnan(eps).sum())
    if missing:
        notes.append(f"{missing} samples own no dense point of M (off M or duplicated)")
    return TheoremChecks(
        m.name,
        m.k,
        m.d,
        exact,
        how,
        eps,
        err,
        bound,
        eps_g,
        covering,
        ms_d,
        ms_r,
        step,
        time.perf_counter() - t0,
        len(pts),
        notes,
    )


def _ms_distance(
    rec: Reconstruction, pts: np.ndarray, tan: np.ndarray, f: np.ndarray, eps: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """Per simplex of M_S: largest distance to M, and largest distance / (eps f)."""
    simp = np.asarray(rec.manifold, dtype=np.int64)
    if len(simp) == 0:
        return np.zeros(0), np.zeros(0), 0.0
    edge = np.linalg.norm(rec.points[simp[:, 0]] - rec.points[simp[:, -1]], axis=1)
    step = float(np.median(edge)) / 4.0
    on, _ = dense_samples(rec.points, simp, step)
    owner = _owners(rec.points, simp, step)
    assert len(owner) == len(on)
    _, j = cKDTree(pts).query(on)
    dist = normal_offset(on - pts[j], tan[j])
    ratio = dist / (eps * f[j])
    return _group_max(owner, dist, len(simp)), _group_max(owner, ratio, len(simp)), step


def _owners(points: np.ndarray, simp: np.ndarray, step: float) -> np.ndarray:
    """Simplex of each point :func:`dense_samples` returns, in its order."""
    corners = points[simp]
    d = simp.shape[1] - 1
    edges = [np.linalg.norm(corners[:, i] - corners[:, j], axis=1) for i in range(d + 1) for j in range(i + 1, d + 1)]
    parts = np.maximum(1, np.ceil(np.max(edges, axis=0) / step)).astype(np.int64)
    out = []
    for mparts in np.unique(parts):
        ids = np.flatnonzero(parts == mparts)
        g = math.comb(int(mparts) + d, d)
        out.append(np.repeat(ids, g))
    return np.concatenate(out)
