"""The facet table and the opposite vectors of a d-complex: what Algorithm 3 reads at every face.

* :func:`facet_structure`: the (d-1)-faces of a pure d-complex as sorted rows, each simplex's facet opposite
  each of its vertices, and the simplices at each facet (CSR).  Triangles (d = 2) take the compiled edge
  table (``util/_surface.cpp``), the same arrays as the numpy code, which every other case runs.
* :func:`opposite_vectors`: the unit vector ``u(sigma, tau)`` from each facet's affine hull to the opposite
  vertex, whose dot products are the angles of :mod:`.extraction`'s rules.

Also used by the robust extension's complex, growth and stray tests and by the report.
"""

from __future__ import annotations

import numpy as np

from ..util.rows import dense_ids, unique_rows

try:
    from ..util import _surface
except ImportError:  # pragma: no cover - the extension is optional
    _surface = None

#: Simplices per block in :func:`opposite_vectors`.
OPPOSITE_BLOCK = 1 << 16


def facet_structure(
    simplices: np.ndarray,
    positions: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(d-1)-faces of a d-complex.

    Parameters
    ----------
    simplices : ndarray of shape (c, d + 1)
    positions : bool
        Return ``inc`` as positions ``simplex * (d + 1) + a`` (the facet
        opposite vertex a) instead of simplex ids: the stable argsort of
        ``facet_of.ravel()``.

    Returns
    -------
    facets : ndarray of shape (g, d)
        Sorted vertex rows.
    facet_of : ndarray of shape (c, d + 1)
        ``facet_of[i, a]`` is the facet of simplex ``i`` opposite its vertex ``a``.
    ptr, inc : ndarray
        CSR: simplices containing facet ``g`` are ``inc[ptr[g]:ptr[g+1]]``.

    Triangles (d = 2) take the compiled edge table (``_surface.edge_structure``: each vertex lists the
    edges to its larger neighbours, which taken vertex by vertex is the sorted order), the same arrays
    as the numpy code below, which every other case runs (``tests/test_core_topology_compiled.py``).
    """
    c, dp1 = simplices.shape
    if dp1 == 3 and c and _surface is not None:
        fast = _edge_structure(simplices)
        if fast is not None:
            facets, facet_of, ptr, pos = fast
            return facets, facet_of, ptr, pos if positions else pos // dp1
    srt = np.sort(simplices, axis=1)
    allf = np.empty((c, dp1, dp1 - 1), dtype=srt.dtype)
    for a in range(dp1):
        allf[:, a] = np.delete(srt, a, axis=1)
    del srt
    facets, inverse = unique_rows(allf.reshape(-1, dp1 - 1))
    del allf
    facet_of = inverse.reshape(c, dp1)
    order = np.argsort(inverse, kind="stable")
    counts = np.bincount(inverse, minlength=len(facets))
    ptr = np.concatenate([[0], np.cumsum(counts)])
    if not positions:
        order //= dp1
    return facets, facet_of, ptr, order


def _edge_structure(triangles: np.ndarray) -> tuple[np.ndarray, ...] | None:
    """:func:`facet_structure` of triangles (``positions=True``) by the compiled edge table, or None."""
    t = np.ascontiguousarray(triangles, dtype=np.int64)
    top = int(t.max())
    if int(t.min()) < 0 or not dense_ids(top, t.size):
        return None
    out = _surface.edge_structure(top + 1, t)
    if out is None:
        return None
    edges, facet_of, ptr, pos = (np.frombuffer(b, dtype=np.int64) for b in out)
    return edges.reshape(-1, 2).copy(), facet_of.reshape(-1, 3).copy(), ptr.copy(), pos.copy()


def opposite_vectors(points: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Unit vectors ``u(sigma, tau)`` for every simplex and facet.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (c, d + 1), rows sorted

    Returns
    -------
    ndarray of shape (c, d + 1, k)
        ``[i, a]``: from aff(facet opposite vertex a) to vertex a.
    """
    c, dp1 = simplices.shape
    out = np.empty((c, dp1, points.shape[1]))
    for lo in range(0, c, OPPOSITE_BLOCK):  # blocks: temporaries stay small (rows are independent)
        blk = simplices[lo : lo + OPPOSITE_BLOCK]
        if dp1 <= 3:
            _opposite_small(points, blk, out[lo : lo + len(blk)])
            continue
        p = points[blk]
        for a in range(dp1):
            rest = np.delete(p, a, axis=1)  # (c, d, k)
            v = p[:, a] - rest[:, 0]
            q, _ = np.linalg.qr(np.swapaxes(rest[:, 1:] - rest[:, :1], 1, 2))
            v = v - np.einsum("ckj,cj->ck", q, np.einsum("ckj,ck->cj", q, v))
            out[lo : lo + len(p), a] = v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)
    return out


def _opposite_small(points: np.ndarray, simplices: np.ndarray, out: np.ndarray) -> None:
    """:func:`opposite_vectors` of edges and triangles, on per-coordinate columns.

    For a triangle the facet opposite vertex a is the edge (b, e), b < e; the
    vector is ``p_a - p_b`` minus its component along the unit edge
    direction (one Gram-Schmidt step, where a batched QR of one column costs
    3-4x more).
    """
    k = points.shape[1]
    dp1 = simplices.shape[1]
    cols = [np.take(points[:, q], simplices) for q in range(k)]  # (c, d + 1) each
    for a in range(dp1):
        b, *e = [j for j in range(dp1) if j != a]
        v = [x[:, a] - x[:, b] for x in cols]
        if e:
            w = [x[:, e[0]] - x[:, b] for x in cols]
            wlen = np.maximum(np.sqrt(sum(x * x for x in w)), 1e-300)
            w = [x / wlen for x in w]
            along = sum(x * y for x, y in zip(v, w))
            v = [x - along * y for x, y in zip(v, w)]
        vlen = np.maximum(np.sqrt(sum(x * x for x in v)), 1e-300)
        for q in range(k):
            out[:, a, q] = v[q] / vlen
