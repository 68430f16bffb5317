"""Built-in test manifolds: geometry, tangents, sampling statistics."""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.spatial import cKDTree

from crustview.core.errors import InputError
from crustview.core.samples.manifolds import MANIFOLDS, get_manifold
from crustview.core.samples.sampling import NONUNIFORM_RATIO, Sample

EXPECTED_NAMES = {
    "circle", "ellipse", "trefoil", "hopf-link", "sphere", "ellipsoid", "torus",
    "clifford-torus", "flat-klein", "sphere-r4", "s3", "circle-r4", "torus-r5",
}  # fmt: skip


# ---------------------------------------------------------------- implicit equations
# Each function returns residuals that vanish exactly on the manifold, derived
# from its definition independently of the parametrization code.
def _wrap(a):
    """Angle difference to (-pi, pi]."""
    return np.angle(np.exp(1j * a))


def _knot_residuals(p):
    """(2,3) torus knot on the torus with radii 1, 0.5: the tube equation and 3 phi = 2 psi."""
    rho = np.hypot(p[:, 0], p[:, 1])
    phi = np.arctan2(p[:, 1], p[:, 0])
    psi = np.arctan2(p[:, 2], rho - 1.0)
    return [(rho - 1.0) ** 2 + p[:, 2] ** 2 - 0.25, _wrap(3 * phi - 2 * psi)]


def _hopf(p):
    on_a = np.abs(p[:, 2]) + np.abs(np.hypot(p[:, 0], p[:, 1]) - 1)
    on_b = np.abs(p[:, 1]) + np.abs(np.hypot(p[:, 0] - 1, p[:, 2]) - 1)
    return [np.minimum(on_a, on_b)]


def _klein(p):
    rho = np.hypot(p[:, 0], p[:, 1])
    u = np.arctan2(p[:, 1], p[:, 0])
    tube = (rho - 1) ** 2 + p[:, 2] ** 2 + p[:, 3] ** 2 - 0.45**2
    twist = p[:, 2] * np.sin(u / 2) - p[:, 3] * np.cos(u / 2)  # (z, w) parallel to e^{iu/2}
    return [tube, twist]


def _circle_r4(p):
    rho = np.hypot(p[:, 0], p[:, 1])
    t = np.arctan2(p[:, 2], rho - 1.0) - np.arctan2(p[:, 1], p[:, 0])  # 3t - 2t
    return [*_knot_residuals(p[:, :3]), p[:, 3] - 0.35 * np.cos(t)]


def _torus_r5(p):
    u, v = np.arctan2(p[:, 1], p[:, 0]), np.arctan2(p[:, 3], p[:, 2])
    return [
        np.hypot(p[:, 0], p[:, 1]) - 1,
        np.hypot(p[:, 2], p[:, 3]) - 1,
        p[:, 4] - 0.3 * np.sin(u + v),
    ]


IMPLICIT = {
    "circle": lambda p: [np.linalg.norm(p, axis=1) - 1],
    "ellipse": lambda p: [p[:, 0] ** 2 + (p[:, 1] / 0.5) ** 2 - 1],
    "trefoil": _knot_residuals,
    "hopf-link": _hopf,
    "sphere": lambda p: [np.linalg.norm(p, axis=1) - 1],
    "ellipsoid": lambda p: [(p / [1.0, 0.8, 0.6]) ** 2 @ np.ones(3) - 1],
    "torus": lambda p: [(np.hypot(p[:, 0], p[:, 1]) - 1) ** 2 + p[:, 2] ** 2 - 0.45**2],
    "clifford-torus": lambda p: [p[:, 0] ** 2 + p[:, 1] ** 2 - 0.5, p[:, 2] ** 2 + p[:, 3] ** 2 - 0.5],
    "flat-klein": _klein,
    "sphere-r4": lambda p: [
        np.linalg.norm(p[:, :3], axis=1) - 1,
        p[:, 3] - 0.4 * (p[:, 0] * p[:, 1] + p[:, 2] ** 2),
    ],
    "s3": lambda p: [np.linalg.norm(p, axis=1) - 1],
    "circle-r4": _circle_r4,
    "torus-r5": _torus_r5,
}

ALL = sorted(MANIFOLDS)


# ---------------------------------------------------------------- registry
def test_registry_has_every_manifold_and_an_equation_for_each():
    assert set(MANIFOLDS) == EXPECTED_NAMES
    assert set(IMPLICIT) == EXPECTED_NAMES


