"""bench_thin.py's U: its two bumps are the gap it says apart, and its sample lies on the union's surface."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_thin import BALL, RADIUS, REACH, SPACING, u_distance, u_shape, u_with_bumps  # noqa: E402


def test_the_bumps_are_the_gap_apart_and_reach_into_the_space_between_the_arms():
    for gap in (0.1, 0.2):
        caps, (c1, c2) = u_shape(gap)
        assert np.isclose(np.linalg.norm(c2 - c1) - 2 * BALL, gap)
        left_arm, right_arm = caps[0][0][0], caps[1][0][0]  # the arms' axes' x
        assert np.isclose(c1[0] + BALL - (left_arm + RADIUS), REACH)
        assert np.isclose((right_arm - RADIUS) - (c2[0] - BALL), REACH)
        # the closest points of the two bumps are on the surface of the union, gap apart
        inner = np.array([c1 + [BALL, 0, 0], c2 - [BALL, 0, 0]])
        assert np.allclose(u_distance(inner, gap), 0.0)
        assert np.isclose(np.linalg.norm(inner[1] - inner[0]), gap)


def test_the_sample_is_on_the_surface_spacing_apart_and_covers_the_bumps():
    gap = 0.2
    pts = u_with_bumps(gap, 1)
    assert np.abs(u_distance(pts, gap)).max() < 1e-9
    tree = cKDTree(pts)
    assert tree.query(pts, k=2)[0][:, 1].min() >= SPACING
    _, (c1, c2) = u_shape(gap)
    for tip in (c1 + [BALL, 0, 0], c2 - [BALL, 0, 0]):
        assert tree.query(tip)[0] < SPACING  # thinning keeps a sample within a spacing of every point
