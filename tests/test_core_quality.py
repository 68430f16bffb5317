"""Estimated sampling quality (core.quality) on cases checkable on paper."""

from __future__ import annotations

import json

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.quality import delaunay_edges, sampling_quality, summary, thresholds
from crustview.core.samples.manifolds import get_manifold


def circle(n: int, skip=None) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    if skip is not None:
        t = t[~skip(t)]
    return np.c_[np.cos(t), np.sin(t)]


@pytest.mark.parametrize("n", [12, 40, 200])
def test_even_circle_epsilon_is_tan_pi_over_n(n):
    # The cell of s = (1, 0) between neighbours at angle +-a = 2 pi / n ends along the tangent at
    # the bisector: (1 - cos a) / sin a = tan(a / 2); every Voronoi vertex is the centre, so the
    # pole distance is the radius 1.  Hence epsilon = tan(pi / n) at every sample.  The tangent is
    # Algorithm 1's estimate (all vertices coincide at the centre, so the joggle picks the pole and
    # tilts the normal slightly): the extent along a tilted line is longer by 1 / cos(tilt), < 3%.
    q = sampling_quality(reconstruct(circle(n), d=1))
    tan = np.tan(np.pi / n)
    assert np.all((q.radius > tan * (1 - 1e-4)) & (q.radius < tan * 1.03))
    assert np.allclose(q.height, 1.0, rtol=1e-3)
    assert np.all((q.epsilon > tan * (1 - 1e-3)) & (q.epsilon < tan * 1.03))


def test_dense_cells_are_long_and_thin_sparse_ones_are_not():
    dense = sampling_quality(reconstruct(circle(200), d=1))
    sparse = sampling_quality(reconstruct(circle(12), d=1))
    assert np.nanmax(dense.epsilon) < 0.02 and np.nanmin(dense.aspect) > 50
    assert np.nanmin(sparse.epsilon) > 0.25  # tan(15 deg) = 0.268: beyond the paper's bound
    assert not dense.beyond(0.25).any() and sparse.beyond(0.25).all()


def test_a_gap_flags_exactly_the_two_samples_at_its_ends():
    # 120 samples every 3 deg, those strictly inside a 40 deg arc removed: the two samples at the
    # gap's ends see a neighbour 42 deg away, tan(21 deg) = 0.38 > 0.25; all others tan(1.5 deg).
    start = 0.5
    pts = circle(120, skip=lambda t: (t > start) & (t < start + np.radians(40)))
    rec = reconstruct(pts, d=1)
    q = sampling_quality(rec)
    flagged = np.flatnonzero(q.beyond(0.25))
    ang = np.mod(np.arctan2(rec.points[:, 1], rec.points[:, 0]), 2 * np.pi)
    gap_ends = {int(np.argmax(np.where(ang <= start, ang, -1))), int(np.argmin(np.where(ang >= start, ang, 9)))}
    assert set(flagged.tolist()) == gap_ends
    others = np.delete(q.epsilon, flagged)
    assert np.allclose(others, np.tan(np.radians(1.5)), rtol=0.05)


def test_sphere_epsilon_shrinks_with_the_square_root_of_density():
    # on a unit sphere the pole distance is ~1 and the cell radius ~ spacing ~ n^(-1/2)
    m = get_manifold("sphere")
    qs = [sampling_quality(reconstruct(m.sample(n, seed=1).points, d=2)) for n in (250, 2500)]
    for q in qs:
        assert np.all(np.abs(q.height - 1.0) < 0.1)
    ratio = np.nanmedian(qs[0].epsilon) / np.nanmedian(qs[1].epsilon)
    assert 2.4 < ratio < 4.2  # sqrt(10) = 3.16
    assert not qs[1].beyond(0.25).any()


def test_summary_counts_samples_beyond_each_bound_and_is_json():
    pts = circle(120, skip=lambda t: (t > 0.5) & (t < 0.5 + np.radians(40)))
    rec = reconstruct(pts, d=1)
    s = summary(rec)
    json.dumps(s)
    assert s["beyond"] == {"theorem 2": 2, "theorems 3, 4, 10, 11": 2}
    assert s["undetermined"] == 0 and s["epsilon_max"] > 0.25 > s["epsilon_median"]


def test_thresholds_follow_the_codimension():
    assert thresholds(3, 2) == {"theorem 2": 0.25, "theorems 3, 4, 10, 11": 0.25}
    t = thresholds(5, 1)
    assert t["theorem 2"] == pytest.approx(0.0625) and t["theorems 3, 4, 10, 11"] == pytest.approx(0.125)


def test_codimension_two_curve_uses_the_nearest_pole():
    # a circle of radius 1 in R^3 (tilted, with tiny noise so the Delaunay is 3-D): the cell's
    # tangential radius is tan(pi / n) as in the plane; every Voronoi vertex lies near the circle's
    # axis (the medial axis, at distance >= 1 from every sample), so the height is >= 1 and epsilon
    # at most tan(pi / n).  (How far along the axis the poles lie depends on the noise: the height
    # overestimates the local feature size of nearly planar data in codimension 2.)
    n = 60
    p = np.c_[circle(n), np.zeros(n)] @ np.linalg.qr(np.random.default_rng(0).normal(size=(3, 3)))[0]
    p = p + 1e-3 * np.random.default_rng(1).normal(size=p.shape)
    q = sampling_quality(reconstruct(p, d=1))
    tan = np.tan(np.pi / n)
    assert np.all(np.abs(q.radius / tan - 1) < 0.05)
    assert np.all((q.height > 0.99) & (q.height < 5))
    assert np.all(q.epsilon < 1.05 * tan)


@pytest.mark.parametrize("dtype", [np.int32, np.int64])
def test_delaunay_edges_are_unique_and_sorted(dtype):
    # int32 goes through the compiled face lister, int64 through numpy
    e = delaunay_edges(np.array([[0, 1, 2], [1, 2, 3]], dtype=dtype))
    assert e.tolist() == [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]


def test_delaunay_edges_compiled_and_numpy_agree_on_a_real_triangulation(monkeypatch):
    from crustview.core.delaunay import faces

    rec = reconstruct(get_manifold("torus").sample(800, seed=3).points, 2)
    simp = rec.delaunay_simplices
    assert simp.dtype == np.int32 and faces._native is not None
    fast = delaunay_edges(simp)
    monkeypatch.setattr(faces, "_native", None)
    assert np.array_equal(fast, delaunay_edges(simp))


def test_quality_reports_progress_in_order_and_can_be_cancelled():
    import threading

    from crustview.core.analysis import quality
    from crustview.core.errors import Cancelled

    rec = reconstruct(get_manifold("torus").sample(1500, seed=1).points, 2)
    seen = []
    q = sampling_quality(rec, progress=seen.append)
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen) and len(seen) >= 4
    assert np.array_equal(q.epsilon, sampling_quality(rec).epsilon, equal_nan=True)
    stop = threading.Event()
    stop.set()
    with pytest.raises(Cancelled):
        sampling_quality(rec, cancel=stop)
    # cancelled in the middle: after the first block of the radius pass
    stop = threading.Event()
    calls = []

    def watch(f):
        calls.append(f)
        if len(calls) == 3:
            stop.set()

    old = quality.QUALITY_ROWS
    quality.QUALITY_ROWS = 1000  # many blocks
    try:
        with pytest.raises(Cancelled):
            sampling_quality(rec, progress=watch, cancel=stop)
    finally:
        quality.QUALITY_ROWS = old
    assert 3 <= len(calls) < 10
