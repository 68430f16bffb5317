"""Rule tour-curve: noisy plane curves split by their persistent cycles and closed by short tours."""

from __future__ import annotations

import numpy as np

from crustview.core import reconstruct
from crustview.core.robust.tour_curve import curve_groups, short_tour
from crustview.core.samples.manifolds import get_manifold


def _noisy_ellipse(seed: int) -> np.ndarray:
    """bench_variants' 'noise 1 % size' variant of the ellipse, with sample seed ``seed``."""
    m = get_manifold("ellipse")
    base = m.sample(m.default_n, seed=seed).points
    size = float(np.ptp(base, axis=0).max())
    return base + np.random.default_rng(seed + 1).normal(scale=0.01 * size, size=base.shape)


def test_two_circles_apart_are_two_groups_and_their_noise_is_not_a_curve() -> None:
    rng = np.random.default_rng(4)
    t = rng.uniform(0, 2 * np.pi, 120)
    a = np.c_[np.cos(t), np.sin(t)]
    b = np.c_[4 + 0.5 * np.cos(t), 0.5 * np.sin(t)]
    pts = np.vstack([a, b]) + rng.normal(scale=0.01, size=(240, 2))
    groups = curve_groups(pts)
    assert groups is not None and len(groups) == 2
    assert sorted(map(tuple, (sorted(g.tolist()) for g in groups))) == [
        tuple(range(120)),
        tuple(range(120, 240)),
    ]


def test_a_sample_without_a_persistent_cycle_is_not_split() -> None:
    rng = np.random.default_rng(5)
    arc = np.c_[np.linspace(0, 3, 80), np.zeros(80)] + rng.normal(scale=0.01, size=(80, 2))
    assert curve_groups(arc) is None
    blob = rng.uniform(-1, 1, size=(300, 2))  # a filled square: cycles of the gaps, none persistent
    assert curve_groups(blob) is None


def test_the_short_tour_of_a_shuffled_circle_is_the_circle() -> None:
    n = 40
    order = np.random.default_rng(6).permutation(n)
    t = 2 * np.pi * order / n
    pts = np.c_[np.cos(t), np.sin(t)]
    tour = short_tour(pts, np.zeros((0, 2), np.int64))
    walked = order[tour]  # the angle index of each visited sample
    steps = (np.roll(walked, -1) - walked) % n
    assert set(steps.tolist()) in ({1}, {n - 1})  # around the circle, one way


def test_the_noisy_ellipse_is_closed_through_every_sample_and_says_so() -> None:
    # sigma = 1 % of its size, about one spacing: before the rule 5 of 12 seeds were right (seed 1 open)
    rec = reconstruct(_noisy_ellipse(1), 1)
    t = rec.topology
    assert t.closed_manifold and t.unused_samples == 0 and tuple(t.betti) == (1, 1)
    tours = [s for s in rec.extraction.steps if s.rule == "tour-curve"]
    assert len(tours) == 1 and tours[0].added
    feats = [f for f in rec.uncertain_features if "tour-curve" in f.reason]
    assert len(feats) == 1 and feats[0].kind == "component"
    assert feats[0].size_spacings > 1


def test_a_grown_curve_closed_through_every_sample_is_kept() -> None:
    # sample seed 0 of the same variant: the paper's loop fails, the growing path closes the curve
    # through every sample, and the rule must leave that alone
    rec = reconstruct(_noisy_ellipse(0), 1)
    rules = {s.rule for s in rec.extraction.steps}
    assert "grow" in rules and "tour-curve" not in rules
    assert rec.topology.closed_manifold and tuple(rec.topology.betti) == (1, 1)
    assert rec.uncertain_features == []


def test_the_tour_ends_where_a_move_and_its_undoing_tie() -> None:
    # five samples where an Or-opt move's removal gain is negative: with a tolerance that turned with its
    # sign the move and its undoing both looked shorter, for ever (found in review)
    pts = np.array([[0, 1], [1, 1], [2, 1], [3, 0], [3, 2]], float)
    tour = short_tour(pts, np.zeros((0, 2), np.int64))
    assert sorted(tour.tolist()) == [0, 1, 2, 3, 4]


def test_the_tour_stops_when_cancelled() -> None:
    import threading

    import pytest

    from crustview.core.errors import Cancelled

    t = 2 * np.pi * np.random.default_rng(8).permutation(600) / 600
    pts = np.c_[np.cos(t), np.sin(t)] + np.random.default_rng(9).normal(scale=0.01, size=(600, 2))
    stop = threading.Event()
    stop.set()
    with pytest.raises(Cancelled):
        short_tour(pts, np.zeros((0, 2), np.int64), stop)
