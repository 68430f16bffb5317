"""Holes over planar rims (analysis/planar.py): a planar cut, or a flat face sampled only on its outline."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.features import Feature
from crustview.core.analysis.planar import PLANAR_RIM, flat_offset, planar_holes, rim_offset


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
    assert out[0].uncertain and "PLANAR_RIM" in out[0].reason and out[0].vertices is feats[0].vertices
    assert out[1] is feats[1] and out[2] is feats[2]
    # a rim just inside the bound is planar, one just outside is not
    for wave, planar in ((0.99 * PLANAR_RIM * math.sqrt(2), True), (1.01 * PLANAR_RIM * math.sqrt(2), False)):
        pts = _circle_rim(60, 10.0, wave)
        assert planar_holes(pts, [_hole(np.arange(60))], 1.0)[0].uncertain is planar
    # nothing to do: the same list back
    rest = feats[1:]
    assert planar_holes(points, rest, 1.0) is rest


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
        assert all("PLANAR_RIM" in f.reason for f in holes if "open-cap" not in f.reason)
    # the clean sample is the paper's own closed result: nothing to flag
    clean = reconstruct(pts, 2)
    assert clean.topology.closed_manifold and clean.topology.betti == (1, 0, 1) and not clean.uncertain_features


def test_an_open_curve_has_its_gap_as_a_hole_and_the_robust_result_calls_it_uncertain() -> None:
    """An arc of 3/4 of a circle (150 samples): the gap between its ends is measured as a hole (the ends'
    distance over their local spacing, half an edge: here 2 sin(134.1 deg) / sin(0.9 deg) = 91 radii, well above
    HOLE_SUPPORTED); the robust result is open there, and since two ends always lie on a line (a gap or a
    straight piece sampled only at its ends), it says so."""
    from crustview.core.analysis.features import HOLE_SUPPORTED, features

    t = 2 * np.pi * np.arange(150) / 200
    pts = np.c_[np.cos(t), np.sin(t)]
    path = np.c_[np.arange(149), np.arange(1, 150)]
    holes = [f for f in features(pts, path, 1) if f.kind == "hole"]
    assert len(holes) == 1 and sorted(holes[0].vertices.tolist()) == [0, 149]
    radius = np.linalg.norm(pts[1] - pts[0]) / 2  # an edge's enclosing radius: half the chord
    assert holes[0].size_spacings == pytest.approx(np.linalg.norm(pts[149] - pts[0]) / radius, rel=1e-9)
    assert holes[0].size_spacings > HOLE_SUPPORTED and not holes[0].uncertain
    # a closed curve has none; a gap of one missing sample is uncertain by its size
    assert not [f for f in features(pts, np.r_[path, [[149, 0]]], 1) if f.kind == "hole"]
    short = [f for f in features(pts[:3], np.array([[0, 1]]), 1) if f.kind == "hole"]
    assert len(short) == 1 and short[0].size_spacings == pytest.approx(2.0) and short[0].uncertain
    rec = reconstruct(pts, 1)
    gaps = [f for f in rec.features if f.kind == "hole"]
    if not rec.topology.closed_manifold:
        assert gaps and all(f.uncertain and "straight piece" in f.reason for f in gaps)
