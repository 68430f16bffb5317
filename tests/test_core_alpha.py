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
    assert loops.shape == (1, 4)
    assert loops[0, 0] == pytest.approx(half_side)
    assert loops[0, 1] == pytest.approx(1.0)
    assert ladder.loop_samples([0])[0].tolist() == [0, 1, 2, 3, 4]  # the region: the fan, all five
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


def _raster_b1(points: np.ndarray, r: float, cell: float) -> int:
    """b1 of the union of discs of radius r, counted on a raster: the bounded components of the complement."""
    from scipy import ndimage

    lo, hi = points.min(axis=0) - r - 2 * cell, points.max(axis=0) + r + 2 * cell
    xs, ys = np.arange(lo[0], hi[0], cell), np.arange(lo[1], hi[1], cell)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    grid = np.c_[gx.ravel(), gy.ravel()]
    from scipy.spatial import cKDTree

    covered = (cKDTree(points).query(grid)[0] <= r).reshape(gx.shape)
    labels, count = ndimage.label(~covered)  # 4-connected complement
    outside = set(np.unique(np.r_[labels[0], labels[-1], labels[:, 0], labels[:, -1]]).tolist()) - {0}
    return count - len(outside)


def test_plane_persistence_counts_the_holes_of_the_union_of_discs() -> None:
    # an independent count: the union of discs drawn on a fine raster, its enclosed holes labelled
    rng = np.random.default_rng(3)
    t = rng.uniform(0, 2 * np.pi, 24)
    pts = np.vstack([np.c_[np.cos(t), np.sin(t)], np.c_[3 + 0.6 * np.cos(t[:14]), 0.6 * np.sin(t[:14])]])
    pts += rng.normal(scale=0.05, size=pts.shape)
    ladder = AlphaLadder(pts)
    loops = ladder.loops()
    # where edges and triangles enter, and where two discs touch (an attached edge's half length)
    e = ladder.faces[1]
    half = np.linalg.norm(pts[e[:, 0]] - pts[e[:, 1]], axis=1) / 2
    values = np.r_[np.sqrt(np.r_[ladder.levels[1], ladder.levels[2]]), half]
    tried = 0
    for r in np.arange(0.05, 1.0, 0.03):
        if np.abs(values - r).min() < 0.01:  # a simplex enters too close to r for a raster to tell
            continue
        if tried == 4:
            break
        coarse, fine = _raster_b1(pts, r, 0.008), _raster_b1(pts, r, 0.004)
        if coarse != fine:  # a pocket near the raster's cell size: the raster cannot tell
            continue
        tried += 1
        alive = int(((loops[:, 0] <= r) & (loops[:, 1] > r)).sum())
        assert alive == fine == ladder.betti(r)[1], r
    assert tried == 4


def test_a_cycles_region_is_everything_it_bounds_at_birth() -> None:
    # two nested circles, unevenly sampled: the outer cycle's region holds the ring, less the inner disc
    t_in, t_out = 2 * np.pi * np.arange(20) / 20, 2 * np.pi * (np.arange(200) + 0.5) / 200
    pts = np.vstack([0.5 * np.c_[np.cos(t_in), np.sin(t_in)], np.c_[np.cos(t_out), np.sin(t_out)]])
    ladder = AlphaLadder(pts)
    loops = ladder.loops()
    keep = np.flatnonzero(loops[:, 1] >= 2 * loops[:, 0])
    assert len(keep) == 2
    regions = ladder.loop_samples(keep)
    inner = min(regions, key=len)
    ring = max(regions, key=len)
    assert set(inner.tolist()) == set(range(20))  # the disc: the inner circle's samples
    assert set(ring.tolist()) == set(range(220))  # the ring: both circles' samples


def test_the_loops_need_points_in_the_plane() -> None:
    with pytest.raises(ValueError):
        AlphaLadder(np.random.default_rng(0).normal(size=(20, 3))).loops()
