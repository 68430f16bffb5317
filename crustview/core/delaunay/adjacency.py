"""The pairs of Delaunay cells that share a face (the labelling's ties, the enclosures' dual graph).

Kept with the triangulation because both the robust extension (:mod:`crustview.core.robust.labelling`)
and the analyses (:mod:`crustview.core.analysis.enclosures`) walk the cells through their faces.
"""

from __future__ import annotations

import numpy as np

from .faces import _native as _faces_native
from .faces import _native_arrays


def cell_adjacency(simplices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pairs of k-cells that share a (k-1)-face.

    Parameters
    ----------
    simplices : ndarray of shape (m, k + 1)
        Delaunay k-simplices (samples and bounding points).

    Returns
    -------
    a, b : ndarray of shape (p,)
        The two cells of each shared face, the lower-numbered first; the
        faces in increasing order of their sorted vertex ids.
    faces : ndarray of shape (p, k)
        The face, sorted vertex ids.
    """
    m, w = simplices.shape
    if m and simplices.dtype == np.int32 and _faces_native is not None and 2 <= w <= 8 and m < 2**31:
        # the compiled face listing with every vertex a "sample": each facet with its cells in increasing order
        n_all = int(simplices.max()) + 1
        if float(n_all) ** (w - 1) < 2**62 and simplices.min() >= 0:
            listing = _faces_native.faces(np.ascontiguousarray(simplices), w, w - 1, n_all)
            faces, ptr, owners = _native_arrays(listing, w - 1)
            two = np.flatnonzero(np.diff(ptr) == 2)
            a, b = owners[ptr[two]].astype(np.int64), owners[ptr[two] + 1].astype(np.int64)
            return a, b, faces[two].astype(simplices.dtype)  # the numpy path's dtype (its rows of srt)
    srt = np.sort(simplices, axis=1)
    owner = np.tile(np.arange(m, dtype=np.int64), w)
    base = np.int64(srt.max() + 1)
    if float(base) ** (w - 1) < 2**62:
        # one int64 key per face, built column by column without materialising the faces
        key = np.empty(m * w, np.int64)
        for j in range(w):
            cols = [c for c in range(w) if c != j]
            k = srt[:, cols[0]].astype(np.int64)
            for c in cols[1:]:
                k = k * base + srt[:, c]
            key[j * m : (j + 1) * m] = k
        order = np.argsort(key)  # equal keys come in pairs, in either order: ordered below
        same = key[order][1:] == key[order][:-1]
        i = np.flatnonzero(same)
        fo = order[i]
        j_of, c_of = fo // m, fo % m
        faces = _face_rows(srt, c_of, j_of)
        return _lower_first(owner[fo], owner[order[i + 1]], faces)
    faces = np.concatenate([np.delete(srt, j, axis=1) for j in range(w)])
    order = np.lexsort(faces.T[::-1])
    sf = faces[order]
    same = (sf[1:] == sf[:-1]).all(axis=1)
    i = np.flatnonzero(same)
    return _lower_first(owner[order[i]], owner[order[i + 1]], faces[order[i]])


def _lower_first(a: np.ndarray, b: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each pair with its lower-numbered cell first.

    The labelling's later rules visit the pairs' cells in this order, so it
    must not be left to an unstable sort: numpy's quicksort orders equal keys
    differently on different CPUs (its SIMD sorts).
    """
    return np.minimum(a, b), np.maximum(a, b), faces


def _face_rows(srt: np.ndarray, cell: np.ndarray, drop: np.ndarray) -> np.ndarray:
    """Row ``cell`` of the sorted simplices without its column ``drop``, for each pair."""
    w = srt.shape[1]
    cols = np.arange(w - 1)[None, :]
    cols = cols + (cols >= drop[:, None])
    return srt[cell[:, None], cols]
