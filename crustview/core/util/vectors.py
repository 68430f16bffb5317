"""Row-wise vector products and lengths of many vectors at once, numpy's values bit for bit."""

from __future__ import annotations

import numpy as np

#: numpy's norm adds a row of fewer coordinates than this from its first entry on; from 8 on it sums in pairs
#: (its 8-way unrolled reduction), and :func:`edge_lengths` leaves such rows to numpy.
SEQUENTIAL_SUM = 8


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross(a, b)`` for float64 arrays of shape (n, 3), bit for bit and in C order, in about half its time.

    Each component is the same two products and one difference, in numpy's order
    (``a1 b2 - a2 b1``, ``a2 b0 - a0 b2``, ``a0 b1 - a1 b0``; numpy fuses no
    operations), taken over contiguous columns instead of strided ones.  The
    result is row-major like numpy's, so what callers compute from it (an
    ``einsum`` sums in the order of the memory layout) is the same too.  Other
    dtypes and shapes go to ``np.cross``.

    Parameters
    ----------
    a, b : ndarray of shape (n, 3)

    Returns
    -------
    ndarray of shape (n, 3)
    """
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != np.float64 or b.dtype != np.float64 or a.ndim != 2 or a.shape != b.shape or a.shape[1] != 3:
        return np.cross(a, b)
    at, bt = np.ascontiguousarray(a.T), np.ascontiguousarray(b.T)
    out = np.empty((3, at.shape[1]))
    np.multiply(at[1], bt[2], out=out[0])
    out[0] -= at[2] * bt[1]
    np.multiply(at[2], bt[0], out=out[1])
    out[1] -= at[0] * bt[2]
    np.multiply(at[0], bt[1], out=out[2])
    out[2] -= at[1] * bt[0]
    return np.ascontiguousarray(out.T)


def edge_lengths(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)``, bit for bit, in about 40 % of its time.

    For float64 points of fewer than :data:`SEQUENTIAL_SUM` coordinates numpy's norm adds the squared
    differences of a row from its first coordinate on, then takes the square root; this does the same, one
    contiguous coordinate column at a time, without the (e, k) temporaries.  Other points go to numpy.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    edges : ndarray of shape (e, 2)

    Returns
    -------
    ndarray of shape (e,)
    """
    points = np.asarray(points)
    a, b = edges[:, 0], edges[:, 1]
    if points.dtype != np.float64 or points.ndim != 2 or not 1 <= points.shape[1] < SEQUENTIAL_SUM:
        return np.linalg.norm(points[a] - points[b], axis=1)
    cols = np.ascontiguousarray(points.T)
    out = cols[0][a] - cols[0][b]
    out *= out
    for c in cols[1:]:
        diff = c[a] - c[b]
        diff *= diff
        out += diff
    return np.sqrt(out, out=out)
