"""Holes over planar rims (analysis/planar.py): a planar cut, or a flat face sampled only on its outline."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.features import Feature
from crustview.core.analysis.planar import (
    PLANAR_MEDIAN,
    PLANAR_RIM,
    flat_offset,
    planar_holes,
    rim_offset,
    trimmed_offset,
    trimmed_plane,
)


def test_flat_offset_of_a_square_and_of_a_saddle_by_hand() -> None:
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    assert flat_offset(square, 2) == pytest.approx(0.0, abs=1e-12)
    # corners lifted +a, -a, -a, +a: z is uncorrelated with x and y, so the best plane is z = 0 (a < 1/2)
    saddle = square + np.array([[0, 0, 0.2], [0, 0, -0.2], [0, 0, -0.2], [0, 0, 0.2]])
    assert flat_offset(saddle, 2) == pytest.approx(0.2)
    # in units of the spacing
    assert rim_offset(saddle, np.arange(4), 0.1) == pytest.approx(2.0)


def _circle_rim(m: int, radius: float, wave: float) -> np.ndarray:
    t = 2 * np.pi * np.arange(m) / m
    return np.c_[radius * np.cos(t), radius * np.sin(t), wave * np.cos(3 * t)]


def _hole(vertices: np.ndarray, uncertain: bool = False) -> Feature:
    return Feature("hole", np.zeros(3), 20.0, uncertain, vertices, "hole with 60 rim edges")


def test_a_planar_rim_makes_its_hole_uncertain_and_a_wavy_one_does_not() -> None:
    # two rims of 60 samples about one spacing apart (radius 10): one in a plane, one waving 3 spacings
    # up and down (RMS 3 / sqrt 2 = 2.1 spacings off its best plane)
    flat, wavy = _circle_rim(60, 10.0, 0.0), _circle_rim(60, 10.0, 3.0) + [0, 0, 50]
    points = np.vstack([flat, wavy])
    assert rim_offset(points, np.arange(60, 120), 1.0) == pytest.approx(3 / math.sqrt(2), rel=1e-6)
    handle = Feature("handle", np.zeros(3), 30.0, False, np.arange(5), "loop")
    feats = [_hole(np.arange(60)), _hole(np.arange(60, 120)), handle]
    out = planar_holes(points, feats, 1.0)
    assert out[0].uncertain and "from a plane, within" in out[0].reason and out[0].vertices is feats[0].vertices
    assert out[1] is feats[1] and out[2] is feats[2]
    # a rim just inside the bound is planar, one just outside is not
    # a rim just inside the RMS bound is planar; one just outside it is as planar as its median distance from
    # its trimmed plane says (the second test); three times the bound is neither
    inside, outside = (
        _circle_rim(60, 10.0, 0.99 * PLANAR_RIM * math.sqrt(2)),
        _circle_rim(60, 10.0, 1.01 * PLANAR_RIM * math.sqrt(2)),
    )
    assert planar_holes(inside, [_hole(np.arange(60))], 1.0)[0].uncertain
    # the wave's median distance from its plane is its amplitude times the median of |cos|, 1 / sqrt 2: 1.01 times
    # PLANAR_RIM = 0.606, over PLANAR_MEDIAN = 0.405, so the second test does not call it planar either
    assert trimmed_offset(outside, np.arange(60), 1.0) == pytest.approx(1.01 * PLANAR_RIM, rel=0.03)
    assert not planar_holes(outside, [_hole(np.arange(60))], 1.0)[0].uncertain
    far = _circle_rim(60, 10.0, 3 * PLANAR_RIM * math.sqrt(2))
    assert trimmed_offset(far, np.arange(60), 1.0) > PLANAR_MEDIAN
    assert not planar_holes(far, [_hole(np.arange(60))], 1.0)[0].uncertain
    # nothing to do: the same list back
    rest = feats[1:]
    assert planar_holes(points, rest, 1.0) is rest


def test_a_rim_that_leaves_its_plane_on_less_than_half_its_length_is_planar_by_hand() -> None:
    """On paper: 10 samples of a rim at z = 0 and 6 at z = 5 (a flat end's rim that zigzags to the next ring
    of samples).  Off the least-squares plane they lie over 2 RMS; concentration steps from it reach z = 0,
    the plane of the nearest half, and the median distance from it is 0: planar.  With 8 and 8 alternating
    the steps stop at a tilted plane: the median distance stays about half the step, far over
    PLANAR_MEDIAN."""
    t = 2 * np.pi * np.arange(16) / 16
    up = np.isin(np.arange(16), [1, 3, 5, 9, 11, 13])  # 6 of 16
    pts = np.c_[10 * np.cos(t), 10 * np.sin(t), 5.0 * up]
    assert rim_offset(pts, np.arange(16), 1.0) > 2 * PLANAR_RIM
    centre, normal, distance = trimmed_plane(pts)
    assert abs(normal[2]) == pytest.approx(1.0) and centre[2] == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(distance, 5.0 * up)
    assert trimmed_offset(pts, np.arange(16), 1.0) == pytest.approx(0.0, abs=1e-12)
    assert trimmed_offset(pts, np.arange(16), 0.5) == pytest.approx(0.0, abs=1e-12)
    (out,) = planar_holes(pts, [_hole(np.arange(16))], 1.0)
    assert out.uncertain and "half its rim or more lies in a plane" in out.reason
    even = np.c_[pts[:, :2], 5.0 * (np.arange(16) % 2)]  # 8 and 8
    assert trimmed_offset(even, np.arange(16), 1.0) > 2.0 > PLANAR_MEDIAN
    assert not planar_holes(even, [_hole(np.arange(16))], 1.0)[0].uncertain


def test_a_closed_cylinder_whose_rings_are_five_times_apart_is_never_reported_open_for_sure() -> None:
    """Rings 5 times farther apart than the samples along them: open-cap's patch over a flat end also takes
    long faces of the wall beside it, so the hole's rim zigzags to the next ring in places (0.8-1.3 spacings
    RMS off its plane, over PLANAR_RIM: two sure holes on a closed solid before PLANAR_MEDIAN).  Half the
    rim or more still lies in the end's plane: every hole is uncertain, or the result closed."""
    pts = _turned_outline(ratio=5.0)
    h = float(np.median(np.linalg.norm(pts[1:97] - pts[:96], axis=1)))
    for level in (0.1, 0.3):
        rec = reconstruct(pts + np.random.default_rng(1).normal(scale=level * h, size=pts.shape), 2)
        holes = [f for f in rec.features if f.kind == "hole" and not f.removed and not f.disputed]
        if rec.topology.closed_manifold:
            assert rec.topology.betti == (1, 0, 1)
        else:
            assert holes and all(f.uncertain for f in holes), [f.reason for f in holes]


