"""Test manifolds of known topology given by charts, and point samples of them.

Every manifold is given by one or more *charts*: smooth maps from a
parameter box ``lower <= u < upper`` in R^d into R^k that together cover the
manifold once (up to a set of measure zero).  Samples are drawn uniformly
with respect to the d-volume by rejection on the volume element
``sqrt(det(J^T J))`` of each chart, optionally re-weighted by a smooth
density factor, and thinned to a near-even spacing by farthest-point
sampling.  Each sample carries the true tangent space at every point so the
estimated normals of Algorithm 1 can be compared with the truth.  The
built-in manifolds are in :mod:`.manifolds`, which imports this module (and
not the other way round).

Examples
--------
>>> from crustview.core.samples.manifolds import get_manifold
>>> torus = get_manifold("torus")
>>> s = torus.sample(500, seed=1)
>>> s.points.shape, s.tangents.shape
((500, 3), (500, 3, 2))
>>> torus.betti
(1, 2, 1)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError

#: Accepted values of ``density`` and ``method`` in :meth:`TestManifold.sample`.
DENSITIES = ("uniform", "nonuniform")
METHODS = ("even", "random")

#: Candidates drawn per requested point by ``method="even"``.
OVERSAMPLE = 6
#: Ratio between the largest and the smallest density of ``"nonuniform"``.
NONUNIFORM_RATIO = 4.0

_FD_STEP = 1e-5  # central-difference step in parameter units
_BOUND_MARGIN = 1.25  # safety factor on the sampled maximum volume element
_TAU = 2.0 * np.pi

ParamMap = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Chart:
    """One parametrized piece of a manifold.

    Attributes
    ----------
    func : callable
        Maps parameters of shape (m, d) to points of shape (m, k).  It must
        be smooth on a neighbourhood of the box (central differences step
        slightly outside it).
    lower, upper : tuple of float
        The parameter box, length d.
    """

    func: ParamMap
    lower: tuple[float, ...]
    upper: tuple[float, ...]

    @property
    def d(self) -> int:
        return len(self.lower)

    @property
    def box_volume(self) -> float:
        return float(np.prod(np.subtract(self.upper, self.lower)))

    def __call__(self, u: np.ndarray) -> np.ndarray:
        return np.asarray(self.func(np.asarray(u, dtype=float)), dtype=float)

    def jacobian(self, u: np.ndarray) -> np.ndarray:
        """Central-difference Jacobian.

        Parameters
        ----------
        u : ndarray of shape (m, d)

        Returns
        -------
        ndarray of shape (m, k, d)
        """
        u = np.asarray(u, dtype=float)
        cols = []
        for j in range(u.shape[1]):
            step = np.zeros(u.shape[1])
            step[j] = _FD_STEP
            cols.append((self(u + step) - self(u - step)) / (2.0 * _FD_STEP))
        return np.stack(cols, axis=-1)

    def volume_element(self, u: np.ndarray) -> np.ndarray:
        """``sqrt(det(J^T J))`` at parameters ``u`` of shape (m, d); shape (m,)."""
        jac = self.jacobian(u)
        gram = np.einsum("mki,mkj->mij", jac, jac)
        return np.sqrt(np.clip(np.linalg.det(gram), 0.0, None))

    def grid(self, total: int) -> np.ndarray:
        """A regular grid of about ``total`` cell-centred parameters, shape (g, d)."""
        per_axis = max(2, int(round(total ** (1.0 / self.d))))
        axes = [lo + (hi - lo) * (np.arange(per_axis) + 0.5) / per_axis for lo, hi in zip(self.lower, self.upper)]
        mesh = np.meshgrid(*axes, indexing="ij")
        return np.stack([m.ravel() for m in mesh], axis=1)


@dataclass
class Sample:
    """Points drawn from a :class:`TestManifold`, with their true tangents.

    Attributes
    ----------
    points : ndarray of shape (n, k)
        In farthest-point order for ``method="even"``: every prefix is itself
        a near-even (coarser) sample.
    tangents : ndarray of shape (n, k, d)
        Orthonormal basis (columns) of the true tangent space at the
        noise-free position of each point.
    manifold : TestManifold
    seed : int or None
    noise : float
        Noise level in units of the median nearest-neighbour spacing.
    density : str
        ``"uniform"`` or ``"nonuniform"``.
    method : str
        ``"even"`` or ``"random"``.
    """

    points: np.ndarray
    tangents: np.ndarray
    manifold: TestManifold
    seed: int | None
    noise: float
    density: str
    method: str = "even"

    @property
    def n(self) -> int:
        return len(self.points)

    @property
    def normals(self) -> np.ndarray:
        """Orthonormal basis (columns) of the true normal space, shape (n, k, k - d)."""
        d = self.tangents.shape[2]
        q, _ = np.linalg.qr(self.tangents, mode="complete")
        return q[:, :, d:]


@dataclass(frozen=True)
class TestManifold:
    """A closed d-manifold in R^k with known topology.

    Attributes
    ----------
    name : str
    k, d : int
        Ambient and intrinsic dimension.
    betti : tuple of int
        Z/2 Betti numbers b_0..b_d.
    euler : int
    orientable : bool
    cospherical : bool
        Whether every point lies on one (k-1)-sphere (a degenerate input for
        Delaunay).
    description : str
    default_n : int
        A sample size at which reconstruction is expected to succeed.
    charts : tuple of Chart
        The parametrization: pieces that cover the manifold once.
    """

    __test__ = False  # not a pytest test class despite its name

    name: str
    k: int
    d: int
    betti: tuple[int, ...]
    euler: int
    orientable: bool
    cospherical: bool
    description: str
    default_n: int
    charts: tuple[Chart, ...]

    # ---------------------------------------------------------------- geometry
    @cached_property
    def _bounds(self) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
        """Per-chart bound on the volume element, chart masses, x0 range."""
        bound, mass, xs = [], [], []
        for chart in self.charts:
            u = chart.grid(60_000)
            g = chart.volume_element(u)
            bound.append(_BOUND_MARGIN * float(g.max()))
            mass.append(chart.box_volume * bound[-1])
            xs.append(chart(u)[:, 0])
        x0 = np.concatenate(xs)
        return np.array(bound), np.array(mass), (float(x0.min()), float(x0.max()))

    def density_factor(self, points: np.ndarray) -> np.ndarray:
        """The smooth factor of ``density="nonuniform"``.

        It grows geometrically along the first coordinate from 1 to
        :data:`NONUNIFORM_RATIO` across the manifold.

        Parameters
        ----------
        points : ndarray of shape (m, k)

        Returns
        -------
        ndarray of shape (m,)
        """
        lo, hi = self._bounds[2]
        s = np.clip((np.asarray(points)[:, 0] - lo) / (hi - lo), 0.0, 1.0)
        return NONUNIFORM_RATIO**s

    def _draw(self, m: int, rng: np.random.Generator, nonuniform: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rejection-sample ``m`` points: parameters (m, d), chart ids (m,), points (m, k)."""
        bound, mass, _ = self._bounds
        prob = mass / mass.sum()
        wmax = NONUNIFORM_RATIO if nonuniform else 1.0
        us, cs, xs = [], [], []
        got, rate = 0, 0.5
        while got < m:
            batch = int(1.2 * (m - got) / rate) + 64
            which = rng.choice(len(self.charts), size=batch, p=prob)
            u = rng.random((batch, self.d))
            x = np.empty((batch, self.k))
            ceiling = np.empty(batch)
            target = np.empty(batch)
            for c, chart in enumerate(self.charts):
                rows = which == c
                lo, hi = np.array(chart.lower), np.array(chart.upper)
                u[rows] = lo + (hi - lo) * u[rows]
                x[rows] = chart(u[rows])
                target[rows] = chart.volume_element(u[rows])
                ceiling[rows] = bound[c] * wmax
            if nonuniform:
                target *= self.density_factor(x)
            keep = rng.random(batch) * ceiling < target  # proposal order is kept
            us.append(u[keep])
            cs.append(which[keep])
            xs.append(x[keep])
            accepted = int(keep.sum())
            got += accepted
            rate = max(accepted / batch, 0.01)
        return (
            np.concatenate(us)[:m],
            np.concatenate(cs)[:m],
            np.concatenate(xs)[:m],
        )

    def tangents_at(self, params: np.ndarray, chart_ids: np.ndarray) -> np.ndarray:
        """Orthonormal tangent bases from the charts' Jacobians.

        Parameters
        ----------
        params : ndarray of shape (m, d)
        chart_ids : ndarray of shape (m,)

        Returns
        -------
        ndarray of shape (m, k, d)
            Gram-Schmidt of the Jacobian columns (first column along the
            first parameter direction).
        """
        out = np.empty((len(params), self.k, self.d))
        for c, chart in enumerate(self.charts):
            rows = np.flatnonzero(chart_ids == c)
            if len(rows) == 0:
                continue
            q, r = np.linalg.qr(chart.jacobian(params[rows]))
            sign = np.sign(np.diagonal(r, axis1=1, axis2=2))
            sign[sign == 0] = 1.0
            out[rows] = q * sign[:, None, :]
        return out

    # ---------------------------------------------------------------- public
    def sample(
        self,
        n: int,
        *,
        seed: int | None = 0,
        noise: float = 0.0,
        density: str = "uniform",
        method: str = "even",
    ) -> Sample:
        """Draw ``n`` points from the manifold.

        Parameters
        ----------
        n : int
            Number of points, at least 2.
        seed : int or None
            Seed of ``numpy.random.default_rng``; equal seeds give equal samples.
        noise : float
            Standard deviation of isotropic Gaussian noise added to the
            points, in units of the median nearest-neighbour spacing of the
            noise-free sample.  Tangents stay those of the noise-free points.
        density : {"uniform", "nonuniform"}
            ``"uniform"`` follows the d-volume; ``"nonuniform"`` multiplies it
            by :meth:`density_factor` (a 4x variation).
        method : {"even", "random"}
            ``"random"`` draws i.i.d. points.  ``"even"`` draws
            ``OVERSAMPLE * n`` i.i.d. candidates and keeps ``n`` of them by
            farthest-point sampling (distances scaled by the local target
            density for ``"nonuniform"``), which gives a near-even spacing.

        Returns
        -------
        Sample

        Raises
        ------
        InputError
            For an invalid argument.
        """
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
            raise InputError(f"The number of points must be an integer >= 2, got {n!r}.")
        if not np.isfinite(noise) or noise < 0:
            raise InputError(f"The noise level must be a finite number >= 0, got {noise!r}.")
        if density not in DENSITIES:
            raise InputError(f"Unknown density {density!r}; use one of {', '.join(DENSITIES)}.")
        if method not in METHODS:
            raise InputError(f"Unknown method {method!r}; use one of {', '.join(METHODS)}.")
        n = int(n)
        rng = np.random.default_rng(seed)
        nonuniform = density == "nonuniform"
        if method == "random":
            params, ids, points = self._draw(n, rng, nonuniform)
        else:
            params, ids, points = self._draw(OVERSAMPLE * n, rng, nonuniform)
            scale = self.density_factor(points) ** (1.0 / self.d) if nonuniform else None
            keep = farthest_point_sampling(points, n, rng, scale=scale)
            params, ids, points = params[keep], ids[keep], points[keep]
        tangents = self.tangents_at(params, ids)
        if noise > 0:
            spacing = float(np.median(cKDTree(points).query(points, k=2)[0][:, 1]))
            points = points + rng.normal(scale=noise * spacing, size=points.shape)
        return Sample(
            points=points,
            tangents=tangents,
            manifold=self,
            seed=seed,
            noise=float(noise),
            density=density,
            method=method,
        )

    def reference(self, n_dense: int = 20_000, *, seed: int = 12345) -> np.ndarray:
        """Dense i.i.d. points on the true manifold (uniform in d-volume).

        Parameters
        ----------
        n_dense : int
        seed : int

        Returns
        -------
        ndarray of shape (n_dense, k)
        """
        return self._draw(int(n_dense), np.random.default_rng(seed), False)[2]


