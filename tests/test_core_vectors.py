"""Row-wise vector products: the same bits as numpy's."""

from __future__ import annotations

import numpy as np

from crustview.core.util.vectors import cross3


def test_cross3_on_paper() -> None:
    e = np.eye(3)
    assert cross3(e[[0, 1, 2]], e[[1, 2, 0]]).tolist() == [[0, 0, 1], [1, 0, 0], [0, 1, 0]]
    assert cross3(np.array([[2.0, 0, 0]]), np.array([[4.0, 0, 0]])).tolist() == [[0, 0, 0]]


def test_cross3_is_numpy_s_cross_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    for scale in (1e-8, 1.0, 1e8):
        a, b = rng.normal(size=(2, 1000, 3)) * scale
        b[:10] = a[:10] * 3.0  # parallel rows: the differences cancel
        assert np.array_equal(cross3(a, b), np.cross(a, b))
    # rows taken from larger arrays (strided views), as the callers pass them
    p = rng.normal(size=(500, 3, 3))
    assert np.array_equal(cross3(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    # in numpy's memory layout (C order): an einsum over it sums in the same order as over numpy's
    out = cross3(a, b)
    assert out.flags["C_CONTIGUOUS"]
    assert np.array_equal(np.einsum("ij,ij->i", out, a), np.einsum("ij,ij->i", np.cross(a, b), a))
    # other dtypes are numpy's own answer
    f32 = a.astype(np.float32), b.astype(np.float32)
    assert cross3(*f32).dtype == np.float32 and np.array_equal(cross3(*f32), np.cross(*f32))


def test_the_callers_of_cross3_compute_what_np_cross_gave() -> None:
    """The enclosures' triangle balls, bit for bit, against the same formula with np.cross."""
    from crustview.core.analysis.enclosures import _triangle_balls

    rng = np.random.default_rng(9)
    p = rng.normal(size=(3000, 3, 3))
    a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    axb = np.cross(a, b)
    den = 2 * np.einsum("ij,ij->i", axb, axb)
    num = np.cross(np.einsum("ij,ij->i", a, a)[:, None] * b - np.einsum("ij,ij->i", b, b)[:, None] * a, axb)
    off = num / den[:, None]
    centre, r2 = _triangle_balls(p)
    assert np.array_equal(r2, np.einsum("ij,ij->i", off, off)) and np.array_equal(centre, p[:, 0] + off)


def test_edge_lengths_are_numpy_s_norms_bit_for_bit() -> None:
    from crustview.core.util.vectors import edge_lengths

    assert edge_lengths(np.array([[0.0, 0, 0], [3, 4, 0]]), np.array([[0, 1], [1, 0], [1, 1]])).tolist() == [5, 5, 0]
    rng = np.random.default_rng(8)
    for dim in (1, 2, 3, 4, 5, 7, 8, 9, 10, 17):  # from 8 on numpy sums in pairs, and so does edge_lengths (by numpy)
        for scale in (1e-7, 1.0, 1e7):
            p = rng.normal(size=(3000, dim)) * scale
            e = rng.integers(0, 3000, size=(10000, 2))
            assert np.array_equal(edge_lengths(p, e), np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1))