def _turned_outline(around: int = 96, ratio: float = 1.5) -> np.ndarray:
    """A closed cylinder (radius 0.8, height 2) sampled as CAD tools tessellate it: rings only, none on its ends."""
    step = ratio * 2 * np.pi * 0.8 / around
    rings = int(round(2.0 / step)) + 1
    out = []
    for i, z in enumerate(np.linspace(0.0, 2.0, rings)):
        a = 2 * np.pi * np.arange(around) / around + (np.pi / around) * (i % 2)
        out.append(np.c_[0.8 * np.cos(a), 0.8 * np.sin(a), np.full(around, z)])
    return np.vstack(out)


def test_a_closed_cylinder_sampled_on_its_rings_is_never_reported_open_for_sure() -> None:
    """Its flat ends have no sample inside their outlines.  Under noise of 0.1 h the robust extraction
    opens them (open-cap: caps 17 times the faces around them); before this rule the result was an open
    tube with two sure holes, a closed solid shown as a sure open surface.  Each hole must now be
    uncertain, or the result closed."""
    pts = _turned_outline()
    h = float(np.median(np.linalg.norm(pts[1:97] - pts[:96], axis=1)))
    noisy = pts + np.random.default_rng(1).normal(scale=0.1 * h, size=pts.shape)
    rec = reconstruct(noisy, 2)
    holes = [f for f in rec.features if f.kind == "hole" and not f.removed and not f.disputed]
    if rec.topology.closed_manifold:
        assert rec.topology.betti == (1, 0, 1)
    else:
        assert holes and all(f.uncertain for f in holes)
        assert all("from a plane, within" in f.reason for f in holes if "open-cap" not in f.reason)
    # the clean sample is the paper's own closed result, unchanged; since session 35 its two flat ends, caps
    # over no sample, are named as possible openings (robust/closed_caps.py): the other side of the same
    # ambiguity (a flat face sampled on its outline, or an opening), never a sure answer either way
    clean = reconstruct(pts, 2)
    assert clean.topology.closed_manifold and clean.topology.betti == (1, 0, 1)
    ends = clean.uncertain_features
    assert len(ends) == 2 and all(f.kind == "hole" and f.removed and "possible opening" in f.reason for f in ends)
    assert sorted(round(float(f.location[2])) for f in ends) == [0, 2]  # one at each end (z = 0 and z = 2)


