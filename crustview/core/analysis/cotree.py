"""The dual side of the loop basis's tree-cotree split: each edge's triangles, the dual forest, its edges.

:func:`.loops.short_basis` pairs a spanning tree of the vertices with a
spanning forest of the triangles across the remaining edges (Eppstein 2003);
the edges in neither are the basis's leftover edges.  :func:`edge_triangles`
and :func:`bfs_forest` give the same arrays with and without the compiled
code (``_paths.cpp``), which does each in one pass instead of a sort and a
graph search (0.3-0.4 s to a few tens of milliseconds on a 300,000-point
torus); :func:`up_edges` reads the forest's edges off the dual edges, and
:func:`may_have_loops` tells the basis when searching ahead cannot pay.
:func:`triangle_edges` is the primal side's table (every edge once, each triangle's three), from the
compiled edge table of ``util/_surface.cpp`` or numpy's keys.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components

from ..util.rows import dense_ids

try:
    from . import _paths
except ImportError:  # pragma: no cover - the extension is optional
    _paths = None
try:
    from ..util import _surface
except ImportError:  # pragma: no cover - the extension is optional
    _surface = None


def edge_triangles(tri_edges: np.ndarray, n_edges: int) -> np.ndarray:
    """Each edge's first and last triangle (in triangle order) among those holding it.

    Parameters
    ----------
    tri_edges : ndarray of shape (t, 3)
        Each triangle's edge ids, in ``[0, n_edges)``.
    n_edges : int

    Returns
    -------
    ndarray of shape (n_edges, 2) of int64
        -1 where an edge has no triangle (both) or one (the second).  For an edge
        of two triangles, the two.
    """
    tri_edges = np.ascontiguousarray(tri_edges, dtype=np.int64)
    if _paths is not None:
        return np.frombuffer(_paths.edge_triangles(tri_edges, int(n_edges)), dtype=np.int64).reshape(-1, 2)
    return _edge_triangles_numpy(tri_edges, n_edges)


def _edge_triangles_numpy(tri_edges: np.ndarray, n_edges: int) -> np.ndarray:
    """:func:`edge_triangles` by a stable sort of the flattened triples."""
    e_tris = np.full((n_edges, 2), -1, np.int64)
    flat_e = tri_edges.ravel()
    flat_t = np.repeat(np.arange(len(tri_edges)), 3)
    o = np.argsort(flat_e, kind="stable")
    fe, ft = flat_e[o], flat_t[o]
    first = np.r_[True, fe[1:] != fe[:-1]] if len(fe) else np.zeros(0, bool)
    e_tris[fe[first], 0] = ft[first]
    second = ~first
    e_tris[fe[second], 1] = ft[second]
    return e_tris


def may_have_loops(tris: np.ndarray, count: np.ndarray, used: np.ndarray, pieces: int) -> bool:
    """False only for closed surfaces of spheres (every edge in two triangles, V - E + F = 2 per piece).

    A scheduling test of :func:`.loops.short_basis` (no loop: its trees are not searched ahead):
    ``count`` is the triangles at each edge, ``used`` the vertices of the triangles and ``pieces`` their
    components.  A closed piece has Euler characteristic 2 only as a sphere, so the sum is 2 per piece
    only when there is no loop.  Anything else (boundary or non-manifold edges) may have loops.
    """
    if len(count) == 0 or not (count == 2).all():
        return True
    chi = int(used.sum()) - len(count) + len(tris)
    return chi < 2 * pieces


def up_edges(
    tris: np.ndarray, edges: np.ndarray, tri_edges: np.ndarray, tparent: np.ndarray, de: np.ndarray, pair: tuple
) -> np.ndarray:
    """Each triangle's edge shared with its dual parent (-1 at roots): the first of its three it shares.

    Two triangles with different vertex sets share at most one edge, which is then the dual edge that joins
    them in the forest; read off the dual edges.  A triangle whose parent has its very vertices (a repeated
    row) shares all three, and takes the first of its own edge slots, as comparing the edge triples does.
    """
    up_edge = np.full(len(tris), -1, np.int64)
    for t, u in ((pair[0], pair[1]), (pair[1], pair[0])):
        up = tparent[t] == u
        up_edge[t[up]] = de[up]
    kids = np.flatnonzero(tparent >= 0)
    e = up_edge[kids]
    # the same vertex set: the third vertices (beside the shared edge) are the same
    rest = edges[e].sum(axis=1)
    twin = kids[tris[kids].sum(axis=1) - rest == tris[tparent[kids]].sum(axis=1) - rest]
    if len(twin):
        te, pe = tri_edges[twin], tri_edges[tparent[twin]]
        match = (te[:, :, None] == pe[:, None, :]).any(axis=2)
        up_edge[twin] = te[np.arange(len(twin)), np.argmax(match, axis=1)]
    return up_edge


def bfs_forest(n: int, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Breadth-first forest of the undirected graph on ``n`` nodes with edges ``(a[i], b[i])``.

    Each component is searched from its smallest node, each node's neighbours
    taken in increasing order: scipy's ``breadth_first_order`` on the graph's
    canonical CSR matrix, component by component.

    Returns
    -------
    parent : ndarray of shape (n,) of int64
        -1 at each component's root.
    depth : ndarray of shape (n,) of int64
        Hops to the root.
    """
    a = np.ascontiguousarray(a, dtype=np.int64)
    b = np.ascontiguousarray(b, dtype=np.int64)
    if _paths is not None:
        parent, depth = _paths.bfs_forest(int(n), a, b)
        return np.frombuffer(parent, dtype=np.int64), np.frombuffer(depth, dtype=np.int64)
    return _bfs_forest_scipy(n, a, b)


