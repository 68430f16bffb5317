"""Theorems 2 and 10 on built-ins, against quantities known by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.theorems import (
    LFS_FORMS,
    check_theorems,
    dense_points,
    distance_to_filled_ellipse,
    numeric_reach,
    theorem2_bound,
)
from crustview.core.samples.manifolds import get_manifold


def test_distance_to_filled_ellipse_matches_circle_and_segment():
    q = np.array([[3.0, 4.0], [0.1, 0.2], [2.0, 0.0], [0.0, 1.0]])
    # a circle of radius 2: outside |q| - 2, inside 0
    np.testing.assert_allclose(distance_to_filled_ellipse(q, 2.0, 2.0), [3.0, 0.0, 0.0, 0.0], atol=1e-9)
    # the segment [-1, 1] x {0}
    seg = distance_to_filled_ellipse(q, 1.0, 0.0)
    np.testing.assert_allclose(seg, [math.hypot(2, 4), 0.2, 1.0, 1.0], atol=1e-9)


@pytest.mark.parametrize(
    "name, reach", [("circle", 1.0), ("torus", 0.45), ("clifford-torus", 1 / math.sqrt(2)), ("ellipse", 0.25)]
)
def test_numeric_reach_agrees_with_known_reach(name, reach):
    # the ellipse's reach is its smallest radius of curvature b^2 / a = 0.25
    pts, tan = dense_points(get_manifold(name), 3000, seed=3)
    assert numeric_reach(pts, tan) == pytest.approx(reach, rel=0.03)


@pytest.mark.parametrize("name", ["ellipse", "ellipsoid"])
def test_closed_form_lfs_between_reach_and_empty_ball_radius(name):
    """reach <= f(x) <= radius of the largest empty ball tangent at x (its centre is medial)."""
    m = get_manifold(name)
    pts, tan = dense_points(m, 2500, seed=4)
    f = LFS_FORMS[name][0](pts)
    reach = numeric_reach(pts, tan)
    assert f.min() >= reach * 0.98
    v = pts[None] - pts[:, None]
    sq = np.einsum("abk,abk->ab", v, v)
    tv = np.einsum("abk,akd->abd", v, tan)
    nrm = np.sqrt(np.maximum(sq - np.einsum("abd,abd->ab", tv, tv), 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        ball = np.where(nrm > 1e-12, sq / (2 * nrm), np.inf).min(axis=1)
    assert np.all(f <= ball * 1.02)


def test_theorem2_bound_values():
    assert theorem2_bound(np.array([0.25]), 1)[0] == pytest.approx(math.asin(0.5))
    assert theorem2_bound(np.array([0.1]), 4)[0] == pytest.approx(math.asin(0.4))
    assert theorem2_bound(np.array([1.0]), 2)[0] == pytest.approx(math.pi / 2)


def test_circle_epsilon_and_chord_distance_by_hand():
    """Unit circle: eps(s) is the chord to the middle of s's larger half-gap; M_S's farthest point is
    the sagitta of the longest chord."""
    rng = np.random.default_rng(0)
    t = np.sort(rng.uniform(0, 2 * np.pi, 40))
    rec = reconstruct(np.c_[np.cos(t), np.sin(t)], d=1)
    c = check_theorems(rec, "circle", dense=400_000)
    gaps = np.diff(np.r_[t, t[0] + 2 * np.pi])  # gap after sample i
    before, after = np.roll(gaps, 1), gaps
    half = np.maximum(before, after) / 2
    expect = 2 * np.sin(half / 2)  # chord from s to the point half a gap away (f = 1)
    order = np.argsort(rec.point_input)
    np.testing.assert_allclose(c.epsilon[order], expect, rtol=2e-3)
    assert c.epsilon_global == pytest.approx(expect.max(), rel=2e-3)
    # every edge of M_S joins neighbours; the farthest point from the circle is the midpoint of the longest
    assert rec.topology.closed_manifold
    sag = 1 - np.cos(gaps.max() / 2)
    assert c.ms_distance.max() == pytest.approx(sag, rel=0.02)


def test_normal_error_uses_the_true_normal():
    """A wrong 'truth' (tangents rotated by 90 degrees) gives errors near 90 degrees."""
    m = get_manifold("circle")
    s = m.sample(100, seed=0)
    rec = reconstruct(s.points, d=1)
    good = check_theorems(rec, m, s.tangents, dense=50_000)
    rotated = np.stack([-s.tangents[:, 1], s.tangents[:, 0]], axis=1)  # the normal, not the tangent
    bad = check_theorems(rec, m, rotated, dense=50_000)
    assert np.degrees(good.normal_error).max() < 5
    assert np.degrees(bad.normal_error).min() > 85
    assert len(bad.violations) == rec.n


@pytest.mark.parametrize("name", ["torus", "clifford-torus", "trefoil"])
def test_theorem2_holds_on_builtin_default_density(name, default_run):
    m = get_manifold(name)
    rec, s = default_run(name)  # s = m.sample(m.default_n, seed=0); rec = reconstruct(s.points, d=m.d)
    c = check_theorems(rec, m, s.tangents)
    summ = c.summary()
    assert summ["theorem2"]["beyond_local_bound"] == 0, summ["theorem2"]["violating_samples"]
    assert summ["theorem10"]["max_ratio"] <= 2.65
    # a closed-form LFS, by hand: the torus's (from its two radii) and the Clifford torus's (a product of two
    # circles of radius 1/sqrt 2); the trefoil's is numeric
    assert summ["lfs_exact"] == {"torus": True, "clifford-torus": True, "trefoil": False}[name]
    assert 0 < c.epsilon_global < 1
