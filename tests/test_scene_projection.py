"""Projection and grand tour (pure numpy, no Qt/VTK)."""

import numpy as np
import pytest

from crustview.scene.projection import Projection, givens
from crustview.scene.tour import GrandTour, geodesic, random_frame


def orthonormal(b, m=3):
    return np.allclose(b[:, :m].T @ b[:, :m], np.eye(m), atol=1e-9)


def test_coordinates_pick_the_chosen_axes():
    p = Projection(5)
    p.set_coordinates(4, 0, 2)
    x = np.arange(5.0)[None]
    assert np.allclose(p.project(x), [[4.0, 0.0, 2.0]])
    assert p.axis_labels() == ["x5", "x1", "x3"]


def test_coordinates_reject_repeats():
    with pytest.raises(ValueError):
        Projection(4).set_coordinates(1, 1, 2)


def test_pca_captures_the_spread():
    rng = np.random.default_rng(0)
    x = rng.standard_normal((500, 4)) * [0.01, 5.0, 0.02, 3.0]
    p = Projection(4)
    p.set_pca(x)
    b = p.basis
    assert orthonormal(b)
    # the two big axes (x2, x4) dominate the first two view axes
    assert abs(b[1, 0]) > 0.99 and abs(b[3, 1]) > 0.99


def test_plane_rotation_is_a_rotation_and_composes():
    p = Projection(4)
    p.set_angle(0, 3, np.pi / 2)
    assert orthonormal(p.basis)
    assert np.allclose(p.basis[:, 0], [0, 0, 0, 1])  # x1 rotated onto x4
    assert p.description == "coordinates (1, 2, 3), rotated in x1-x4"
    p.rotate(3, 0, np.pi / 2)  # back by the same angle (reversed plane)
    assert np.allclose(p.basis, np.eye(4, 3))
    assert p.description == "coordinates (1, 2, 3)"
    assert np.allclose(givens(3, 0, 1, 0.3) @ givens(3, 0, 1, -0.3), np.eye(3))


def test_projection_does_not_modify_data():
    x = np.random.default_rng(1).standard_normal((50, 4))
    before = x.copy()
    p = Projection(4)
    p.set_pca(x)
    p.set_angle(1, 2, 0.7)
    p.project(x)
    assert np.array_equal(x, before)


def test_flat_2d_data_has_zero_z():
    p = Projection(2)
    y = p.project(np.array([[1.0, 2.0], [3.0, -1.0]]))
    assert np.allclose(y[:, 2], 0) and np.allclose(y[:, :2], [[1, 2], [3, -1]])
    assert p.flat


def test_changed_signal_fires():
    p = Projection(3)
    seen = []
    p.changed.connect(lambda: seen.append(1))
    p.set_angle(0, 1, 0.1)
    assert seen


def test_geodesic_reaches_target():
    from scipy.linalg import expm

    rng = np.random.default_rng(3)
    for k in (3, 4, 6):
        a, b = random_frame(k, 3, rng), random_frame(k, 3, rng)
        log = geodesic(a, b)
        assert np.allclose(log, -log.T)
        end = expm(log) @ a
        # the target frame up to the sign of the last axis (orientation fix)
        assert np.allclose(end[:, :2], b[:, :2], atol=1e-8)
        assert np.allclose(np.abs(end[:, 2]), np.abs(b[:, 2]), atol=1e-8)


def test_tour_moves_smoothly_and_stays_orthonormal():
    p = Projection(4)
    tour = GrandTour(p, speed=0.5, seed=1)
    prev = p.basis
    for _ in range(60):
        b = tour.advance(0.05)
        assert orthonormal(b)
        assert np.linalg.norm(b - prev) < 0.1  # small step per frame
        prev = b
    assert not np.allclose(p.basis, np.eye(4, 3))
    # a hand-set projection restarts the tour from there
    p.set_coordinates(0, 1, 2)
    b = tour.advance(0.01)
    assert np.linalg.norm(b - np.eye(4, 3)) < 0.05
