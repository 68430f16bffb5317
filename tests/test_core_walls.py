"""open-cap's walls (core/robust/walls.py): patches between two rims the sample shows, on hand-made meshes."""

import numpy as np
import pytest

from crustview.core.analysis.features import LOOP_MIN
from crustview.core.robust.walls import is_wall, kept_walls, pieces_without, rim_lengths


def _can(k: int = 8, height: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A closed can: two octagons (radius 1, z = 0 and ``height``) fanned from their centres, and the band of
    side faces between them.  Returns points, faces, and the rows of the bottom fan, the band and the top fan."""
    a = 2 * np.pi * np.arange(k) / k
    ring = np.c_[np.cos(a), np.sin(a)]
    pts = np.r_[np.c_[ring, np.zeros(k)], np.c_[ring, np.full(k, height)], [[0, 0, 0], [0, 0, height]]]
    nxt = (np.arange(k) + 1) % k
    bottom = np.c_[np.full(k, 2 * k), nxt, np.arange(k)]
    top = np.c_[np.full(k, 2 * k + 1), k + np.arange(k), k + nxt]
    band = np.r_[np.c_[np.arange(k), nxt, k + nxt], np.c_[np.arange(k), k + nxt, k + np.arange(k)]]
    faces = np.r_[bottom, band, top]
    rows = np.arange(len(faces))
    return pts, faces, rows[:k], rows[k : 3 * k], rows[3 * k :]


def test_rims_are_measured_in_their_own_spacing():
    # each rim is an octagon of radius 1: 8 sides of 2 sin(pi / 8); its samples' nearest neighbour is a side
    # (0.765, the height 1 is farther), so each rim is 8 spacings long.  A fan has one rim, the band two.
    pts, faces, bottom, band, top = _can()
    nn = np.full(len(pts), 2 * np.sin(np.pi / 8))
    assert rim_lengths(faces, band, pts, nn) == pytest.approx([8.0, 8.0])
    assert rim_lengths(faces, bottom, pts, nn) == pytest.approx([8.0])
    assert 8.0 >= LOOP_MIN  # 2 pi: the band's rims are loops a sample shows
    assert is_wall(faces, band, pts, nn) and not is_wall(faces, bottom, pts, nn)
    assert not is_wall(faces, np.r_[bottom, band], pts, nn)  # a fan and the band: a cup, one rim


def test_a_band_with_a_rim_too_short_to_show_is_a_cap():
    # a hexagon cap around a triangle island (the island's own face left out of the patch): the inner rim,
    # three sides of 0.1 over a spacing of 0.1, is 3 spacings, under LOOP_MIN: one rim that counts, a cap
    a = 2 * np.pi * np.arange(6) / 6
    b = 2 * np.pi * np.arange(3) / 3 + 0.3
    pts = np.r_[np.c_[np.cos(a), np.sin(a), np.zeros(6)], np.c_[0.0577 * np.cos(b), 0.0577 * np.sin(b), np.zeros(3)]]
    faces = np.array(
        [[0, 1, 6], [1, 2, 6], [2, 7, 6], [2, 3, 7], [3, 4, 7], [4, 8, 7], [4, 5, 8], [5, 0, 8], [0, 6, 8], [6, 7, 8]]
    )
    cap = np.arange(9)  # all but the island [6, 7, 8]
    nn = np.r_[np.full(6, 1.0), np.full(3, 0.1)]
    rims = rim_lengths(faces, cap, pts, nn)
    assert len(rims) == 2 and rims[1] == pytest.approx(3 * 0.0577 * np.sqrt(3) / 0.1, rel=1e-2) and rims[1] < LOOP_MIN
    assert not is_wall(faces, cap, pts, nn)


def test_a_wall_kept_names_a_hole_and_the_part_it_joins():
    # the can's band kept closed: an uncertain removed hole at it, and, since without it the two fans fall
    # apart, an uncertain removed component at the smaller part, its gap the can's height over the spacing
    pts, faces, bottom, band, top = _can(height=3.0)
    parts = pieces_without(faces, band)
    assert sorted(map(sorted, (p.tolist() for p in parts))) == [sorted(bottom.tolist()), sorted(top.tolist())]
    assert len(pieces_without(faces, bottom)) == 1  # a fan off a can leaves a cup: one part
    feats = kept_walls(pts, faces, [(band, np.unique(faces[band]), 9.0)])
    hole, part = sorted(feats, key=lambda f: f.kind != "hole")
    assert hole.kind == "hole" and hole.uncertain and hole.removed and "wall kept closed" in hole.reason
    assert part.kind == "component" and part.uncertain and part.removed
    spacing = float(np.median(np.r_[np.full(8, 2 * np.sin(np.pi / 8)), 1.0]))  # the fan's samples' nn distances
    assert part.size_spacings == pytest.approx(3.0 / spacing, rel=0.05)