def test_a_curves_gaps_pair_the_ends_that_face_each_other() -> None:
    """curve_gaps, on paper: a 60-sample circle missing samples 0 and 30 is two arcs with two gaps of one
    sample each (two edges long: 4 radii, at HOLE_SUPPORTED, uncertain), each at its missing sample, not the
    arcs' own chords across the circle; an arc is one gap between its ends; a branch point is left out."""
    from crustview.core.analysis.features import HOLE_SUPPORTED
    from crustview.core.analysis.gaps import curve_gaps

    t = 2 * np.pi * np.arange(60) / 60
    pts = np.c_[np.cos(t), np.sin(t)]
    path = np.array([[i, (i + 1) % 60] for i in range(60) if i not in (0, 59, 29, 30)])
    gaps = curve_gaps(pts, path)
    assert len(gaps) == 2 and sorted(sorted(g.vertices.tolist()) for g in gaps) == [[1, 59], [29, 31]]
    radius = np.linalg.norm(pts[1] - pts[0]) / 2
    for g in gaps:
        a, b = pts[g.vertices]
        assert g.size_spacings == pytest.approx(np.linalg.norm(a - b) / radius, rel=1e-9)
        assert g.size_spacings == pytest.approx(HOLE_SUPPORTED, rel=0.01) and g.uncertain
        assert np.linalg.norm(g.location) > 0.99  # at the missing sample, on the circle
    # a three-quarter arc: one gap, between its two ends, far above the bound
    arc = np.array([[i, i + 1] for i in range(44)])
    (one,) = curve_gaps(pts, arc)
    assert sorted(one.vertices.tolist()) == [0, 44] and one.size_spacings > 5 * HOLE_SUPPORTED and not one.uncertain
    # a closed curve has none; a circle with a whisker (a branch point) is not a path: none either
    assert curve_gaps(pts, np.array([[i, (i + 1) % 60] for i in range(60)])) == []
    whisker = np.vstack([pts, [[1.2, 0.0]]])
    assert curve_gaps(whisker, np.array([[i, (i + 1) % 60] for i in range(60)] + [[0, 60]])) == []


def test_an_open_curve_in_the_plane_is_flagged_by_its_gap_in_robust_mode_only() -> None:
    """A half circle of 80 samples stays open in both modes.  The robust report measures its gap and calls
    it uncertain (two ends lie on a line: a gap or a straight piece); the paper mode's report is as before,
    with no hole feature."""
    t = np.linspace(0, np.pi, 80)
    pts = np.c_[np.cos(t), np.sin(t)]
    rec = reconstruct(pts, 1)
    assert not rec.topology.closed_manifold and rec.topology.betti == (1, 0)
    gaps = [f for f in rec.features if f.kind == "hole"]
    assert len(gaps) == 1 and np.allclose(sorted(rec.points[gaps[0].vertices].tolist()), [[-1.0, 0.0], [1.0, 0.0]])
    assert gaps[0].uncertain and "straight piece" in gaps[0].reason
    assert np.allclose(gaps[0].location, [0.0, 0.0], atol=1e-9)  # midway between the ends, as scaled back
    paper = reconstruct(pts, 1, mode="paper", prune_boundary=False)
    assert not [f for f in paper.features if f.kind == "hole"]