def _bfs_forest_scipy(n: int, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`bfs_forest` by scipy's search from each component's smallest node."""
    g = coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n)).tocsr()
    g = g + g.T
    _, label = connected_components(g, directed=False)
    parent = np.full(n, -1, np.int64)
    for c in np.unique(label):
        r = int(np.nonzero(label == c)[0][0])
        bfs, par = breadth_first_order(g, r, directed=False, return_predecessors=True)
        parent[bfs[1:]] = par[bfs[1:]]
    return parent, depths(parent)


def depths(pred: np.ndarray) -> np.ndarray:
    """Hops from every reached vertex to its tree's root (pointer doubling)."""
    n = len(pred)
    anc = np.where(pred >= 0, pred, np.arange(n))
    depth = (pred >= 0).astype(np.int64)
    while True:
        nxt = anc[anc]
        if np.array_equal(nxt, anc):
            return depth
        depth = depth + depth[anc]  # a root's own depth is 0
        anc = nxt


def triangle_edges(tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique edges of the triangles (sorted rows, in key order), and each triangle's three edge ids.

    A triangle (x, y, z) has the edges (x, y), (y, z) and (x, z), in that order.  With the compiled edge
    table (``util._surface``) the same arrays come from one pass per vertex; numpy's keys otherwise, and
    for a triangle that repeats a vertex.
    """
    fast = _compiled_edges(tris)
    if fast is not None:
        return fast
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]])
    e = np.sort(e, axis=1).astype(np.int64)
    base = np.int64(e.max() + 1) if len(e) else np.int64(1)
    key = e[:, 0] * base + e[:, 1]
    uniq, first, inv = np.unique(key, return_index=True, return_inverse=True)
    return e[first], inv.reshape(3, -1).T


def _compiled_edges(tris: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """:func:`triangle_edges` by the compiled edge table, or None (no kernel, no triangles, a repeated vertex).

    The table gives the edge of each *sorted* row opposite each position; the edge (x, y) of a row is the
    one opposite z, at z's rank in its row (the number of the row's entries below it).
    """
    t = np.asarray(tris)
    if _surface is None or t.ndim != 2 or t.shape[1] != 3 or len(t) == 0 or int(t.min()) < 0:
        return None
    t = np.ascontiguousarray(t, dtype=np.int64)
    top = int(t.max())
    if not dense_ids(top, t.size):
        return None
    out = _surface.edge_structure(top + 1, t)
    if out is None:
        return None
    edges = np.frombuffer(out[0], dtype=np.int64).reshape(-1, 2).copy()
    opposite = np.frombuffer(out[1], dtype=np.int64).reshape(-1, 3)
    x, y, z = t[:, 0], t[:, 1], t[:, 2]
    rank = [(c > a).astype(np.int64) + (c > b) for c, a, b in ((z, x, y), (x, y, z), (y, x, z))]
    rows = np.arange(len(t))
    return edges, np.stack([opposite[rows, r] for r in rank], axis=1)