@pytest.mark.parametrize("name", ALL)
def test_metadata_is_consistent(name):
    m = get_manifold(name)
    assert m.name == name
    assert 1 <= m.d < m.k
    assert len(m.betti) == m.d + 1
    assert m.betti == m.betti[::-1]  # Poincare duality over Z/2 (closed manifolds)
    assert m.euler == sum((-1) ** i * b for i, b in enumerate(m.betti))
    assert m.default_n >= 50 and m.description
    for chart in m.charts:
        assert chart.d == m.d
        assert chart(np.zeros((3, m.d))).shape == (3, m.k)


def test_unknown_name_lists_the_valid_ones():
    with pytest.raises(InputError) as info:
        get_manifold("doughnut")
    msg = str(info.value)
    assert "doughnut" in msg and all(name in msg for name in MANIFOLDS)


# ---------------------------------------------------------------- geometry
@pytest.mark.parametrize("name", ALL)
def test_points_lie_on_the_manifold(name):
    m = get_manifold(name)
    s = m.sample(300, seed=1)
    assert isinstance(s, Sample)
    assert s.points.shape == (300, m.k) and s.points.dtype == np.float64
    assert s.tangents.shape == (300, m.k, m.d)
    for res in IMPLICIT[name](s.points):
        assert np.abs(res).max() < 1e-9
    for res in IMPLICIT[name](m.reference(2000)):
        assert np.abs(res).max() < 1e-9


@pytest.mark.parametrize("name", ALL)
def test_tangents_orthonormal_and_normal_to_local_pca_normal(name):
    m = get_manifold(name)
    s = m.sample(200, seed=2)
    gram = np.einsum("nki,nkj->nij", s.tangents, s.tangents)
    assert np.abs(gram - np.eye(m.d)).max() < 1e-12
    normals = s.normals
    assert normals.shape == (200, m.k, m.k - m.d)
    assert np.abs(np.einsum("nki,nkj->nij", normals, s.tangents)).max() < 1e-12
    # Numerical normal: the trailing principal directions of a small patch of
    # a dense independent sample around each point.
    ref = m.reference(60_000 if m.d < 3 else 150_000, seed=7)
    _, nbr = cKDTree(ref).query(s.points[:40], k=12 * m.d)
    errors = []
    for i, rows in enumerate(nbr):
        patch = ref[rows] - ref[rows].mean(axis=0)
        est_normal = np.linalg.svd(patch)[2][m.d :].T  # (k, k - d)
        errors.append(np.linalg.norm(est_normal.T @ s.tangents[i], 2))
    assert max(errors) < 0.1


@pytest.mark.parametrize("name", ["sphere", "s3", "clifford-torus"])
def test_tangents_against_analytic_normals(name):
    s = get_manifold(name).sample(300, seed=3)
    p = s.points
    if name == "clifford-torus":
        normals = [p * [1, 1, 0, 0], p * [0, 0, 1, 1]]
    else:
        normals = [p]
    for nrm in normals:
        assert np.abs(np.einsum("nk,nkd->nd", nrm, s.tangents)).max() < 1e-8


@pytest.mark.parametrize("name", ALL)
def test_cospherical_flag_matches_the_points(name):
    m = get_manifold(name)
    p = m.reference(3000)
    # |p|^2 = 2 c.p + (rho^2 - |c|^2) is linear in (c, const).
    a = np.column_stack([2 * p, np.ones(len(p))])
    b = (p**2).sum(axis=1)
    coef = np.linalg.lstsq(a, b, rcond=None)[0]
    residual = np.abs(a @ coef - b).max()
    if m.cospherical:
        assert residual < 1e-9
    else:
        assert residual > 1e-3


@pytest.mark.parametrize("name", ALL)
def test_points_span_the_ambient_space(name):
    m = get_manifold(name)
    p = m.reference(3000)
    sv = np.linalg.svd(p - p.mean(axis=0), compute_uv=False)
    assert len(sv) == m.k and sv[-1] > 0.05 * sv[0]


def test_hopf_link_samples_both_components_equally():
    p = get_manifold("hopf-link").sample(400, seed=0, method="random").points
    on_a = np.abs(p[:, 2]) < 1e-12
    assert 150 < on_a.sum() < 250  # equal lengths: binomial(400, 1/2)


# ---------------------------------------------------------------- statistics
def test_sphere_random_is_uniform_in_area():
    # Archimedes: z is uniform on [-1, 1] for the uniform area measure.
    z = np.sort(get_manifold("sphere").sample(3000, seed=5, method="random").points[:, 2])
    ks = np.abs(np.arange(1, 3001) / 3000 - (z + 1) / 2).max()
    assert ks < 0.03  # 1 % critical value is 1.63 / sqrt(3000) = 0.0298


def test_torus_random_is_uniform_in_area():
    # Area element (R + r cos psi): E[cos psi] = pi r / (2 pi R) = r / (2 R).
    p = get_manifold("torus").sample(20_000, seed=6, method="random").points
    cos_psi = (np.hypot(p[:, 0], p[:, 1]) - 1.0) / 0.45
    assert abs(cos_psi.mean() - 0.45 / 2) < 0.02  # std of the mean ~ 0.005


