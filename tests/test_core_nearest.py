"""The nearest-neighbour distances computed once per point set."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from crustview.core.util.nearest import KEEP, nearest_distances


def test_nearest_distances_on_paper_and_against_a_fresh_query() -> None:
    # three samples on a line at 0, 1 and 3: nearest others 1, 1, 2; a duplicate gives 0
    p = np.array([[0.0, 0, 0], [1, 0, 0], [3, 0, 0]])
    assert nearest_distances(p).tolist() == [1.0, 1.0, 2.0]
    assert nearest_distances(np.vstack([p, p[:1]])).tolist() == [0.0, 1.0, 2.0, 0.0]
    rng = np.random.default_rng(4)
    q = rng.normal(size=(2000, 3))
    assert np.array_equal(nearest_distances(q), cKDTree(q).query(q, k=2)[0][:, 1])


def test_a_copy_with_the_same_values_is_served_from_the_cache_read_only() -> None:
    q = np.random.default_rng(5).normal(size=(500, 3))
    first = nearest_distances(q)
    again = nearest_distances(q * 1.0)  # another array, the same bytes
    assert again is first
    with pytest.raises(ValueError):
        again[0] = 1.0
    assert again.base is None or not again.base.flags.writeable  # no writable array behind the shared one
    moved = q.copy()
    moved[7] += 1e-9  # one value changed: another key
    assert nearest_distances(moved) is not first
    for s in range(KEEP + 1):  # older entries make way
        nearest_distances(q + s + 1.0)
    assert nearest_distances(q) is not first and np.array_equal(nearest_distances(q), first)
