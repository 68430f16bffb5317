"""Rule resample-check: a handle just above the resolution bound must survive losing a tenth of the samples.

Tiny cases checkable on paper drive the decision with a hand-made resample; the real cases run the
whole pipeline: a real scan's real handles survive, and so the check leaves them sure.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.features import LOOP_SUPPORTED, Feature
from crustview.core.analysis.resample import LOOP_CHECKED, RESAMPLE_KEEP, checked, resample_check
from crustview.io import read_mesh

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def _ring(centre, radius, m=12):
    t = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return np.c_[radius * np.cos(t), radius * np.sin(t), np.zeros(m)] + np.asarray(centre, float)


def _handle(points, rows, size):
    return Feature("handle", points[rows].mean(axis=0), size, False, np.asarray(rows), f"loop of {size}")


@pytest.fixture()
def two_loops():
    """Two loops of radius 1 around (0, 0, 0) and (10, 0, 0): one in the checked band, one above it."""
    pts = np.vstack([_ring((0, 0, 0), 1.0), _ring((10, 0, 0), 1.0)])
    feats = [_handle(pts, np.arange(12), 13.0), _handle(pts, np.arange(12, 24), 40.0)]
    return pts, feats


def test_only_sure_handles_in_the_band_are_checked(two_loops):
    pts, feats = two_loops
    below = Feature("handle", pts[0], 0.9 * LOOP_SUPPORTED, True, np.arange(3), "uncertain already")
    removed = Feature("handle", pts[0], 5.0, False, np.arange(3), "cut", removed=True)
    assert LOOP_CHECKED == 2 * LOOP_SUPPORTED == 8 * math.pi
    assert checked([*feats, below, removed]) == [0]


def test_a_handle_the_resample_does_not_show_becomes_uncertain(two_loops):
    pts, feats = two_loops
    seen = []

    def run(sub):
        seen.append(len(sub))
        # the resample keeps the far loop only: b1 drops from 4 to 2
        return (1, 2, 1), True, [_handle(pts, np.arange(12, 24), 38.0)], pts

    out, said = resample_check(pts, feats, (1, 4, 1), run)
    assert 0.7 * len(pts) < seen[0] < len(pts)  # about RESAMPLE_KEEP of them, never all
    assert out[0].uncertain and "resample-check" in out[0].reason
    assert out[1] == feats[1] and not feats[0].uncertain  # the other untouched, the input list unchanged
    assert said.endswith("has b1 = 2 where this one has 4: 1 of these loops is not there, made uncertain")


def test_a_handle_the_resample_shows_nearby_stays_sure(two_loops):
    pts, feats = two_loops
    moved = _ring((0.8, 0.5, 0), 1.1)  # the same tube's meridian, moved along it: centroids 0.94 apart

    def run(sub):
        return (1, 2, 1), True, [_handle(moved, np.arange(12), 14.0)], moved

    out, said = resample_check(pts, feats, (1, 4, 1), run)
    assert out == feats and said.endswith("has b1 = 2 where this one has 4: each of these loops is there too, kept")


@pytest.mark.parametrize("answer", [((1, 4, 0), False), ((1, 4, 1), True), ((1, 6, 1), True)])
def test_a_resample_that_is_open_or_has_as_many_handles_says_nothing(two_loops, answer):
    pts, feats = two_loops
    betti, closed = answer
    out, said = resample_check(pts, feats, (1, 4, 1), lambda sub: (betti, closed, [], pts))
    assert out == feats and said.endswith("kept")


def test_on_an_open_surface_handle_loops_are_counted_not_b1(two_loops):
    """An open M_S: its b1 counts its holes too.  A resample with a hole fewer and the same handle loops keeps
    them (b1 3 against 5 would read as a lost handle); one without fins with the near loop gone makes that
    loop uncertain; one with fins, or whose loops were too many to list, says nothing."""
    pts, feats = two_loops
    hole = Feature("hole", pts[0], 30.0, False, np.arange(3), "a rim")
    open_feats = [*feats, hole]
    same = [_handle(pts, np.arange(12), 13.5), _handle(pts, np.arange(12, 24), 40.0)]
    out, said = resample_check(pts, open_feats, (1, 5, 0), lambda sub: ((1, 3, 0), True, same, pts), closed=False)
    assert out == open_feats and said.endswith("gives 2 handle loops: kept")
    far_only = [_handle(pts, np.arange(12, 24), 40.0)]
    out, said = resample_check(pts, open_feats, (1, 5, 0), lambda sub: ((1, 3, 0), True, far_only, pts), closed=False)
    assert out[0].uncertain and "resample-check" in out[0].reason and out[1:] == open_feats[1:]
    assert said.endswith("has 1 handle loops where this one has 2: 1 of these loops is not there, made uncertain")
    out, said = resample_check(pts, open_feats, (1, 5, 0), lambda sub: ((1, 3, 0), False, far_only, pts), closed=False)
    assert out == open_feats and said.endswith("gives a surface with fins: kept")
    stand_in = [Feature("handle", pts[0], 0.0, True, np.arange(0), "too many loops to list")]
    out, said = resample_check(pts, open_feats, (1, 5, 0), lambda sub: ((1, 400, 0), True, stand_in, pts), closed=False)
    assert out == open_feats and said.endswith("too many loops to count in the reconstruction of 90%: kept")


def test_an_open_scans_false_bridge_is_checked_too():
    """The elephant (genus 0) with a hole cut into it (5 % of its vertices, ``benchmarks/bench_reshaped.py
    --opened 0.05 --seed 43``) and noise of 0.1 h (``../shared/tools/noisy.py``, draw 43): the result keeps the
    hole open but has a false handle: one loop of 20.6 sampling radii, in the checked band, the other of 26,
    above it (not checked, still sure).  Before the check ran on open surfaces both were reported sure: an
    open genus-1 elephant with nothing said."""
    rec = reconstruct(np.loadtxt(RESOURCES / "elephant-open05-n10.xyz"), 2)
    top = rec.topology
    assert not top.closed_manifold and top.nonmanifold_faces == 0 and top.boundary_faces > 0
    handles = [f for f in rec.features if f.kind == "handle" and not f.removed]
    assert handles  # the false bridge this test is about (the elephant has none)
    checked_now = [f for f in handles if "resample-check" in f.reason]
    assert checked_now and all(f.uncertain and f.size_spacings < LOOP_CHECKED for f in checked_now)
    assert any(f.kind == "handle" for f in rec.uncertain_features)
    assert any(m.startswith("resample-check") for m in top.messages)


def test_nothing_to_check_runs_nothing(two_loops):
    pts, feats = two_loops

    def run(sub):
        raise AssertionError("no handle in the band: the resample must not run")

    out, said = resample_check(pts, feats[1:], (1, 2, 1), run)
    assert out == feats[1:] and said is None


def test_real_handles_survive_the_resample():
    """fertility (genus 4): two of its handle loops lie in the checked band (12.7 and 16.8 radii); the
    reconstruction of 90 % of its samples has them too, so the result stays closed genus 4 with no doubt."""
    rec = reconstruct(read_mesh(RESOURCES / "fertility.off").points, 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 8, 1)
    band = [f for f in rec.features if f.kind == "handle" and LOOP_SUPPORTED <= f.size_spacings < LOOP_CHECKED]
    assert band  # the case this test is about
    assert not rec.uncertain_features
    assert any(m.startswith("resample-check") and f"{RESAMPLE_KEEP:.0%}" in m for m in rec.topology.messages)


def test_the_check_is_skipped_on_request_and_in_paper_mode():
    pts = read_mesh(RESOURCES / "fertility.off").points
    for rec in (reconstruct(pts, 2, resample=False), reconstruct(pts, 2, mode="paper")):
        assert not any(m.startswith("resample-check") for m in rec.topology.messages)


def test_a_sparse_sample_of_a_high_genus_object_is_never_a_sure_wrong_answer():
    """A random half of the seahorse's vertices (``resources/seahorse-half.xyz``: numpy's draw 7 keeping
    each of the 20,494 with probability 1/2; genus 8, its real handles at the resolution limit).  Every
    result is either the closed genus-8 surface through every sample, or says it may be wrong.  (A
    resample-based rule that made a removal sure where the 90 % resample did not form the handle failed
    here: the real 8.3-radius handle it removed is not formed by the sparser resample either.)"""
    pts = np.loadtxt(RESOURCES / "seahorse-half.xyz")
    rec = reconstruct(pts, 2)
    top = rec.topology
    right = top.closed_manifold and top.betti == (1, 16, 1) and top.unused_samples == 0
    # a wrong answer names the kind that is wrong (as bench_scans judges: an open result of a closed truth
    # still names its handles when b1 is wrong)
    kinds = {f.kind for f in rec.uncertain_features}
    assert right or rec.uncertain_features
    assert top.betti[1] == 16 or "handle" in kinds
    assert top.betti[0] == 1 or "component" in kinds
    assert top.closed_manifold or "hole" in kinds or top.boundary_faces == 0


def test_the_resampled_complex_comes_back_on_the_rows_it_was_given():
    """resample_betti compares the resample's M_S with the result's on the same samples: the rerun numbers its
    samples its own way (spatially sorted), so its M_S must come back on the rows of the subset it was given.
    Until session 37 the rerun's own order came back, never matched, and the two complexes were not compared."""
    from crustview.core.samples.manifolds import get_manifold
    from crustview.core.uncertainty import _resampled_complex

    s = get_manifold("sphere").sample(400, seed=2).points
    rec = reconstruct(s, 2)
    sub = s[np.random.default_rng(0).permutation(len(s))[:300]]  # an order of its own
    betti, closed, simplices = _resampled_complex(sub, rec, rec.test, rec.theta, None, lambda *a: None)
    assert closed and tuple(betti) == (1, 0, 1)
    edges = np.linalg.norm(sub[simplices] - sub[np.roll(simplices, 1, axis=1)], axis=2)
    assert edges.max() < 0.6  # faces of nearby samples (a spacing is about 0.18 here), not of shuffled rows
