"""The greedy farthest-point subset: the local pass gives the plain pass's picks, in the same order."""

from __future__ import annotations

import numpy as np
import pytest

from crustview.core.samples import sampling
from crustview.core.samples.sampling import _farthest_local, farthest_point_sampling


def _plain(points, n, seed, scale=None):
    """The plain pass over every candidate (the set is below LOCAL_FPS_MIN)."""
    assert len(points) <= sampling.LOCAL_FPS_MIN
    return farthest_point_sampling(points, n, np.random.default_rng(seed), scale=scale)


def _local(points, n, seed, scale=None):
    coords = np.ascontiguousarray(np.asarray(points, float).T)
    m = coords.shape[1]
    start = int(np.random.default_rng(seed).integers(m))  # the first pick, as farthest_point_sampling draws it
    weight = None if scale is None else np.asarray(scale, float) ** 2
    return _farthest_local(coords, n, weight, np.empty(n, np.intp), np.full(m, np.inf), start)


@pytest.mark.parametrize("k", [2, 3, 4])
def test_the_local_pass_picks_what_the_plain_pass_picks(k):
    rng = np.random.default_rng(k)
    points = rng.normal(size=(3000, k))
    scale = rng.uniform(0.5, 2.0, size=len(points))
    for n in (1, 2, 50, 500):
        assert np.array_equal(_local(points, n, 7), _plain(points, n, 7))
        assert np.array_equal(_local(points, n, 8, scale), _plain(points, n, 8, scale))


def test_ties_go_to_the_lowest_index_as_argmax_gives_them():
    """On paper: a 6 x 6 grid of spacing 1 has many candidates at the same distance; both passes take the
    first of them, so the picks agree even where only the order of equal distances decides."""
    g = np.stack(np.meshgrid(np.arange(6.0), np.arange(6.0)), -1).reshape(-1, 2)
    for seed in range(5):
        assert np.array_equal(_local(g, 36, seed), _plain(g, 36, seed))
    picks = _plain(g, 4, 0)
    assert len(set(picks.tolist())) == 4


def test_a_large_even_sample_takes_the_local_pass(monkeypatch):
    """Above LOCAL_FPS_MIN candidates the built-in sampler goes local: the same sample as the plain pass
    (checked here with the bound lowered so that both run on the same 600-point torus)."""
    from crustview.core.samples.manifolds import get_manifold

    torus = get_manifold("torus")
    plain = torus.sample(600, seed=4).points
    monkeypatch.setattr(sampling, "LOCAL_FPS_MIN", 100)
    calls = []
    real = sampling._farthest_local
    monkeypatch.setattr(sampling, "_farthest_local", lambda *a: calls.append(1) or real(*a))  # a spy: it runs
    local = torus.sample(600, seed=4).points
    assert calls == [1] and np.array_equal(plain, local)
