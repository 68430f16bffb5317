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


def _zipper(outer: np.ndarray, inner: np.ndarray, ang_o: np.ndarray, ang_i: np.ndarray) -> np.ndarray:
    """Triangles between two loops of vertex ids around one axis, taken in order of angle (a zipper)."""
    faces, p, q = [], 0, 0
    no, ni = len(outer), len(inner)
    while p < no or q < ni:
        next_o = ang_o[p % no] + 2 * np.pi * (p // no) if p < no else np.inf
        next_i = ang_i[q % ni] + 2 * np.pi * (q // ni) if q < ni else np.inf
        if next_o <= next_i:
            faces.append([outer[p % no], outer[(p + 1) % no], inner[q % ni]])
            p += 1
        else:
            faces.append([inner[q % ni], outer[p % no], inner[(q + 1) % ni]])
            q += 1
    return np.array(faces)


def test_a_band_with_a_rim_too_short_to_show_is_a_cap():
    # a 12-gon cap (radius 1: its rim 12 sides of 0.52, each sample's spacing, so 12 spacings, over LOOP_MIN)
    # around a triangle island (sides 0.5, its samples' spacing 0.3: 5 spacings, under LOOP_MIN, though
    # 1.5 long, farther than its 0.71 from the outer rim): one rim that counts, a cap, not a wall
    a = 2 * np.pi * np.arange(12) / 12
    b = 2 * np.pi * np.arange(3) / 3 + 0.3
    r = 0.5 / np.sqrt(3)
    pts = np.r_[np.c_[np.cos(a), np.sin(a), np.zeros(12)], np.c_[r * np.cos(b), r * np.sin(b), np.zeros(3)]]
    faces = np.r_[_zipper(np.arange(12), np.arange(12, 15), a, b), [[12, 13, 14]]]
    cap = np.arange(len(faces) - 1)  # all but the island's own face
    nn = np.r_[np.full(12, 2 * np.sin(np.pi / 12)), np.full(3, 0.3)]
    rims = rim_lengths(faces, cap, pts, nn)
    assert rims == pytest.approx([12.0, 5.0]) and rims[1] < LOOP_MIN <= rims[0]
    assert not is_wall(faces, cap, pts, nn)
    assert is_wall(faces, cap, pts, np.r_[nn[:12], np.full(3, 0.2)])  # the island 7.5 spacings: two rims, a wall


def test_a_band_taller_than_its_rims_are_long_is_a_tube():
    # the can's octagon rims are 8 sides of 0.765 (6.1 long): a band 3 tall is a wall, one 10 tall a tube,
    # and the bound is the rims' length: 3 % under it a wall, 3 % over it a tube
    rim = 8 * 2 * np.sin(np.pi / 8)
    for height, wall in ((3.0, True), (6.0, True), (0.97 * rim, True), (1.03 * rim, False), (10.0, False)):
        pts, faces, _, band, _ = _can(height=height)
        assert is_wall(faces, band, pts, np.full(len(pts), 2 * np.sin(np.pi / 8))) == wall


def test_a_face_on_an_edge_of_three_parts_from_the_others():
    # three triangles on one edge: without the middle one the other two still share the edge, one part
    faces = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4]])
    (only,) = pieces_without(faces, np.array([1]))
    assert sorted(only.tolist()) == [0, 2]


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


def test_a_coin_sampled_on_its_faces_is_closed_and_its_rim_named():
    # a CAD coin: two unit discs 1 apart (12.5 spacings) sampled on a grid of 0.08 and densely on their rims,
    # nothing on its side.  The labelling closes it; the side is a band between two rims 81 spacings long, a
    # wall: it stays (before session 46 open-cap opened it: two flat discs with sure holes), and is named, a
    # hole at it and a component for the disc it holds to the other, in its own rule's words
    from crustview.core import reconstruct

    s, height = 0.08, 1.0
    g = np.arange(-1, 1 + 1e-9, s)
    x, y = np.meshgrid(g, g)
    disc = np.c_[x.ravel(), y.ravel()]
    disc = disc[np.hypot(*disc.T) < 1 - s / 2]
    k = int(2 * np.pi / s)
    a = 2 * np.pi * np.arange(k) / k
    disc = np.r_[disc, np.c_[np.cos(a), np.sin(a)]]
    pts = np.r_[np.c_[disc, np.zeros(len(disc))], np.c_[disc, np.full(len(disc), height)]]
    pts = pts + np.random.default_rng(3).normal(scale=0.02 * s, size=pts.shape)
    rec = reconstruct(pts, 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 0, 1) and rec.topology.unused_samples == 0
    (hole,) = [f for f in rec.features if f.kind == "hole" and f.removed]
    (part,) = [f for f in rec.features if f.kind == "component" and f.removed]
    assert hole.uncertain and hole.reason.startswith("a wall kept closed (rule open-cap)")
    assert part.uncertain and part.reason.startswith("joined by a wall kept closed (rule open-cap)")
    assert part.size_spacings == pytest.approx(height / s, rel=0.1)


def test_caps_kept_on_either_end_of_a_solid_name_a_possible_tunnel():
    # cap_holes.facing_caps: the can's two end fans kept closed face each other through the can (the path
    # between their centres crosses no other face, and its middle is inside): one uncertain removed handle,
    # its size the path over the caps' spacing.  Two cans stacked with a gap: the lower one's top and the
    # upper one's bottom face each other across the outside: nothing
    from crustview.core.robust.cap_holes import facing_caps

    pts, faces, bottom, _, top = _can(height=3.0)
    caps = [(np.unique(faces[bottom]), 4.0), (np.unique(faces[top]), 5.0)]
    (tunnel,) = facing_caps(pts, faces, caps)
    spacing = 2 * np.sin(np.pi / 8)  # the median of the caps' samples' nearest distances: a rim's side
    assert tunnel.kind == "handle" and tunnel.uncertain and tunnel.removed
    assert tunnel.size_spacings == pytest.approx(3.0 / spacing, rel=0.05)
    assert np.allclose(tunnel.location, [0, 0, 1.5]) and "(rule open-cap" in tunnel.reason
    upper = pts + [0, 0, 5.0]
    two = np.r_[pts, upper]
    faces2 = np.r_[faces, faces + len(pts)]
    gap = [(np.unique(faces[top]), 4.0), (np.unique(faces[bottom]) + len(pts), 4.0)]
    assert facing_caps(two, faces2, gap) == []
    assert len(facing_caps(two, faces2, [caps[0], (caps[1][0] + len(pts), 5.0)])) == 0  # across the gap too
