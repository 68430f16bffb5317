"""Each sample's distance to its nearest other sample, computed once per point set.

Many rules of the robust extraction and the report's measures need the same
nearest-neighbour distances of the same samples (the labelling, the patcher,
the hole filler, the size of a face, the clusters left out, the local
spacing): on a 50,000-point scan each k-d tree query costs 30-40 ms, and a
run made the same one six to eight times.  :func:`nearest_distances` keeps
the last few answers, keyed by the points' bytes (a new array with the same
values, as ``points / scale`` made twice, is the same key), and hands them
out read-only.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict

import numpy as np
from scipy.spatial import cKDTree

#: Point sets remembered (a run uses one or two: the samples, and rescaled copies of them).
KEEP = 4

_cache: OrderedDict[tuple, np.ndarray] = OrderedDict()
_lock = threading.Lock()


def nearest_other(tree: cKDTree) -> np.ndarray:
    """Each point's distance to its nearest other point of the tree (0 for a point with an exact copy).

    ``tree.query(tree.data, k=2)[0][:, 1]``, the same values, asked in the tree's own leaf order
    (neighbours close in memory: input files come in any order) and put back in the points' order:
    0.27 -> 0.16-0.19 s for 300,000 points in random order.  A new array of n values.
    """
    pts = tree.data
    out = np.empty(len(pts))
    if len(pts) < 2:
        out[:] = np.inf
        return out
    leaf = tree.indices
    out[leaf] = tree.query(pts[leaf], k=2, workers=-1)[0][:, 1]
    return out


def nearest_distances(points: np.ndarray) -> np.ndarray:
    """:func:`nearest_other` of the points (``cKDTree(points).query(points, k=2)[0][:, 1]``), from a small cache.

    Parameters
    ----------
    points : ndarray of shape (n, k)

    Returns
    -------
    ndarray of shape (n,)
        Read-only (shared between callers); 0 for a sample with a duplicate.
    """
    p = np.ascontiguousarray(points, dtype=np.float64)
    key = (p.shape, hashlib.blake2b(p.tobytes(), digest_size=20).digest())
    with _lock:
        hit = _cache.get(key)
        if hit is not None:
            _cache.move_to_end(key)
            return hit
    dist = nearest_other(cKDTree(p)) if len(p) > 1 else np.full(len(p), np.inf)
    dist.flags.writeable = False
    with _lock:
        _cache[key] = dist
        while len(_cache) > KEEP:
            _cache.popitem(last=False)
    return dist


def remember(points: np.ndarray, distances: np.ndarray) -> None:
    """Put ``distances``, known to be :func:`nearest_distances` of ``points``, into the cache.

    For a caller that measured them already with the same query (``prepare``'s merging: the same tree
    query on the same samples, scaled by a power of two): later callers take them from here.
    """
    p = np.ascontiguousarray(points, dtype=np.float64)
    key = (p.shape, hashlib.blake2b(p.tobytes(), digest_size=20).digest())
    dist = np.array(distances, dtype=np.float64)
    dist.flags.writeable = False
    with _lock:
        _cache[key] = dist
        _cache.move_to_end(key)
        while len(_cache) > KEEP:
            _cache.popitem(last=False)
