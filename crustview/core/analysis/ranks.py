"""Ranks over GF(2) of the boundary matrices of a simplicial complex (:mod:`.topology`'s Betti numbers).

The boundary map from the j-faces to the (j-1)-faces has a column per j-face listing its facets' rows;
its rank comes from the compiled column reduction (``_gf2.cpp``) where it is built, otherwise from the
same reduction in Python with integers as bit sets, which stays as its reference
(``tests/test_core_topology_compiled.py``).
"""

from __future__ import annotations

import numpy as np

try:
    from . import _gf2
except ImportError:  # pragma: no cover - the extension is optional
    _gf2 = None


def _face_index(faces: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Row of ``faces`` (sorted unique rows) equal to each row of ``query``."""
    if faces.shape[1] == 1:
        return np.searchsorted(faces[:, 0], query[:, 0])
    base = int(max(faces.max(), query.max())) + 1
    if float(base) ** faces.shape[1] < 2**62:

        def key(a: np.ndarray) -> np.ndarray:
            k = np.zeros(len(a), dtype=np.int64)
            for c in range(a.shape[1]):
                k = k * base + a[:, c]
            return k

        return np.searchsorted(key(faces), key(query))
    view = np.ascontiguousarray(faces).view([("", faces.dtype)] * faces.shape[1]).ravel()
    qv = np.ascontiguousarray(query).view([("", query.dtype)] * query.shape[1]).ravel()
    return np.searchsorted(view, qv)


def boundary_rank_gf2(faces_hi: np.ndarray, faces_lo: np.ndarray) -> int:
    """Rank over GF(2) of the boundary map from ``faces_hi`` (j-faces) to ``faces_lo``.

    The compiled column reduction (``_gf2.cpp``) where it is built; otherwise, and as its reference,
    :func:`boundary_rank_gf2_python`.  The 3-manifolds' middle rank took 0.1-0.4 s a call in Python
    (25,000-39,000 triangles or tetrahedra).
    """
    if len(faces_hi) == 0 or len(faces_lo) == 0:
        return 0
    cols = _boundary_columns(faces_hi, faces_lo)
    if _gf2 is not None:
        return int(_gf2.rank(np.ascontiguousarray(cols, dtype=np.int64), len(faces_lo), cols.shape[1]))
    return _reduce_python(cols)


def boundary_rank_gf2_python(faces_hi: np.ndarray, faces_lo: np.ndarray) -> int:
    """:func:`boundary_rank_gf2` by Python integers as bit sets (the reference of the compiled one)."""
    if len(faces_hi) == 0 or len(faces_lo) == 0:
        return 0
    return _reduce_python(_boundary_columns(faces_hi, faces_lo))


def _boundary_columns(faces_hi: np.ndarray, faces_lo: np.ndarray) -> np.ndarray:
    """Row of ``faces_lo`` of each facet of each row of ``faces_hi``: the boundary matrix's columns."""
    jp1 = faces_hi.shape[1]
    return np.stack([_face_index(faces_lo, np.delete(faces_hi, a, axis=1)) for a in range(jp1)], axis=1)


def _reduce_python(cols: np.ndarray) -> int:
    """The GF(2) rank of the matrix whose columns list their rows (``cols``), by column reduction."""
    pivots: dict[int, int] = {}
    rank = 0
    for row in cols.tolist():
        c = 0
        for b in row:
            c ^= 1 << b
        while c:
            low = c.bit_length() - 1
            p = pivots.get(low)
            if p is None:
                pivots[low] = c
                rank += 1
                break
            c ^= p
    return rank