def farthest_point_sampling(
    points: np.ndarray,
    n: int,
    rng: np.random.Generator,
    *,
    scale: np.ndarray | None = None,
) -> np.ndarray:
    """Greedy farthest-point subset.

    Parameters
    ----------
    points : ndarray of shape (m, k)
    n : int
        Number of rows to keep, ``n <= m``.
    rng : numpy.random.Generator
        Picks the first row.
    scale : ndarray of shape (m,), optional
        The distance of candidate ``i`` to the chosen set is multiplied by
        ``scale[i]``; larger values attract more points there.

    Returns
    -------
    ndarray of shape (n,)
        Row indices in the order they were chosen.
    """
    coords = np.ascontiguousarray(np.asarray(points, dtype=float).T)  # (k, m): fast rows
    m = coords.shape[1]
    weight = None if scale is None else np.asarray(scale, dtype=float) ** 2
    chosen = np.empty(n, dtype=np.intp)
    best = np.full(m, np.inf)
    nxt = int(rng.integers(m))
    if m > LOCAL_FPS_MIN and (weight is None or weight.min() > 0):
        return _farthest_local(coords, n, weight, chosen, best, nxt)
    dist, tmp = np.empty(m), np.empty(m)
    for i in range(n):
        chosen[i] = nxt
        dist.fill(0.0)
        for row in coords:
            np.subtract(row, row[nxt], out=tmp)
            np.multiply(tmp, tmp, out=tmp)
            dist += tmp
        if weight is not None:
            dist *= weight
        np.minimum(best, dist, out=best)
        nxt = int(np.argmax(best))
    return chosen


