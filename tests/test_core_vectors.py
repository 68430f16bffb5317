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


def test_squared_distances_are_numpy_s_bit_for_bit() -> None:
    """((x[ia] - y[ib]) ** 2).sum(axis=1) and the norm's square root, with and without row indices, in 1-17
    dimensions (from 8 on numpy's own answer), and for other dtypes."""
    from crustview.core.util.vectors import squared_distances

    x = np.array([[0.0, 0], [3, 4]])
    assert squared_distances(x, np.array([1, 0]), x, np.array([0, 0])).tolist() == [25, 0]
    assert squared_distances(x, None, x[::-1], None).tolist() == [25, 25]
    rng = np.random.default_rng(12)
    for dim in (1, 2, 3, 4, 7, 8, 9, 17):
        for scale in (1e-7, 1.0, 1e7):
            p, q = rng.normal(size=(2, 3000, dim)) * scale
            ia, ib = rng.integers(0, 3000, size=(2, 5000))
            assert np.array_equal(squared_distances(p, ia, q, ib), ((p[ia] - q[ib]) ** 2).sum(axis=1))
            assert np.array_equal(squared_distances(p, None, q, None), ((p - q) ** 2).sum(axis=1))
            assert np.array_equal(squared_distances(p, None, q, ib[:3000]), ((p - q[ib[:3000]]) ** 2).sum(axis=1))
            assert np.array_equal(
                np.sqrt(squared_distances(p, None, q, ib[:3000])), np.linalg.norm(p - q[ib[:3000]], axis=1)
            )
    f32 = rng.normal(size=(50, 3)).astype(np.float32)
    got = squared_distances(f32, None, f32[::-1], None)
    assert got.dtype == np.float32 and np.array_equal(got, ((f32 - f32[::-1]) ** 2).sum(axis=1))
