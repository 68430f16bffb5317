"""A short basis of the loops of a triangulated surface (its first Z/2 homology).

Loops through the roots of shortest-path trees -- a tree path, one non-tree
edge, a tree path back -- are taken shortest first while they are independent
in homology; a tree-cotree decomposition (Eppstein 2003) gives every edge its
cohomology class as a bit mask, so independence is Gaussian elimination over
GF(2).  With every vertex a root this is the greedy shortest basis of Erickson
and Whittlesey (2005); :data:`ROOTS` roots per component, spread by
farthest-point sampling, keep it fast, so a loop's length is an upper bound of
the shortest loop of its class.  Used by :mod:`.features` for handles.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import connected_components, dijkstra, minimum_spanning_tree

from ..util.parallel import run_in_order, start_in_background
from ..util.vectors import SEQUENTIAL_SUM, edge_lengths
from .cotree import bfs_forest, edge_triangles, may_have_loops, triangle_edges, up_edges
from .necks import _reduce

try:
    from . import _paths
except ImportError:  # pragma: no cover - the extension is optional
    _paths = None

#: Shortest-path-tree roots per component for the loop basis (more: shorter loops, slower).
ROOTS = 12
#: Basis loops are not searched above this first Betti number.
MAX_LOOPS = 256
#: Vertices from which the spread roots' trees run beside the tree-cotree split and the roots' loops on both
#: cores (below, in line: starting threads costs more than they save).  A scheduling choice, not part of the
#: result, which is the same either way; measured in docs/history.md (issue 21, fourteenth round).
PARALLEL_MIN = 50_000


def short_basis(
    points: np.ndarray,
    tris: np.ndarray,
    edges: np.ndarray,
    tri_edges: np.ndarray,
    count: np.ndarray,
    n: int,
    local: np.ndarray | None = None,
    surface: int | None = None,
    cocycles: dict | None = None,
    cocycles_only: bool = False,
) -> list[tuple[np.ndarray, float]] | int:
    """A short Z/2 homology basis of the closed part of a triangulated surface.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    tris : ndarray of shape (t, 3)
    edges : ndarray of shape (e, 2)
        The triangles' unique edges (sorted rows).
    tri_edges : ndarray of shape (t, 3)
        Each triangle's edge ids.
    count : ndarray of shape (e,)
        Triangles per edge (boundary edges, count 1, are cut).
    n : int
        Number of points.
    local : ndarray of shape (n,), optional
        A search radius per vertex.  Besides the spread roots, every vertex of
        a leftover edge of the tree-cotree decomposition (one per basis
        element, on its handle) is a root, searched only this far: a short
        loop far from the spread roots is found there, at the cost of a
        small search.
    surface : int, optional
        Only vertices below this index are spread roots (:func:`capped` appends each hole's apex after the
        surface's points; an apex root's loops all pass through a cap).
    cocycles : dict, optional
        Filled with what :func:`.necks.walk_class` needs to tell the class of any closed walk: ``mask`` (every
        edge's cohomology class, a bit per basis element), ``edge_ids`` (vertex pairs to edge ids) and
        ``graph`` (the edge graph, weighted by length).
    cocycles_only : bool
        Fill ``cocycles`` and return an empty list: the loops are not searched (the cocycles come from the
        tree-cotree split alone, before the search, so they are the same either way).

    Returns
    -------
    list of (vertices, length), or int
        One loop per basis element, its vertices in order and its length; the
        number of independent loops instead when it exceeds :data:`MAX_LOOPS`.
    """
    # only edges with exactly two triangles carry the dual graph; boundary edges are cut
    inner = count == 2
    length = edge_lengths(points, edges)
    g = coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    g = g + g.T
    ncomp, label = connected_components(g, directed=False)
    used = np.zeros(n, bool)
    used[edges.ravel()] = True
    # primal spanning forest: shortest-path tree from one root per component
    roots0 = [int(np.nonzero(used & (label == c))[0][0]) for c in np.unique(label[used])]
    in_tree = np.zeros(len(edges), bool)
    key = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(key)
    skey = key[order]

    def edge_ids(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        return order[np.searchsorted(skey, lo * n + hi)]

    comps = np.unique(label[used])
    spread_roots = [] if cocycles_only else [_spread_roots(points, used & (label == c), surface) for c in comps]
    # the spread roots' trees need only the graph: the largest component's, when it has PARALLEL_MIN vertices
    # and may have loops, are searched on other threads (the compiled search releases the GIL) while the
    # tree-cotree split below runs; the others in line, one component at a time; the same arrays either way
    sizes = np.bincount(label[used], minlength=ncomp)
    big = int(comps[np.argmax(sizes[comps])]) if len(comps) else -1
    parallel = (
        not cocycles_only and big >= 0 and sizes[big] >= PARALLEL_MIN and may_have_loops(tris, count, used, len(comps))
    )
    trees = (
        start_in_background(shortest_path_trees, g, spread_roots[int(np.searchsorted(comps, big))])
        if parallel
        else None
    )
    dist0, pred0, _ = dijkstra(g, indices=roots0, return_predecessors=True, min_only=True)
    pred_ms = pred0
    child = np.nonzero((pred_ms >= 0) & used)[0]
    in_tree[edge_ids(child, pred_ms[child])] = True
    # dual graph over triangles through inner non-tree edges: spanning forest (BFS)
    tcount = len(tris)
    e_tris = edge_triangles(tri_edges, len(edges))
    dual_ok = inner & ~in_tree
    de = np.nonzero(dual_ok)[0]
    pair = (e_tris[de, 0], e_tris[de, 1])
    if surface is not None and (edges >= surface).any():
        # the caps' edges into the cotree first: a cap is a fan, so all its edges but the tree's one join
        # its triangles without a cycle, and then no cap edge is left over, and no leftover edge's loop
        # (root, tree path, the edge, tree path) passes an apex, a leaf of the shortest-path tree (a
        # noisy plastic vase had a handle whose only loop found ran through a cap)
        weight = np.where((edges[de] >= surface).any(axis=1), 1.0, 2.0)
        mst = minimum_spanning_tree(coo_matrix((weight, pair), shape=(tcount, tcount)).tocsr()).tocoo()
        tparent, tdepth = bfs_forest(tcount, mst.row, mst.col)
    else:
        tparent, tdepth = bfs_forest(tcount, *pair)
    tri_up_edge = up_edges(tris, edges, tri_edges, tparent, de, pair)
    cotree = np.zeros(len(edges), bool)
    cotree[tri_up_edge[tparent >= 0]] = True
    left = np.nonzero(inner & ~in_tree & ~cotree)[0]
    if len(left) == 0:
        return []
    if len(left) > MAX_LOOPS:
        return int(len(left))
    # cocycle of each leftover edge: the dual path between its two triangles, plus itself
    words = (len(left) + 63) // 64
    mask = np.zeros((len(edges), words), np.uint64)
    for j, e in enumerate(left):
        a, b = int(e_tris[e, 0]), int(e_tris[e, 1])
        bit = np.uint64(1) << np.uint64(j % 64)
        w = j // 64
        mask[e, w] ^= bit
        while a != b:
            if tdepth[a] >= tdepth[b]:
                mask[tri_up_edge[a], w] ^= bit
                a = int(tparent[a])
            else:
                mask[tri_up_edge[b], w] ^= bit
                b = int(tparent[b])
    # candidate loops from several roots per component; the leftover edges' own loops through
    # the first tree always complete the basis
    # the few edges on the leftover edges' dual paths are the only ones with a nonzero mask
    hot = np.flatnonzero(mask.any(axis=1))
    marked, marked_mask = edges[hot], mask[hot]
    if cocycles is not None:
        cocycles.update(mask=mask, edge_ids=edge_ids, graph=g)
        if cocycles_only:
            return []
    cand_len, cand_mask, cand_info = [], [], []
    spread_pred: dict[int, np.ndarray] = {}
    pm0 = _path_masks(pred0, marked, marked_mask)
    a0, b0 = edges[left, 0], edges[left, 1]
    cand_len.append(dist0[a0] + length[left] + dist0[b0])
    cand_mask.append(pm0[a0] ^ pm0[b0] ^ mask[left])
    cand_info.extend((-1, -1, int(x), int(y)) for x, y in zip(a0, b0))
    for c, roots in zip(comps, spread_roots):
        dist, pred = trees.result() if parallel and c == big else shortest_path_trees(g, roots)
        # each row is its own single-source search: the chosen loops are walked on these trees below
        spread_pred.update((int(r), pred[ri]) for ri, r in enumerate(roots))
        sel_c = np.nonzero(inner & (label[edges[:, 0]] == c))[0]  # the same for every root
        edges_c = (sel_c, edges[sel_c, 0], edges[sel_c, 1], mask[sel_c])
        tasks = [(pred[ri], dist[ri], marked, marked_mask, edges_c, length, 8 * len(left)) for ri in range(len(roots))]
        # the largest component's roots on both cores (numpy's gathers and the compiled XOR release the
        # GIL), the results in root order either way
        for ri, found in enumerate(run_in_order(_root_loops, tasks, None if parallel and c == big else 1)):
            if found is not None:
                cand_len.append(found[0])
                cand_mask.append(found[1])
                cand_info.extend((ri, int(roots[ri]), int(x), int(y)) for x, y in zip(found[2], found[3]))
    if local is not None:
        lroots = np.unique(edges[left].ravel())
        for r in lroots.tolist():
            dist, pred = dijkstra(g, indices=[r], return_predecessors=True, limit=float(local[r]))
            dist, pred = dist[0], pred[0]
            reach = np.flatnonzero(np.isfinite(dist))
            pm = _path_masks(pred, marked, marked_mask)
            near = np.zeros(n, bool)
            near[reach] = True
            sel = np.flatnonzero(inner & near[edges[:, 0]] & near[edges[:, 1]])
            a, b = edges[sel, 0], edges[sel, 1]
            tree_edge = (pred[a] == b) | (pred[b] == a)
            sel, a, b = sel[~tree_edge], a[~tree_edge], b[~tree_edge]
            cls = pm[a] ^ pm[b] ^ mask[sel]
            nz = cls.any(axis=1)
            if not nz.any():
                continue
            lens = dist[a[nz]] + length[sel[nz]] + dist[b[nz]]
            keep = np.argsort(lens)[:4]
            cand_len.append(lens[keep])
            cand_mask.append(cls[nz][keep])
            cand_info.extend((-2, int(r), int(x), int(y)) for x, y in zip(a[nz][keep], b[nz][keep]))
    if not cand_len:
        return []
    L = np.concatenate(cand_len)
    M = np.concatenate(cand_mask)
    order_c = np.argsort(L, kind="stable")
    chosen = _independent(M, order_c, len(left))
    result = []
    # reconstruct each chosen loop's vertices
    all_pred = {}
    for i in chosen:
        ri, r, a, b = cand_info[i]
        if r < 0:
            pr = pred0
        else:
            if r not in all_pred:
                found = spread_pred.get(r) if ri >= 0 else None
                all_pred[r] = found if found is not None else dijkstra(g, indices=[r], return_predecessors=True)[1][0]
            pr = all_pred[r]
        loop = _walk(pr, a)[::-1] + _walk(pr, b)
        result.append((np.array(loop, np.int64), float(L[i])))
    return result


def no_loops(tris: np.ndarray, edges: np.ndarray, tri_edges: np.ndarray, count: np.ndarray, n: int) -> bool:
    """Whether a complex whose every edge has two triangles has b1 = 0 (Z/2): then it has no handle.

    Euler-Poincare over Z/2: V - E + F = b0 - b1 + b2.  With two triangles at
    every edge, the 2-cycles are the unions of the pieces that triangles form
    across edges, so b2 is their number, and b1 = b0 + b2 - (V - E + F).  Most
    scans are spheres: their loop basis, the features' costliest part, is then
    not searched for.  False for any other complex (it is searched as before).
    """
    if len(count) == 0 or not (count == 2).all():
        return False
    used = np.flatnonzero(np.bincount(tris.ravel(), minlength=n))
    chi = len(used) - len(edges) + len(tris)
    if chi <= 0:  # b1 = b0 + b2 - chi > 0: every genus >= 1 surface, no component count needed
        return False
    _, b0_label = connected_components(
        coo_matrix((np.ones(len(edges), np.int8), (edges[:, 0], edges[:, 1])), shape=(n, n)), directed=False
    )
    b0 = len(np.unique(b0_label[used]))
    # triangles across each edge: the edge's two triangles, paired
    owner = np.argsort(tri_edges.ravel(), kind="stable") // 3
    t = len(tris)
    b2, _ = connected_components(coo_matrix((np.ones(len(edges), np.int8), (owner[0::2], owner[1::2])), shape=(t, t)))
    return b0 + b2 - chi == 0


def _independent(masks: np.ndarray, order: np.ndarray, rank: int) -> list[int]:
    """The candidates, in ``order``, that are independent of those before them over Z/2, up to ``rank`` of them.

    Gaussian elimination with each class as one Python integer (bit j of word w is bit 64 w + j): a row
    reduced by the echelon basis (pivot, its highest bit, to row) is zero exactly when it is in the span of
    the rows taken before it.  Which rows are taken does not depend on how a row is reduced, only on the
    span, so this is the same choice as a reduction word by word, at a few XORs of machine words per
    pivot instead of a numpy call per basis row (the gears at 0.3 h: 16,000 candidates against up to 254
    rows).
    """
    le = np.ascontiguousarray(masks, dtype="<u8")
    echelon: dict[int, int] = {}
    chosen: list[int] = []
    for i in order.tolist():
        x = _reduce(int.from_bytes(le[i].tobytes(), "little"), echelon)
        if not x:
            continue
        echelon[x.bit_length() - 1] = x
        chosen.append(i)
        if len(chosen) == rank:
            break
    return chosen


def shortest_path_trees(g: csr_matrix, roots: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The trees of scipy's ``dijkstra(g, indices=roots, return_predecessors=True)``, the roots on two threads.

    Parameters
    ----------
    g : csr_matrix of shape (n, n)
        Non-negative edge lengths.
    roots : list of int

    Returns
    -------
    dist : ndarray of shape (len(roots), n)
    pred : ndarray of shape (len(roots), n) of int32
        scipy's arrays.  The compiled search (``_paths.cpp``) gives them
        wherever no two nodes are at the same distance from the root (then
        the order of the search, and so every tree, is fixed); a root with
        such a tie is searched by scipy.
    """
    weights = np.ascontiguousarray(g.data, dtype=np.float64)
    compiled = _paths is not None and g.indptr.dtype == g.indices.dtype == np.int32 and len(roots) > 0
    if not compiled or not (weights >= 0).all():  # NaN or negative lengths: scipy's own answer
        return dijkstra(g, indices=roots, return_predecessors=True)
    n = g.shape[0]
    raw_dist, raw_pred, ties = _paths.shortest_paths(
        np.ascontiguousarray(g.indptr), np.ascontiguousarray(g.indices), weights, np.asarray(roots, np.int64), 2
    )
    dist = np.frombuffer(raw_dist, dtype=np.float64).reshape(len(roots), n)  # writable: bytearrays, no copy
    pred = np.frombuffer(raw_pred, dtype=np.int32).reshape(len(roots), n)
    for i in np.flatnonzero(np.frombuffer(ties, dtype=np.uint8)).tolist():
        d1, p1 = dijkstra(g, indices=[roots[i]], return_predecessors=True)
        dist[i], pred[i] = d1[0], p1[0]
    return dist, pred


def _root_loops(task: tuple) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """One root's shortest loops of a nonzero class: (lengths, classes, a, b) of their non-tree edges (a, b).

    ``task`` is (pred, dist, marked, marked_mask, (sel, a, b, mask) of the component's inner edges,
    edge lengths, how many loops); None when no edge closes a loop of a nonzero class.
    """
    pred, dist, marked, marked_mask, (sel_c, a_c, b_c, mask_c), length, limit = task
    pm = _path_masks(pred, marked, marked_mask)
    # a tree edge's class is 0 (pm of the child = pm of the parent ^ the edge's mask), so the
    # nonzero classes are those of non-tree edges without removing the tree edges first
    cls = pm[a_c] ^ pm[b_c] ^ mask_c
    nz = np.flatnonzero(cls.any(axis=1))
    if len(nz) == 0:
        return None
    sel, a, b = sel_c[nz], a_c[nz], b_c[nz]
    L = dist[a] + length[sel] + dist[b]
    keep = np.argsort(L)[:limit]
    return L[keep], cls[nz][keep], a[keep], b[keep]


def _spread_roots(points: np.ndarray, member: np.ndarray, surface: int | None) -> list[int]:
    """A component's :data:`ROOTS` spread roots (its vertices where ``member``, below ``surface`` if given)."""
    vs = np.nonzero(member)[0]
    if surface is not None:
        vs = vs[vs < surface]
    return _spread(points, vs, ROOTS)


def _spread(points: np.ndarray, vs: np.ndarray, k: int) -> list[int]:
    """Up to k vertices of vs spread by farthest-point sampling.

    Each distance is ``np.linalg.norm(p - p[j], axis=1)``'s, bit for bit: for float64 points of fewer than
    :data:`~crustview.core.util.vectors.SEQUENTIAL_SUM` coordinates, the squares of the coordinate
    differences added in numpy's order (a short row from its first entry on) and the square root, over
    contiguous coordinate columns in place (0.14 -> 0.02 s for 300,000 vertices); other points by numpy.
    """
    p = np.asarray(points)[vs]
    if p.dtype != np.float64 or p.ndim != 2 or not 1 <= p.shape[1] < SEQUENTIAL_SUM:
        return _spread_numpy(p, vs, k)
    cols = np.ascontiguousarray(p.T)
    chosen = [0]
    dist = _distances_to(cols, 0)
    for _ in range(min(k, len(vs)) - 1):
        j = int(np.argmax(dist))
        if dist[j] == 0:
            break
        chosen.append(j)
        np.minimum(dist, _distances_to(cols, j), out=dist)
    return [int(vs[j]) for j in chosen]


def _distances_to(cols: np.ndarray, j: int) -> np.ndarray:
    """Distances from point j to every point, given as contiguous coordinate columns (k, n), k < 8.

    ``np.linalg.norm(p - p[j], axis=1)`` bit for bit: the squared differences added from the first
    coordinate on, then the square root.
    """
    out = cols[0] - cols[0, j]
    out *= out
    for c in cols[1:]:
        diff = c - c[j]
        diff *= diff
        out += diff
    return np.sqrt(out, out=out)


def _spread_numpy(p: np.ndarray, vs: np.ndarray, k: int) -> list[int]:
    """:func:`_spread` by ``np.linalg.norm`` (points of other dtypes, or of 8 and more coordinates)."""
    chosen = [0]
    dist = np.linalg.norm(p - p[0], axis=1)
    for _ in range(min(k, len(vs)) - 1):
        j = int(np.argmax(dist))
        if dist[j] == 0:
            break
        chosen.append(j)
        dist = np.minimum(dist, np.linalg.norm(p - p[j], axis=1))
    return [int(vs[j]) for j in chosen]


def _path_masks(pred: np.ndarray, marked: np.ndarray, marked_mask: np.ndarray) -> np.ndarray:
    """XOR of the edge masks along each vertex's tree path to the root.

    Parameters
    ----------
    pred : ndarray of shape (n,)
        The tree's predecessors (negative at roots and unreached vertices).
    marked : ndarray of shape (e, 2)
        The edges whose mask is not zero (every other edge adds nothing).
    marked_mask : ndarray of shape (e, words)
        Their masks.

    Returns
    -------
    ndarray of shape (n, words)
        Zero at roots and unreached vertices.

    A vertex whose tree edge is marked starts with that edge's mask; the
    XOR up to the root then comes from one walk per vertex in compiled code
    (``_paths.path_xor``, each vertex done once), or else from pointer
    doubling: after each pass ``acc[v]`` covers the path from ``v`` to
    ``anc[v]``, whose length doubles (log depth passes).  XOR is exact, so
    both equal a walk level by level.
    """
    n = len(pred)
    acc = np.zeros((n, marked_mask.shape[1]), np.uint64)
    u, v = marked[:, 0], marked[:, 1]
    up = pred[u] == v  # the tree edge of u
    acc[u[up]] = marked_mask[up]
    down = pred[v] == u
    acc[v[down]] = marked_mask[down]
    if _paths is not None and pred.dtype == np.int32:  # one walk per node instead of log(depth) passes (same XOR)
        words = acc.shape[1]
        return np.frombuffer(_paths.path_xor(pred, acc, words), dtype=np.uint64).reshape(n, words).copy()
    anc = np.where(pred >= 0, pred, np.arange(n))
    while True:
        nxt = anc[anc]
        if np.array_equal(nxt, anc):  # every ancestor is a root, whose own entry is 0
            return acc
        acc ^= acc[anc]
        anc = nxt


def _walk(pred: np.ndarray, v: int) -> list[int]:
    """Vertices from v up to the root of a predecessor array."""
    out = [v]
    while pred[v] >= 0:
        v = int(pred[v])
        out.append(v)
    return out


def capped(
    points: np.ndarray, tris: np.ndarray, edges: np.ndarray, tri_edges: np.ndarray, count: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """The surface with a cone over every hole's rim (:func:`.features._basis`); the surface itself when it has none.

    Returns the points (each hole's apex appended, far beyond the surface's extent, so that every path
    through it is longer than any path on the surface), triangles, edges, triangle edges, triangles per
    edge and the number of points.
    """
    n = len(points)
    rim = edges[count == 1]
    if len(rim) == 0:
        return points, tris, edges, tri_edges, count, n
    g = coo_matrix((np.ones(len(rim), np.int8), (rim[:, 0], rim[:, 1])), shape=(n, n))
    _, label = connected_components(g, directed=False)
    holes, which = np.unique(label[rim[:, 0]], return_inverse=True)
    used = np.unique(tris)
    lo, hi = points[used].min(axis=0), points[used].max(axis=0)
    far = 1e3 * float(np.linalg.norm(hi - lo) + 1.0)
    apex = np.zeros((len(holes), points.shape[1]))
    apex[:, 0] = hi[0] + far * (1.0 + np.arange(len(holes)))
    pts = np.vstack([points, apex])
    cone = np.c_[rim, n + which]
    all_tris = np.vstack([tris, cone]).astype(np.int64)
    e, te = triangle_edges(all_tris)
    return pts, all_tris, e, te, np.bincount(te.ravel(), minlength=len(e)), n + len(holes)