#: Candidates above which :func:`farthest_point_sampling` updates only the candidates near each new point
#: (:func:`_farthest_local`; the same picks).  A scheduling choice: below it the plain pass over all
#: candidates is as fast; above it the plain pass is quadratic (20,000 points took 6.6 s, 40,000 25 s, and
#: a new user's 300,000 ran for minutes without a word).
LOCAL_FPS_MIN = 20_000


def _farthest_local(
    coords: np.ndarray, n: int, weight: np.ndarray | None, chosen: np.ndarray, best: np.ndarray, nxt: int
) -> np.ndarray:
    """:func:`farthest_point_sampling`'s greedy picks, each new point updating only the candidates it can.

    A candidate's distance to the chosen set changes only where the new point is nearer than that distance,
    which is at most the largest one (the new point's own: it was the farthest).  So the candidates within
    that radius (a k-d tree's ball, widened by 1e-9 against rounding; over the smallest weight with
    ``scale``) are updated, with the same arithmetic as the plain pass (coordinates summed in order, then
    the weight), and the farthest is kept in a heap of (-distance, index) whose stale entries (a candidate
    whose distance has since dropped) are skipped: the same values and, on ties, the lowest index as
    ``np.argmax`` gives, so the same picks in the same order.
    """
    import heapq

    from scipy.spatial import cKDTree

    m = coords.shape[1]
    tree = cKDTree(coords.T)
    wmin = 1.0 if weight is None else float(weight.min())
    heap: list[tuple[float, int]] = []
    for i in range(n):
        chosen[i] = nxt
        top = best[nxt]
        if np.isfinite(top):
            radius = np.sqrt(top / wmin) * (1.0 + 1e-9)
            near = np.asarray(tree.query_ball_point(coords[:, nxt], radius), dtype=np.intp)
        else:
            near = np.arange(m)
        dist = np.zeros(len(near))
        for row in coords:
            tmp = row[near] - row[nxt]
            dist += tmp * tmp
        if weight is not None:
            dist *= weight[near]
        lower = dist < best[near]
        changed = near[lower]
        best[changed] = dist[lower]
        if not np.isfinite(top):
            heap = list(zip((-best).tolist(), range(m)))
            heapq.heapify(heap)
        else:
            for j, value in zip(changed.tolist(), best[changed].tolist()):
                heapq.heappush(heap, (-value, j))
        while -heap[0][0] != best[heap[0][1]]:
            heapq.heappop(heap)
        nxt = heap[0][1]
    return chosen


__all__ = [
    "DENSITIES",
    "METHODS",
    "Chart",
    "Sample",
    "TestManifold",
    "farthest_point_sampling",
]
