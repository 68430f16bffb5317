"""The catalogue of built-in test manifolds: parametrizations and true topology.

The sampling machinery (charts, rejection sampling, farthest-point thinning)
is in :mod:`.sampling`; this module builds on it, and it knows no manifold.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .sampling import Chart, TestManifold

_TAU = 2.0 * np.pi


def _circle(u: np.ndarray) -> np.ndarray:
    t = u[:, 0]
    return np.stack([np.cos(t), np.sin(t)], axis=1)


def _ellipse(u: np.ndarray) -> np.ndarray:
    t = u[:, 0]
    return np.stack([np.cos(t), 0.5 * np.sin(t)], axis=1)


def _torus_knot(t: np.ndarray) -> np.ndarray:
    """The (2, 3) torus knot on the torus with radii 1 and 0.5, shape (m, 3)."""
    rho = 1.0 + 0.5 * np.cos(3 * t)
    return np.stack([rho * np.cos(2 * t), rho * np.sin(2 * t), 0.5 * np.sin(3 * t)], axis=1)


def _trefoil(u: np.ndarray) -> np.ndarray:
    return _torus_knot(u[:, 0])


def _circle_r4(u: np.ndarray) -> np.ndarray:
    t = u[:, 0]
    return np.column_stack([_torus_knot(t), 0.35 * np.cos(t)])


def _hopf_a(u: np.ndarray) -> np.ndarray:
    t = u[:, 0]
    return np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], axis=1)


def _hopf_b(u: np.ndarray) -> np.ndarray:
    t = u[:, 0]
    return np.stack([1.0 + np.cos(t), np.zeros_like(t), np.sin(t)], axis=1)


def _sphere(u: np.ndarray) -> np.ndarray:
    th, ph = u[:, 0], u[:, 1]
    return np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=1)


def _ellipsoid(u: np.ndarray) -> np.ndarray:
    return _sphere(u) * np.array([1.0, 0.8, 0.6])


def _sphere_r4(u: np.ndarray) -> np.ndarray:
    p = _sphere(u)
    w = 0.4 * (p[:, 0] * p[:, 1] + p[:, 2] ** 2)
    return np.column_stack([p, w])


def _torus(u: np.ndarray) -> np.ndarray:
    a, b = u[:, 0], u[:, 1]
    rho = 1.0 + 0.45 * np.cos(b)
    return np.stack([rho * np.cos(a), rho * np.sin(a), 0.45 * np.sin(b)], axis=1)


def _clifford(u: np.ndarray) -> np.ndarray:
    a, b = u[:, 0], u[:, 1]
    return np.stack([np.cos(a), np.sin(a), np.cos(b), np.sin(b)], axis=1) / np.sqrt(2.0)


def _klein(u: np.ndarray) -> np.ndarray:
    a, b = u[:, 0], u[:, 1]
    rho = 1.0 + 0.45 * np.cos(b)
    s = 0.45 * np.sin(b)
    return np.stack([rho * np.cos(a), rho * np.sin(a), s * np.cos(a / 2), s * np.sin(a / 2)], axis=1)


def _torus_r5(u: np.ndarray) -> np.ndarray:
    a, b = u[:, 0], u[:, 1]
    return np.stack([np.cos(a), np.sin(a), np.cos(b), np.sin(b), 0.3 * np.sin(a + b)], axis=1)


def _s3(u: np.ndarray) -> np.ndarray:
    eta, a, b = u[:, 0], u[:, 1], u[:, 2]
    c, s = np.cos(eta), np.sin(eta)
    return np.stack([c * np.cos(a), c * np.sin(a), s * np.cos(b), s * np.sin(b)], axis=1)


_LOOP = ((0.0,), (_TAU,))
_SPHERE_BOX = ((0.0, 0.0), (np.pi, _TAU))
_TORUS_BOX = ((0.0, 0.0), (_TAU, _TAU))


def _build() -> dict[str, TestManifold]:
    def tm(name, k, d, betti, euler, orientable, cospherical, default_n, desc, *charts):
        return TestManifold(
            name=name,
            k=k,
            d=d,
            betti=betti,
            euler=euler,
            orientable=orientable,
            cospherical=cospherical,
            description=desc,
            default_n=default_n,
            charts=tuple(Chart(f, *box) for f, box in charts),
        )

    items = [
        tm("circle", 2, 1, (1, 1), 0, True, True, 200,
           "Unit circle in the plane.", (_circle, _LOOP)),
        tm("ellipse", 2, 1, (1, 1), 0, True, False, 200,
           "Ellipse with semi-axes 1 and 0.5.", (_ellipse, _LOOP)),
        tm("trefoil", 3, 1, (1, 1), 0, True, False, 200,
           "Trefoil knot: the (2,3) torus knot on a torus with radii 1 and 0.5.",
           (_trefoil, _LOOP)),
        tm("hopf-link", 3, 1, (2, 2), 0, True, False, 160,
           "Two linked unit circles, one in the xy-plane, one in the xz-plane through its centre.",
           (_hopf_a, _LOOP), (_hopf_b, _LOOP)),
        tm("sphere", 3, 2, (1, 0, 1), 2, True, True, 1000,
           "Unit sphere S^2.", (_sphere, _SPHERE_BOX)),
        tm("ellipsoid", 3, 2, (1, 0, 1), 2, True, False, 1200,
           "Ellipsoid with semi-axes 1, 0.8, 0.6.", (_ellipsoid, _SPHERE_BOX)),
        tm("torus", 3, 2, (1, 2, 1), 0, True, False, 1500,
           "Torus of revolution with radii R=1 and r=0.45.", (_torus, _TORUS_BOX)),
        tm("clifford-torus", 4, 2, (1, 2, 1), 0, True, True, 1200,
           "Clifford torus (cos u, sin u, cos v, sin v)/sqrt(2) on the unit 3-sphere.",
           (_clifford, _TORUS_BOX)),
        tm("flat-klein", 4, 2, (1, 2, 1), 0, False, False, 1500,
           "Klein bottle ((1+r cos v) cos u, (1+r cos v) sin u, r sin v cos(u/2), "
           "r sin v sin(u/2)) with r=0.45.", (_klein, _TORUS_BOX)),
        tm("sphere-r4", 4, 2, (1, 0, 1), 2, True, False, 1000,
           "Unit sphere lifted to R^4 by w = 0.4 (xy + z^2).", (_sphere_r4, _SPHERE_BOX)),
        tm("s3", 4, 3, (1, 0, 0, 1), 0, True, True, 2000,
           "Unit 3-sphere in Hopf coordinates.",
           (_s3, ((0.0, 0.0, 0.0), (np.pi / 2, _TAU, _TAU)))),
        tm("circle-r4", 4, 1, (1, 1), 0, True, False, 150,
           "A circle in R^4 (codimension 3): the trefoil knot of R^3 lifted by w = 0.35 cos t.",
           (_circle_r4, _LOOP)),
        tm("torus-r5", 5, 2, (1, 2, 1), 0, True, False, 1000,
           "Torus (cos u, sin u, cos v, sin v, 0.3 sin(u+v)) in R^5 (codimension 3).",
           (_torus_r5, _TORUS_BOX)),
    ]  # fmt: skip
    return {m.name: m for m in items}


#: The built-in manifolds by name.
MANIFOLDS: dict[str, TestManifold] = _build()


def get_manifold(name: str) -> TestManifold:
    """The built-in manifold called ``name``.

    Raises
    ------
    InputError
        For an unknown name; the message lists the valid ones.
    """
    try:
        return MANIFOLDS[name]
    except KeyError:
        raise InputError(f"Unknown manifold {name!r}; choose one of {', '.join(MANIFOLDS)}.") from None


def projective_plane_points(n: int = 1000) -> np.ndarray:
    """About ``n`` points of the real projective plane in R^4 (not a built-in: no chart sampler).

    Even (Fibonacci) points of the upper half of the unit sphere, mapped by
    the embedding (xy, xz, y^2 - z^2, 2yz), which identifies antipodes.

    Returns
    -------
    ndarray of shape (about n, 4)
    """
    i = np.arange(2 * n) + 0.5
    z = 1 - 2 * i / (2 * n)
    r = np.sqrt(1 - z * z)
    phi = np.pi * (1 + 5**0.5) * i
    v = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    x, y, z = v[v[:, 2] > 0].T
    return np.stack([x * y, x * z, y * y - z * z, 2 * y * z], axis=1)


def s2_times_s1_points(n: int, tube: float = 0.4, noise: float = 0.0, seed: int = 0) -> np.ndarray:
    """N i.i.d. points of S^2 x S^1 in R^4 (not a built-in: no chart sampler), with Gaussian noise.

    The points at distance ``tube`` from the unit 2-sphere in the hyperplane w = 0, uniform by volume
    (rejection on the area element (1 + tube cos phi)^2); Z/2 Betti numbers (1, 1, 1, 1), its one tunnel the
    tube's circle, 2 pi ``tube`` long.  ``noise`` is the deviation over ``tube``.

    Returns
    -------
    ndarray of shape (n, 4)
    """
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    while sum(len(o) for o in out) < n:
        u = rng.normal(size=(4 * n, 3))
        u /= np.linalg.norm(u, axis=1)[:, None]
        phi = rng.uniform(0.0, 2 * np.pi, 4 * n)
        keep = rng.uniform(0.0, (1 + tube) ** 2, 4 * n) < (1 + tube * np.cos(phi)) ** 2
        out.append(np.c_[(1 + tube * np.cos(phi))[:, None] * u, tube * np.sin(phi)][keep])
    pts = np.vstack(out)[:n]
    return pts + rng.normal(scale=noise * tube, size=pts.shape)
