"""The Delaunay d-faces among the samples and the simplices around each (Algorithm 2's input).

At a million samples a tetrahedralisation has 17 million simplices and 68
million face instances, so this is written for memory: the only arrays as
long as the instances are their int64 keys and one stable sort order.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..util.parallel import WORKERS, run_in_order

try:  # compiled facet listing (setup.py builds it; numpy does the same without it)
    from . import _faces as _native
except ImportError:  # pragma: no cover - depends on the build
    _native = None

#: Simplices (and face instances) per block in :func:`enumerate_faces`.
ENUM_BLOCK = 1 << 20


def enumerate_faces(
    simplices: np.ndarray, n_samples: int, d: int, neighbors: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All d-faces of the Delaunay simplices whose vertices are samples.

    Parameters
    ----------
    simplices : ndarray of shape (t, r + 1)
    n_samples : int
        Vertices ``>= n_samples`` are bounding points; faces with one are left out.
    d : int
    neighbors : ndarray of shape (t, r + 1), optional
        The backend's neighbour table (-1 across the hull).  In codimension 1
        (``r = d + 1``) every face is a facet shared by at most two
        simplices, and the table pairs them without sorting the face
        instances (:func:`_enumerate_facets`, same result).

    Returns
    -------
    faces : ndarray of shape (f, d + 1)
        Sorted rows, lexicographically sorted (int64).
    cell_ptr : ndarray of shape (f + 1,)
    cell_simplices : ndarray
        ``cell_simplices[cell_ptr[i]:cell_ptr[i+1]]`` are the Delaunay
        simplices containing face ``i`` (vertices of its dual cell), in
        increasing order; int32 when the simplex count allows it.

    Notes
    -----
    Memory is the limit at a million samples (tens of millions of face
    instances), so the only arrays as long as the instances are their int64
    keys and one stable sort order; the distinct faces, their pointers and
    the owning simplices are then read from those in blocks.  With int32
    simplices the compiled :mod:`._faces` gives the same arrays: it groups
    the instances by the face's lowest vertex (a counting sort) and sorts
    each group, a few thousand instances that stay in cache, on two
    threads (12 bytes per instance, once; a radix sort of all instances
    needed them twice and was 10-25 % slower on the 10,000-point Klein
    bottle, 26.8 million instances); the numpy code below is the fallback
    and the reference its tests compare with.
    """
    small_keys = float(n_samples) ** (d + 1) < 2**62
    if neighbors is not None and simplices.shape[1] == d + 2 and small_keys and len(simplices):
        return _enumerate_facets(simplices, neighbors, n_samples)
    if _native is not None and small_keys and simplices.dtype == np.int32 and len(simplices) < 2**31:
        return _faces_native(simplices, n_samples, d)
    srt = sort_rows(simplices)
    w = srt.shape[1]
    combos = list(itertools.combinations(range(w), d + 1))
    if not small_keys:
        return _enumerate_faces_lexsort(srt, n_samples, d, combos)
    nc = len(combos)
    # one int64 key per face instance, face-major within each simplex (the
    # order of the old srt[:, combos] layout); -1 when a vertex is a bounding point
    keys = np.empty((len(srt), nc), dtype=np.int64)
    for lo in range(0, len(srt), ENUM_BLOCK):
        blk = srt[lo : lo + ENUM_BLOCK]
        for q, cols in enumerate(combos):
            k = blk[:, cols[0]].astype(np.int64)
            for c in cols[1:]:
                k *= n_samples
                k += blk[:, c]
            keys[lo : lo + len(blk), q] = np.where(blk[:, cols[-1]] < n_samples, k, -1)
    del srt
    keys = keys.ravel()
    order = _stable_argsort(keys, lower=0)  # instances of sample faces only, by key, stable
    owner_dtype = np.int32 if len(keys) // nc < 2**31 else np.int64
    if len(order) == 0:
        return np.empty((0, d + 1), np.int64), np.zeros(1, np.int64), np.empty(0, owner_dtype)
    # first instance of each distinct key, and each instance's simplex, block by block
    starts_parts = []
    owner = np.empty(len(order), dtype=owner_dtype)
    prev = None
    for lo in range(0, len(order), ENUM_BLOCK):
        sl = order[lo : lo + ENUM_BLOCK]
        sk = keys[sl]
        new = np.empty(len(sk), dtype=bool)
        new[0] = prev is None or sk[0] != prev
        np.not_equal(sk[1:], sk[:-1], out=new[1:])
        starts_parts.append(np.flatnonzero(new) + lo)
        owner[lo : lo + len(sl)] = sl // nc
        prev = sk[-1]
    starts = np.concatenate(starts_parts)
    del starts_parts
    rest = keys[order[starts]]
    del keys, order
    uniq = np.empty((len(starts), d + 1), dtype=np.int64)
    for c in range(d, -1, -1):
        uniq[:, c] = rest % n_samples
        rest //= n_samples
    ptr = np.append(starts, len(owner))
    return uniq, ptr, owner


