"""Edge lengths: the same bits as numpy's norm."""

from __future__ import annotations

import numpy as np


def test_edge_lengths_are_numpy_s_norms_bit_for_bit() -> None:
    from crustview.core.util.vectors import edge_lengths

    assert edge_lengths(np.array([[0.0, 0, 0], [3, 4, 0]]), np.array([[0, 1], [1, 0], [1, 1]])).tolist() == [5, 5, 0]
    rng = np.random.default_rng(8)
    for dim in (1, 2, 3, 4, 5, 7, 8, 9, 10, 17):  # from 8 on numpy sums in pairs, and so does edge_lengths (by numpy)
        for scale in (1e-7, 1.0, 1e7):
            p = rng.normal(size=(3000, dim)) * scale
            e = rng.integers(0, 3000, size=(10000, 2))
            assert np.array_equal(edge_lengths(p, e), np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1))
