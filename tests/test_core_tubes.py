"""A short handle loop that slides along a tube is a meridian, not a gap (:mod:`crustview.core.analysis.tubes`)."""

from __future__ import annotations

import math

import numpy as np

from crustview.core.analysis.cotree import triangle_edges
from crustview.core.analysis.features import LOOP_MIN, LOOP_SUPPORTED, features
from crustview.core.analysis.loops import short_basis
from crustview.core.analysis.tubes import SLIDE_MARGIN, slides


def _torus(big: float, small: float, nu: int, nv: int) -> tuple[np.ndarray, np.ndarray]:
    """A torus of revolution as a grid: vertex i * nv + j at angle u_i round the axis and v_j round the tube
    (v = 0 outermost, v = pi on the inner equator)."""
    u = 2 * np.pi * np.arange(nu) / nu
    v = 2 * np.pi * np.arange(nv) / nv
    uu, vv = np.meshgrid(u, v, indexing="ij")
    ring = big + small * np.cos(vv)
    pts = np.c_[(ring * np.cos(uu)).ravel(), (ring * np.sin(uu)).ravel(), (small * np.sin(vv)).ravel()]
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    tris = np.vstack([np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]])
    return pts, tris


def _slides(pts: np.ndarray, tris: np.ndarray, loop: np.ndarray) -> tuple[bool, float]:
    edges, tri_edges = triangle_edges(tris)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    cocycles: dict = {}
    short_basis(pts, tris, edges, tri_edges, count, len(pts), cocycles=cocycles, cocycles_only=True)
    return slides(pts, edges, cocycles, loop)


def test_a_thin_tubes_meridian_slides_far_under_the_lasso_bound():
    # R = 1, r = 0.1: every meridian is the same 8-gon, 0.61 long; 6 lengths away the bound 2 d + L is 13 L
    nv = 8
    pts, tris = _torus(1.0, 0.1, 80, nv)
    ok, ratio = _slides(pts, tris, np.arange(nv))  # the meridian at u = 0
    assert ok
    assert ratio < 0.1


def test_a_fat_tori_hole_rim_does_not_slide():
    # R = 1, r = 0.8: the inner equator (radius 0.2) is the short loop; the loops of its class through a point
    # d = 0.8 phi away along the tube are the circles 2 pi (1 - 0.8 cos phi) long, at least 0.85 times
    # 2 d + L for every phi (worked on paper, minimum near phi = 0): never under half the bound
    nu, nv = 10, 40
    pts, tris = _torus(1.0, 0.8, nu, nv)
    inner = np.arange(nu) * nv + nv // 2
    ok, ratio = _slides(pts, tris, inner)
    assert not ok
    assert ratio * SLIDE_MARGIN > 1.5


def test_a_tube_shorter_than_four_meridians_is_a_neck():
    # R = 1, r = 0.3: the meridian is 2 pi 0.3 = 1.9 long, and no point of the surface is more than
    # pi R = 3.1 = 1.7 meridians from it along the tube: no sample lies
    # SLIDE_AWAY = 2 meridians away, so the loop does not slide (a contact over a stretch looks like this)
    nv = 16
    pts, tris = _torus(1.0, 0.3, 40, nv)
    ok, ratio = _slides(pts, tris, np.arange(nv))
    assert not ok and math.isinf(ratio)


def test_the_same_length_in_radii_is_supported_on_a_tube_and_uncertain_round_a_hole():
    # both short loops measure between LOOP_MIN and LOOP_SUPPORTED local spacings, where the length alone
    # leaves a handle uncertain: a thin torus' meridian slides along its tube (supported); a fat torus'
    # inner equator is the rim of its hole, and the loops of its class grow away from it (uncertain)
    thin = [f for f in features(*_torus(1.0, 0.1, 80, 8), 2) if f.kind == "handle"]
    meridian = min(thin, key=lambda f: f.size_spacings)
    assert LOOP_MIN <= meridian.size_spacings < LOOP_SUPPORTED
    assert math.isclose(float(np.hypot(*meridian.location[:2])), 1.0, abs_tol=0.05)  # round the tube's core
    assert not meridian.uncertain and "tube's meridian" in meridian.reason
    fat = [f for f in features(*_torus(1.0, 0.8, 8, 24), 2) if f.kind == "handle"]
    rim = min(fat, key=lambda f: float(np.hypot(*f.location[:2])))
    assert float(np.hypot(*rim.location[:2])) < 0.05  # the inner equator, round the axis
    assert LOOP_MIN <= rim.size_spacings < LOOP_SUPPORTED
    assert rim.uncertain and "tube" not in rim.reason