def _enumerate_facets(
    simplices: np.ndarray, neighbors: np.ndarray, n_samples: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`enumerate_faces` in codimension 1, from the neighbour table.

    The facet of simplex ``i`` opposite its vertex ``j`` is shared with
    ``neighbors[i, j]``; it is listed once, by the lower-numbered simplex (or
    by ``i`` alone across the hull), so its dual cell is ``(i, neighbor)``,
    already in increasing order.  Only the distinct faces' int64 keys are
    sorted: half as many as the face instances the general path sorts.
    With int32 tables the compiled :mod:`._faces` does the same in one pass
    and a radix sort (3-4x faster at 300,000 samples, identical arrays).
    """
    t, w = simplices.shape
    if _native is not None and simplices.dtype == np.int32 and neighbors.dtype == np.int32:
        return _facets_native(simplices, neighbors, n_samples)
    owner_dtype = np.int32 if t < 2**31 else np.int64
    keys_parts, first_parts, second_parts = [], [], []
    for lo in range(0, t, ENUM_BLOCK):
        blk = simplices[lo : lo + ENUM_BLOCK]
        nb = neighbors[lo : lo + ENUM_BLOCK]
        ids = np.arange(lo, lo + len(blk), dtype=np.int64)
        for j in range(w):
            other = nb[:, j].astype(np.int64)
            cols = [c for c in range(w) if c != j]
            rows = sort_rows(blk[:, cols])
            keep = ((other > ids) | (other < 0)) & (rows[:, -1] < n_samples)
            rows = rows[keep]
            key = rows[:, 0].astype(np.int64)
            for c in range(1, w - 1):
                key *= n_samples
                key += rows[:, c]
            keys_parts.append(key)
            first_parts.append(ids[keep].astype(owner_dtype))
            second_parts.append(other[keep].astype(owner_dtype))
    keys = np.concatenate(keys_parts)
    del keys_parts
    order = _stable_argsort(keys)
    keys = keys[order]
    first = np.concatenate(first_parts)[order]
    second = np.concatenate(second_parts)[order]
    del first_parts, second_parts, order
    faces = np.empty((len(keys), w - 1), dtype=np.int64)
    for c in range(w - 2, -1, -1):
        faces[:, c] = keys % n_samples
        keys //= n_samples
    shared = second >= 0
    if shared.all():
        ptr = np.arange(0, 2 * len(faces) + 1, 2, dtype=np.int64)
        owners = np.stack([first, second], axis=1).ravel()
    else:  # hull facets (no bounding points around the samples) have one simplex
        ptr = np.concatenate([[0], np.cumsum(1 + shared)]).astype(np.int64)
        owners = np.stack([first, second], axis=1).ravel()[np.stack([np.ones_like(shared), shared], axis=1).ravel()]
    return faces, ptr, owners


def _facets_native(
    simplices: np.ndarray, neighbors: np.ndarray, n_samples: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_enumerate_facets` through the extension :mod:`._faces`."""
    w = simplices.shape[1]
    return _native_arrays(
        _native.facets(np.ascontiguousarray(simplices), np.ascontiguousarray(neighbors), w, int(n_samples)), w - 1
    )


def _faces_native(simplices: np.ndarray, n_samples: int, d: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`enumerate_faces` (general path) through the extension :mod:`._faces`: same arrays."""
    return _native_arrays(
        _native.faces(np.ascontiguousarray(simplices), simplices.shape[1], d + 1, int(n_samples)), d + 1
    )


def _native_arrays(result: tuple, width: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Numpy views of :mod:`._faces`' (faces, ptr, owners, count) bytearrays."""
    faces, ptr, owners, count = result
    return (
        np.frombuffer(faces, dtype=np.int64).reshape(count, width),
        np.frombuffer(ptr, dtype=np.int64),
        np.frombuffer(owners, dtype=np.int32),
    )


def _enumerate_faces_lexsort(
    srt: np.ndarray, n_samples: int, d: int, combos: list[tuple[int, ...]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`enumerate_faces` when a face does not fit one int64 key."""
    faces = srt[:, np.array(combos)].reshape(-1, d + 1)
    owner = np.repeat(np.arange(len(srt)), len(combos))
    keep = faces[:, -1] < n_samples
    faces, owner = faces[keep], owner[keep]
    if len(faces) == 0:
        return np.empty((0, d + 1), np.int64), np.zeros(1, np.int64), np.empty(0, np.int64)
    order = np.lexsort(faces.T[::-1])
    sf = faces[order]
    starts = np.flatnonzero(np.concatenate([[True], (sf[1:] != sf[:-1]).any(axis=1)]))
    ptr = np.concatenate([starts, [len(order)]])
    return faces[order[starts]].astype(np.int64), ptr, owner[order]


def sort_rows(rows: np.ndarray) -> np.ndarray:
    """Each row sorted (like ``np.sort(rows, axis=1)``) by compare-exchange on columns."""
    cols = [np.ascontiguousarray(rows[:, c]) for c in range(rows.shape[1])]
    w = len(cols)
    for i in range(w):  # odd-even transposition sort: w rounds of neighbour swaps
        for j in range(i % 2, w - 1, 2):
            lo = np.minimum(cols[j], cols[j + 1])
            cols[j + 1] = np.maximum(cols[j], cols[j + 1])
            cols[j] = lo
    return np.stack(cols, axis=1)


def _stable_argsort(key: np.ndarray, workers: int | None = None, lower: int | None = None) -> np.ndarray:
    """``np.argsort(key, kind="stable")``, with key ranges sorted on separate threads.

    The ranges are split at sample quantiles; each range keeps its
    elements' original order, so concatenating the sorted ranges is exactly
    the stable order of the whole array.  With ``lower``, only the positions
    of keys ``>= lower`` are returned (in the same order).  There are more
    ranges than threads, so the temporaries of the ranges being sorted stay
    a fraction of the key array.
    """
    threads = WORKERS if workers is None else workers
    if threads <= 1 or len(key) < 1 << 16:
        if lower is None:
            return np.argsort(key, kind="stable")
        idx = np.flatnonzero(key >= lower)
        return idx[np.argsort(key[idx], kind="stable")]
    parts = 4 * threads
    sample = key[:: max(1, len(key) // 4096)]
    if lower is not None:
        sample = sample[sample >= lower]
    sample = np.sort(sample)
    cuts = np.unique(sample[(np.arange(1, parts) * len(sample)) // parts]).tolist() if len(sample) else []
    first = None if lower is None else lower
    bounds = list(zip([first, *cuts], [*cuts, None]))

    def sort_part(bound: tuple) -> np.ndarray:
        lo, hi = bound
        if lo is None:
            mask = key < hi if hi is not None else np.ones(len(key), dtype=bool)
        elif hi is None:
            mask = key >= lo
        else:
            mask = (key >= lo) & (key < hi)
        idx = np.flatnonzero(mask)
        del mask
        sub = key[idx]
        perm = np.argsort(sub, kind="stable")
        del sub
        return idx[perm]

    total = len(key) if lower is None else int(np.count_nonzero(key >= lower))
    order = np.empty(total, dtype=np.int64)
    at = 0
    for part in run_in_order(sort_part, bounds, threads):
        order[at : at + len(part)] = part
        at += len(part)
    return order
