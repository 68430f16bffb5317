"""Fast unique rows of small integer arrays (simplex vertex lists)."""

from __future__ import annotations

import numpy as np


def index_dtype(count: int) -> type:
    """The smallest of int32/int64 that holds indices ``0 .. count - 1``.

    Vertex tables of a million-sample triangulation are tens of millions of
    entries; int32 halves them.  Arithmetic on such tables (keys) must cast
    to int64 first, as :func:`row_keys` does.
    """
    return np.int32 if count < 2**31 else np.int64


def row_keys(rows: np.ndarray, base: int) -> np.ndarray | None:
    """Encode each row as one int64 (``None`` when ``base ** width`` overflows)."""
    width = rows.shape[1]
    if float(base) ** width >= 2**62:
        return None
    key = np.zeros(len(rows), dtype=np.int64)
    for c in range(width):
        key = key * base + rows[:, c]
    return key


def unique_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted unique rows and the inverse map, like ``np.unique(axis=0)`` but faster.

    Parameters
    ----------
    rows : ndarray of shape (m, w), non-negative integers

    Returns
    -------
    uniq : ndarray of shape (u, w)
        Lexicographically sorted.
    inverse : ndarray of shape (m,)
        ``uniq[inverse] == rows``.
    """
    rows = np.asarray(rows, dtype=np.int64)
    if len(rows) == 0:
        return rows.reshape(0, rows.shape[1]), np.zeros(0, dtype=np.int64)
    key = row_keys(rows, int(rows.max()) + 1)
    if key is None:
        uniq, inverse = np.unique(rows, axis=0, return_inverse=True)
        return uniq, inverse.ravel()
    order = np.argsort(key, kind="stable")
    sk = key[order]
    new = np.concatenate([[True], sk[1:] != sk[:-1]])
    group = np.cumsum(new) - 1
    inverse = np.empty(len(rows), dtype=np.int64)
    inverse[order] = group
    return rows[order[new]], inverse


#: Vertex ids up to this many times the table's entries (and any id below 2^20) count as dense.
DENSE_IDS = 16


def dense_ids(max_id: int, entries: int) -> bool:
    """Whether a kernel may index a per-vertex table by id: ids at most DENSE_IDS times the entries or < 2^20.

    The compiled edge table and counts (``util/_surface.cpp``) allocate a few int64 per id up to the largest,
    and :func:`crustview.core.analysis.topology.all_faces` a flag per id; a complex over a handful of huge ids
    (never met in the pipeline, where ids are sample rows) takes a sort instead, whose memory follows the
    number of entries.
    """
    return max_id < (1 << 20) or max_id <= DENSE_IDS * entries
