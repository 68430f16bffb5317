"""The alpha filtration's Betti numbers and the plane's cycle persistence (core.analysis.alpha)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crustview.core.analysis.alpha import AlphaLadder


def _pentagon() -> np.ndarray:
    t = 2 * np.pi * np.arange(5) / 5
    return np.c_[np.cos(t), np.sin(t)]


def test_the_regular_pentagon_has_one_cycle_from_half_its_side_to_its_circumradius() -> None:
    # on paper: the sides (2 sin 36 deg) are Gabriel and enter at half their length; each diagonal has
    # the vertex between its ends inside its diametral circle, so it enters with its triangle, and
    # every triangle of the fan is inscribed in the unit circle
    ladder = AlphaLadder(_pentagon())
    half_side = math.sin(math.radians(36))
    loops = ladder.loops()
    assert loops.shape == (1, 5)
    assert loops[0, 0] == pytest.approx(half_side)
    assert loops[0, 1] == pytest.approx(1.0)
    assert loops[0, 4] == 3  # the region the cycle bounds: the fan's three triangles
    assert ladder.betti(0.99 * half_side) == (5, 0)
    assert ladder.betti(0.5 * (half_side + 1)) == (1, 1)
    assert ladder.betti(1.01) == (1, 0)


def test_an_obtuse_triangle_enters_with_its_longest_edge() -> None:
    # the longest edge's diametral circle holds the obtuse vertex: attached, it takes the triangle's value
    pts = np.array([[0.0, 0.0], [4.0, 0.0], [2.0, 0.5]])
    ladder = AlphaLadder(pts)
    r = (2.0**2 + 0.5**2) / (2 * 0.5)  # circumradius of an isosceles triangle of half-base 2, height 0.5
    assert ladder.betti(r * 0.999) == (1, 0)  # the two short edges join it; no cycle without the long one
    assert len(ladder.loops()) == 0  # the long edge never closes a cycle on its own


def test_a_sampled_circle_in_space_has_one_cycle_and_a_sampled_sphere_one_void() -> None:
    t = 2 * np.pi * np.arange(60) / 60
    circle = np.c_[np.cos(t), np.sin(t), 0.01 * np.sin(3 * t)]  # off the plane: a full 3D triangulation
    spacing = 2 * np.pi / 60
    assert AlphaLadder(circle).betti(spacing) == (1, 1, 0)
    rng = np.random.default_rng(0)
    g = rng.normal(size=(800, 3))
    sphere = g / np.linalg.norm(g, axis=1)[:, None]
    b = AlphaLadder(sphere).betti(0.25)
    assert b == (1, 0, 1)
    assert AlphaLadder(sphere).betti(1.5) == (1, 0, 0)


def test_plane_persistence_agrees_with_the_euler_count_at_every_scale() -> None:
    # two noisy circles: b1 from the pairs alive at r equals b0 - chi at every r
    rng = np.random.default_rng(3)
    t = rng.uniform(0, 2 * np.pi, 150)
    pts = np.vstack([np.c_[np.cos(t), np.sin(t)], np.c_[3 + np.cos(t), np.sin(t)]])
    pts += rng.normal(scale=0.02, size=pts.shape)
    ladder = AlphaLadder(pts)
    loops = ladder.loops()
    for r in np.geomspace(0.005, 2.0, 40):
        alive = int(((loops[:, 0] <= r) & (loops[:, 1] > r)).sum())
        assert ladder.betti(r)[1] == alive


def test_the_loops_need_points_in_the_plane() -> None:
    with pytest.raises(ValueError):
        AlphaLadder(np.random.default_rng(0).normal(size=(20, 3))).loops()
