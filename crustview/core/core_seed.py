"""The manifold core of T_S: the part of the candidates that the growth can take at once.

The robust extension (:mod:`crustview.core.robust`) grows M_S one Delaunay
face at a time, cheapest first.  Where T_S is already a manifold *and* its
faces are the cheapest candidates on both sides of every shared face, that
walk has no choice to make: whichever side it arrives from, it takes the
face of T_S.  The robust extension seeds the growth with all such faces in
one step (rule ``seed-core``) and walks only where a choice is left.

A face sigma of T_S is in the core when

* it is small enough to be grown at all (size ratio at most
  :data:`~crustview.core.grow.SIZE_MAX`);
* each of its (d-1)-faces tau lies in exactly one other simplex of T_S, the
  two meet at phi > pi/2 (not sharp in the sense of the paper's line 2),
  and the two are the cheapest of all Delaunay faces at tau in the walk's
  order;
* none of its vertices is pinched: the core simplices at each vertex form
  one fan (this repeats until no pinch is left);
* in codimension 1, its component of the core is orientable.
"""

from __future__ import annotations

import numpy as np

from .topology import graph_components


def manifold_core(faces: np.ndarray, facet_of: np.ndarray, u: np.ndarray, in_ts: np.ndarray,
                  fits: np.ndarray, cost: np.ndarray, cos_limit: float,
                  orientable: bool, by_facet: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Select the manifold core of T_S and orient it.

    Parameters
    ----------
    faces : ndarray of shape (f, d + 1)
        Sorted vertex rows of every face the walk may use.
    facet_of : ndarray of shape (f, d + 1)
        ``facet_of[i, a]``: id of the (d-1)-face of face i opposite vertex a.
    u : ndarray of shape (f, d + 1, k)
        Unit vectors from each (d-1)-face to the opposite vertex.
    in_ts, fits : ndarray of bool, shape (f,)
        Faces of T_S; faces small enough to be grown.
    cost : ndarray of shape (f,)
        The walk's priority of each face (smaller first).
    cos_limit : float
        A pair is flat enough when cos(phi) is below this.
    orientable : bool
        Codimension 1: drop core components that admit no orientation.
    by_facet : ndarray of int, optional
        ``argsort(facet_of.ravel(), kind="stable")`` when the caller has it.

    Returns
    -------
    ids : ndarray of int
        Face ids of the core, ascending.
    orient : ndarray of int
        +1/-1 per core face; adjacent core faces induce opposite
        orientations on their shared face where ``orientable``.
    """
    f, dp1 = faces.shape
    if f == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    n_facets = int(facet_of.max()) + 1
    ts = np.flatnonzero(in_ts)
    cnt = np.bincount(facet_of[ts].ravel(), minlength=n_facets)
    ok = in_ts & fits & (cnt[facet_of] == 2).all(axis=1)
    # every incidence, grouped by facet (stable: by face id within a facet)
    fac = facet_of.ravel()
    by_facet = np.argsort(fac, kind="stable") if by_facet is None else by_facet
    own_s, fac_s = by_facet // dp1, fac[by_facet]
    starts = np.concatenate([[0], np.cumsum(np.bincount(fac, minlength=n_facets))[:-1]])
    # the T_S pair of each facet of T_S-count 2 (consecutive once the others are filtered out)
    pair_entry = in_ts[own_s] & (cnt[fac_s] == 2)
    pairs = own_s[pair_entry].reshape(-1, 2)
    g12 = fac_s[pair_entry][::2]
    s1, s2 = pairs[:, 0], pairs[:, 1]
    # the pair must be the cheapest there: every other face that fits costs strictly more
    c_other = np.where(fits[own_s] & ~in_ts[own_s], cost[own_s], np.inf)
    cheapest_other = np.minimum.reduceat(c_other, starts)
    good = np.zeros(n_facets, dtype=bool)
    good[g12] = np.maximum(cost[s1], cost[s2]) < cheapest_other[g12]
    # flatness of the T_S pair at each facet of count 2
    a1 = np.argmax(facet_of[s1] == g12[:, None], axis=1)
    a2 = np.argmax(facet_of[s2] == g12[:, None], axis=1)
    cos = np.einsum("ik,ik->i", u[s1, a1], u[s2, a2])
    good[g12[cos >= cos_limit]] = False
    ok &= good[facet_of].all(axis=1)
    for _ in range(16):  # pinches: each round can only uncover pinches next to the last ones
        pinched = _pinched_vertices(faces, ok, s1, s2)
        if len(pinched) == 0:
            break
        bad = np.zeros(int(faces.max()) + 1, dtype=bool)
        bad[pinched] = True
        ok &= ~bad[faces].any(axis=1)
    # one component only: other sheets would be joined to it only by gluing
    # moves, which the walk defers (they can form handles)
    pair = ok[s1] & ok[s2]
    edges = np.stack([s1[pair], s2[pair]], axis=1)
    _, labels = graph_components(f, edges)
    if not ok.any():
        return np.empty(0, np.int64), np.empty(0, np.int64)
    ok &= labels == np.bincount(labels[ok]).argmax()
    ids = np.flatnonzero(ok)
    sign = np.where((a1[pair] + a2[pair]) % 2 == 1, 1, -1)  # o2 = sign * o1
    orient = _orient(f, int(ids[0]), edges, sign)
    if orientable and not (orient[edges[:, 1]] == sign * orient[edges[:, 0]])[ok[edges[:, 0]]].all():
        return np.empty(0, np.int64), np.empty(0, np.int64)  # a Moebius core: leave it to the walk
    return ids, orient[ids]


def _pinched_vertices(faces: np.ndarray, ok: np.ndarray, s1: np.ndarray, s2: np.ndarray) -> np.ndarray:
    """Vertices whose star in the selected faces is more than one fan."""
    sel = np.flatnonzero(ok)
    if len(sel) == 0:
        return np.empty(0, dtype=np.int64)
    dp1 = faces.shape[1]
    node = np.full(len(faces), -1, dtype=np.int64)
    node[sel] = np.arange(len(sel))
    pair = ok[s1] & ok[s2]
    p1, p2 = s1[pair], s2[pair]
    edges = [np.empty((0, 2), dtype=np.int64)]
    for a in range(dp1):  # vertex a of p1 is shared with p2 unless it is p1's apex
        v = faces[p1, a]
        hit = faces[p2] == v[:, None]
        shared = hit.any(axis=1)
        b = np.argmax(hit, axis=1)
        edges.append(np.stack([node[p1[shared]] * dp1 + a, node[p2[shared]] * dp1 + b[shared]], axis=1))
    _, labels = graph_components(len(sel) * dp1, np.concatenate(edges))
    vert = faces[sel].ravel()
    pairs = np.unique(vert * (int(labels.max()) + 1) + labels)  # one key per (vertex, fan)
    return np.flatnonzero(np.bincount(pairs // (int(labels.max()) + 1)) > 1)


def _orient(f: int, root: int, edges: np.ndarray, sign: np.ndarray) -> np.ndarray:
    """Orientations over a spanning tree of the root's component of the dual graph.

    ``sign[e]`` relates the orientations across dual edge e: ``o2 = sign * o1``
    (the rule of :meth:`~crustview.core.grow.Grower._induced_orientation`).
    The orientation of a simplex is the product of the signs on its tree path
    to the root, found by pointer doubling.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import breadth_first_order

    code = np.where(sign > 0, 1, 2)  # stored values must be non-zero
    graph = coo_matrix((np.concatenate([code, code]),
                        (np.concatenate([edges[:, 0], edges[:, 1]]), np.concatenate([edges[:, 1], edges[:, 0]]))),
                       shape=(f, f)).tocsr()
    reached, pred = breadth_first_order(graph, root, directed=False, return_predecessors=True)
    up = np.arange(f)
    up[reached] = np.where(pred[reached] < 0, reached, pred[reached])
    par = np.ones(f, dtype=np.int64)
    child = reached[pred[reached] >= 0]
    if len(child):
        par[child] = np.where(np.asarray(graph[child, up[child]]).ravel() == 1, 1, -1)
    while True:
        nxt = up[up]
        if np.array_equal(nxt, up):
            break
        par = par * par[up]
        up = nxt
    par = par * par[up]  # the last hop: up is the root, whose own sign is 1
    out = np.zeros(f, dtype=np.int64)
    out[reached] = par[reached]
    return out