def _nn(points):
    return cKDTree(points).query(points, k=2)[0][:, 1]


def test_even_spacing_is_much_more_regular_than_random():
    m = get_manifold("sphere")
    even, rand = _nn(m.sample(800, seed=1).points), _nn(m.sample(800, seed=1, method="random").points)
    assert even.min() > 5 * rand.min()
    assert even.max() / even.min() < 2.5


def test_seeds_reproduce_and_differ():
    m = get_manifold("torus")
    for method in ("even", "random"):
        a, b = m.sample(300, seed=11, method=method), m.sample(300, seed=11, method=method)
        np.testing.assert_array_equal(a.points, b.points)
        np.testing.assert_array_equal(a.tangents, b.tangents)
        c = m.sample(300, seed=12, method=method)
        assert not np.allclose(a.points, c.points)


def _circle_fraction_right(weighted: bool) -> float:
    """Fraction of the circle's (weighted) length with x > 0, by quadrature."""
    t = (np.arange(200_000) + 0.5) / 200_000 * 2 * np.pi
    w = NONUNIFORM_RATIO ** ((np.cos(t) + 1) / 2) if weighted else np.ones_like(t)
    return float(w[np.cos(t) > 0].sum() / w.sum())


@pytest.mark.parametrize("method", ["random", "even"])
def test_nonuniform_density_follows_the_factor(method):
    m = get_manifold("circle")
    expected = _circle_fraction_right(True)
    assert expected > 0.6  # the factor really tilts the mass
    p = m.sample(4000, seed=2, density="nonuniform", method=method).points
    assert abs((p[:, 0] > 0).mean() - expected) < 0.03
    q = m.sample(4000, seed=2, method=method).points
    assert abs((q[:, 0] > 0).mean() - _circle_fraction_right(False)) < 0.03


def test_nonuniform_even_spacing_varies_across_a_surface():
    m = get_manifold("sphere")
    f = m.density_factor(m.reference(5000))
    assert f.min() == pytest.approx(1, abs=0.02) and f.max() == pytest.approx(NONUNIFORM_RATIO, abs=0.05)

    def spacing_ratio(density):
        p = m.sample(1500, seed=4, density=density).points
        nn = _nn(p)
        return np.median(nn[p[:, 0] < -0.6]) / np.median(nn[p[:, 0] > 0.6])

    # density ~ 1.1 vs ~3.5 there; spacing ~ density^(-1/2) -> ratio ~ 1.75
    assert spacing_ratio("nonuniform") > 1.4
    assert abs(spacing_ratio("uniform") - 1) < 0.1


def test_noise_scale_and_tangents_unchanged():
    m = get_manifold("sphere")
    clean, noisy = m.sample(2000, seed=9), m.sample(2000, seed=9, noise=0.3)
    np.testing.assert_array_equal(clean.tangents, noisy.tangents)
    spacing = np.median(_nn(clean.points))
    radial = np.linalg.norm(noisy.points, axis=1) - 1
    assert radial.std() == pytest.approx(0.3 * spacing, rel=0.1)
    assert noisy.noise == 0.3 and clean.noise == 0.0


@pytest.mark.timing
def test_even_sampling_is_fast():
    m = get_manifold("torus")
    m.sample(100)  # warm the cached bounds
    start = time.perf_counter()
    m.sample(3000, seed=1)
    assert time.perf_counter() - start < 2.0  # ~0.2 s here; generous for loaded machines


@pytest.mark.parametrize(
    "kwargs",
    [{"n": 1}, {"n": 2.5}, {"n": 10, "noise": -1.0}, {"n": 10, "noise": float("nan")},
     {"n": 10, "density": "dense"}, {"n": 10, "method": "grid"}],
)  # fmt: skip
def test_bad_arguments_raise_input_error(kwargs):
    with pytest.raises(InputError):
        get_manifold("circle").sample(**kwargs)


# ---------------------------------------------------------------- the promise of default_n
# torus-r5 is left out: a Delaunay triangulation in R^5 takes most of a minute.
@pytest.mark.slow
@pytest.mark.parametrize("name", [name for name in ALL if name != "torus-r5"])
def test_default_n_reconstructs_the_right_topology(name, default_run):
    m = get_manifold(name)
    rec, _ = default_run(name)  # reconstruct(m.sample(m.default_n, seed=0).points, m.d), shared per process
    assert rec.topology.closed_manifold
    assert tuple(rec.topology.betti) == m.betti
    assert rec.topology.euler == m.euler
    assert rec.topology.orientable == m.orientable