def test_a_hole_in_a_flat_sheet_stays_sure() -> None:
    """A 30 x 30 sheet with a bump in the middle and a flat margin, noise 0.1 spacing: its one boundary is
    planar, but the sheet itself runs through the disc a flat face would fill, so it is no unsampled flat
    face and the hole stays sure; the same rim with nothing inside (the vase's base) is flagged."""
    from crustview.core.analysis.planar import surface_in_disc

    rng = np.random.default_rng(3)
    g = np.stack(np.meshgrid(np.arange(30.0), np.arange(30.0)), -1).reshape(-1, 2)
    g[:, 0] += 0.5 * (np.arange(len(g)) // 30 % 2)
    z = 6.0 * np.exp(-((g[:, 0] - 15) ** 2 + (g[:, 1] - 15) ** 2) / 40.0)
    pts = np.c_[g, z] + rng.normal(scale=0.1, size=(len(g), 3))
    rec = reconstruct(pts, 2)
    (hole,) = [f for f in rec.features if f.kind == "hole"]
    assert rim_offset(rec.points, hole.vertices, rec.spacing) <= PLANAR_RIM and not hole.uncertain
    assert surface_in_disc(rec.points, hole.vertices, rec.spacing) > 100


def test_surface_in_disc_counts_a_sheet_inside_the_rim_not_samples_outside_it_or_on_other_rims() -> None:
    """On paper: a rim of 60 samples on a circle of radius 10 in z = 0 (spacing about 1); a 5 x 5 grid at
    its middle lies in its disc (25), a ring of radius 20 in the same plane lies outside its hull (0), and
    a ring of radius 4 counts as a surface only when it is no other hole's rim and M_S lies flat there."""
    from crustview.core.analysis.planar import surface_in_disc

    rim = _circle_rim(60, 10.0, 0.0)
    grid = np.c_[np.stack(np.meshgrid(np.arange(5.0) - 2, np.arange(5.0) - 2), -1).reshape(-1, 2), np.zeros(25)]
    outer = _circle_rim(120, 20.0, 0.0)
    inner = _circle_rim(24, 4.0, 0.0)
    pts = np.vstack([rim, grid, outer, inner])
    ids = np.arange(60)
    assert surface_in_disc(pts[:85], ids, 1.0) == 25
    assert surface_in_disc(np.vstack([rim, outer]), ids, 1.0) == 0  # in the plane, but outside the rim's hull
    ring = np.arange(205, 229)
    assert surface_in_disc(pts, ids, 1.0) == 25 + 24
    assert surface_in_disc(pts, ids, 1.0, boundary=ring) == 25  # the inner ring is a rim of M_S
    # M_S running up from the inner ring (a tube's wall): the ring's samples do not lie flat in the disc
    up = np.vstack([pts, inner + [0, 0, 3.0]])
    wall = np.array([[205 + i, 205 + (i + 1) % 24, 229 + i] for i in range(24)])
    assert surface_in_disc(up, ids, 1.0, simplices=wall) == 0


def _tube_outline(around: int = 96, ratio: float = 1.5) -> np.ndarray:
    """A thick-walled tube (radii 0.8 and 0.3, height 2) sampled on rings only: its flat annular ends have
    samples on their two circles and none between."""
    out = []
    for rad in (0.8, 0.3):
        step = ratio * 2 * np.pi * rad / around
        for i, z in enumerate(np.linspace(0.0, 2.0, int(round(2.0 / step)) + 1)):
            a = 2 * np.pi * np.arange(around) / around + (np.pi / around) * (i % 2)
            out.append(np.c_[rad * np.cos(a), rad * np.sin(a), np.full(around, z)])
    return np.vstack(out)


def test_a_tube_with_flat_annular_ends_sampled_on_their_circles_has_no_sure_hole() -> None:
    """The inner circle of an annular end lies in the outer rim's disc, but it is the other edge of the same
    flat face, not a surface across it (a review found the outer holes sure).  Since session 46 each end is a
    wall to ``open-cap`` (walls.py: a patch between two rims the sample shows, not a cap over one opening): the
    solid stays closed, genus 1 as it is, and each end is named as a possible opening (uncertain, removed).
    Before, both ends were opened: four uncertain holes on an open result."""
    pts = _tube_outline()
    h = float(np.median(np.linalg.norm(pts[1:96] - pts[:95], axis=1)))
    rec = reconstruct(pts + np.random.default_rng(1).normal(scale=0.1 * h, size=pts.shape), 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 2, 1) and rec.topology.unused_samples == 0
    assert not [f for f in rec.features if f.kind == "hole" and not f.removed and not f.uncertain]  # no sure hole
    ends = [f for f in rec.features if f.kind == "hole" and f.removed and "wall kept closed" in f.reason]
    assert len(ends) == 2 and all(f.uncertain for f in ends)
    assert sorted(round(float(f.location[2])) for f in ends) == [0, 2]  # one at each end of the tube


def test_curve_gaps_pair_every_end_and_survive_duplicate_ends() -> None:
    """A half circle of 40 samples and four two-sample fragments near its chord: the fragments' ends take
    each other's nearest places, and the arc's own gap (its two far ends) is still found (a review found it
    dropped when each end looked only at its 8 nearest).  Two coincident ends pair at distance 0."""
    from crustview.core.analysis.gaps import curve_gaps

    t = np.linspace(0, np.pi, 40)
    frag = np.array([[0, 0.3], [0.02, 0.3], [0, 0.35], [0.02, 0.35], [0, 0.4], [0.02, 0.4], [0, 0.45], [0.02, 0.45]])
    pts = np.r_[np.c_[np.cos(t), np.sin(t)], frag]
    edges = np.r_[np.c_[np.arange(39), np.arange(1, 40)], np.arange(40, 48).reshape(4, 2)]
    gaps = curve_gaps(pts, edges)
    assert len(gaps) == 5 and [0, 39] in [sorted(g.vertices.tolist()) for g in gaps]
    # two paths whose facing ends coincide (a duplicate point): one gap of size 0, uncertain, no endless search
    two = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    (dup,) = [g for g in curve_gaps(two, np.array([[0, 1], [2, 3]])) if sorted(g.vertices.tolist()) == [1, 2]]
    assert dup.size_spacings == 0.0 and dup.uncertain


def test_one_missing_sample_on_a_line_is_an_uncertain_gap_whatever_the_step() -> None:
    """Two edges over half an edge is 4 radii, HOLE_SUPPORTED itself: at the bound, uncertain, for any step
    (a review found 0.1 sure and 0.3 uncertain by rounding)."""
    from crustview.core.analysis.gaps import curve_gaps

    for step in (0.1, 0.3, 1.0):
        pts = np.c_[step * np.r_[np.arange(5), np.arange(6, 11)], np.zeros(10)]
        gaps = curve_gaps(pts, np.array([[i, i + 1] for i in (0, 1, 2, 3, 5, 6, 7, 8)]))
        # the facing ends 4 and 5, then the two far ends (the pieces' other gap, 10 steps: sure)
        (gap,) = [g for g in gaps if sorted(g.vertices.tolist()) == [4, 5]]
        assert len(gaps) == 2 and gap.uncertain and gap.size_spacings == pytest.approx(4.0)


def test_a_space_curves_gap_is_uncertain_too() -> None:
    """Half a helix in R^3: open in the robust result, its gap a straight piece or a gap as in the plane."""
    t = np.linspace(0, 3 * np.pi, 150)
    rec = reconstruct(np.c_[np.cos(t), np.sin(t), 0.3 * t], 1)
    gaps = [f for f in rec.features if f.kind == "hole"]
    assert not rec.topology.closed_manifold and len(gaps) == 1 and gaps[0].uncertain
    assert "straight piece" in gaps[0].reason


def test_an_open_curve_is_called_a_curve_in_the_verdict() -> None:
    from crustview.scene.describe import verdict

    t = np.linspace(0, np.pi, 80)
    level, words = verdict(reconstruct(np.c_[np.cos(t), np.sin(t)], 1))
    assert level == "warn" and words.startswith("M_S is an open curve through every sample (1 hole")
    assert "uncertain: 0 handles, 1 hole, 0 components" in words
