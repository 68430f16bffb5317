"""The manifold core of T_S: the part of the candidates that the growth can take at once.

The robust extension (:mod:`crustview.core.robust.driver`) grows M_S one Delaunay
face at a time, cheapest first.  Where the faces
of T_S are the cheapest candidates on both sides of every shared face, that
walk has no choice to make: whichever side it arrives from, it takes the
face of T_S.  Thin scans have T_S non-manifold at a fifth of its edges; there
the two cheapest faces are the walk's choice as well, so they join the
core.  The robust extension seeds the growth with all such faces in one
step (rule ``seed-core``) and walks only where a choice is left.

A face sigma of T_S is in the core when

* it is small enough to be grown at all (size ratio at most
  :data:`~crustview.core.robust.grow.SIZE_MAX`);
* at each of its (d-1)-faces tau, it and one other simplex of T_S are the
  two cheapest Delaunay faces at tau in the walk's order, both strictly
  cheaper than every other face there (other faces of T_S included: where T_S
  is not a manifold, this is the choice the walk would make), and the two
  meet at phi > pi/2 (not sharp in the sense of the paper's line 2);
* none of its vertices is pinched: the core simplices at each vertex form
  one fan (this repeats until no pinch is left);
* it lies in the largest component of what is left;
* in codimension 1, that component is orientable.  Where it is a Moebius
  band, the faces at the edges where a spanning tree's orientations clash
  are cut out and the above repeats (at most :data:`MOEBIUS_CUTS` times).
"""

from __future__ import annotations

import numpy as np

from ..analysis.topology import graph_components

#: Rounds of cutting a non-orientable core (codimension 1) before giving it up.
MOEBIUS_CUTS = 8


def manifold_core(
    faces: np.ndarray,
    facet_of: np.ndarray,
    u: np.ndarray,
    in_ts: np.ndarray,
    fits: np.ndarray,
    cost: np.ndarray,
    cos_limit: float,
    orientable: bool,
    by_facet: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
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
    # every incidence, grouped by facet (stable: by face id within a facet)
    fac = facet_of.ravel()
    by_facet = np.argsort(fac, kind="stable") if by_facet is None else by_facet
    own_s, fac_s = by_facet // dp1, fac[by_facet]
    starts = np.concatenate([[0], np.cumsum(np.bincount(fac, minlength=n_facets))[:-1]])
    # the two cheapest faces that fit at each facet, both strictly below any other
    c = np.where(fits[own_s], cost[own_s], np.inf)
    at1, n1 = _minima(c, starts, fac_s)
    c[at1] = np.inf
    at2, n2 = _minima(c, starts, fac_s)
    c[at2] = np.inf
    rest = np.minimum.reduceat(c, starts)
    low2 = np.full(n_facets, np.inf)
    low2[fac_s[at2]] = cost[own_s[at2]]
    # a tie of two at the minimum is a pair too, but not a tie at the second place
    single = (n1 == 1) & (n2 == 1) & (low2 < rest)
    pair_facet = (n1 == 2) | single
    member = np.zeros(len(fac), dtype=bool)
    member[at1] = pair_facet[fac_s[at1]]
    member[at2] = single[fac_s[at2]]
    pos = np.flatnonzero(member)  # two consecutive positions per pair facet
    s1, s2 = own_s[pos[0::2]], own_s[pos[1::2]]
    g12 = fac_s[pos[0::2]]
    good = np.zeros(n_facets, dtype=bool)
    good[g12] = in_ts[s1] & in_ts[s2]
    # flatness of the pair (not sharp in the sense of the paper's line 2)
    a1 = np.argmax(facet_of[s1] == g12[:, None], axis=1)
    a2 = np.argmax(facet_of[s2] == g12[:, None], axis=1)
    cos = np.einsum("ik,ik->i", u[s1, a1], u[s2, a2])
    good[g12[cos >= cos_limit]] = False
    pick = good[g12]
    member[pos] = np.repeat(pick, 2)
    # a face is in the core when it is one of a good pair at each of its facets
    inc_ok = np.zeros(len(fac), dtype=bool)
    inc_ok[by_facet] = member
    ok = in_ts & fits & inc_ok.reshape(f, dp1).all(axis=1)
    s1, s2, a1, a2 = s1[pick], s2[pick], a1[pick], a2[pick]
    sign_all = np.where((a1 + a2) % 2 == 1, 1, -1)  # across each pair: o2 = sign * o1
    for _ in range(MOEBIUS_CUTS + 1):
        ok = _unpinched(faces, ok, s1, s2)
        # one component only: other sheets would be joined to it only by gluing
        # moves, which the walk defers (they can form handles)
        pair = ok[s1] & ok[s2]
        edges = np.stack([s1[pair], s2[pair]], axis=1)
        _, labels = graph_components(f, edges)
        if not ok.any():
            break
        ok &= labels == np.bincount(labels[ok]).argmax()
        ids = np.flatnonzero(ok)
        sign = sign_all[pair]
        orient = _orient(f, int(ids[0]), edges, sign)
        if not orientable:
            return ids, orient[ids]
        inside = ok[edges[:, 0]]
        clash = inside & (orient[edges[:, 1]] != sign * orient[edges[:, 0]])
        if not clash.any():
            return ids, orient[ids]
        # a Moebius band: cut it where the spanning tree's orientations meet
        ok[edges[clash].ravel()] = False
    return np.empty(0, np.int64), np.empty(0, np.int64)  # left to the walk


def _unpinched(faces: np.ndarray, ok: np.ndarray, s1: np.ndarray, s2: np.ndarray) -> np.ndarray:
    """``ok`` without the faces at pinched vertices, repeated while that uncovers new pinches.

    Removing the faces at a pinched vertex changes only the stars of their
    own vertices, so after the first round only those vertices are looked at.
    """
    only = None
    for _ in range(16):  # each round can only uncover pinches next to the last ones
        pinched = _pinched_vertices(faces, ok, s1, s2, only)
        if len(pinched) == 0:
            break
        bad = np.zeros(int(faces.max()) + 1, dtype=bool)
        bad[pinched] = True
        drop = ok & bad[faces].any(axis=1)
        ok = ok & ~drop
        only = np.zeros(len(bad), dtype=bool)
        only[faces[drop].ravel()] = True
    return ok


def _minima(c: np.ndarray, starts: np.ndarray, group: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions where each group attains its finite minimum of ``c``, and how many per group.

    ``c`` is laid out group by group, group ``i`` starting at ``starts[i]``;
    ``group`` is the group of each position.
    """
    low = np.minimum.reduceat(c, starts)
    at = np.flatnonzero((c == low[group]) & np.isfinite(c))
    return at, np.bincount(group[at], minlength=len(starts))


def _pinched_vertices(
    faces: np.ndarray, ok: np.ndarray, s1: np.ndarray, s2: np.ndarray, only: np.ndarray | None = None
) -> np.ndarray:
    """Vertices whose star in the selected faces is more than one fan.

    ``only`` (a boolean mask over the vertices) restricts the test to those
    vertices, and the work to their stars.
    """
    if only is not None:
        ok = ok & only[faces].any(axis=1)
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
    pinched = np.flatnonzero(np.bincount(pairs // (int(labels.max()) + 1)) > 1)
    return pinched if only is None else pinched[only[pinched]]


def _orient(f: int, root: int, edges: np.ndarray, sign: np.ndarray) -> np.ndarray:
    """Orientations over a spanning tree of the root's component of the dual graph.

    ``sign[e]`` relates the orientations across dual edge e: ``o2 = sign * o1``
    (the rule of :meth:`~crustview.core.robust.grow.Grower._induced_orientation`).
    The orientation of a simplex is the product of the signs on its tree path
    to the root, found by pointer doubling.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import breadth_first_order

    code = np.where(sign > 0, 1, 2)  # stored values must be non-zero
    graph = coo_matrix(
        (
            np.concatenate([code, code]),
            (np.concatenate([edges[:, 0], edges[:, 1]]), np.concatenate([edges[:, 1], edges[:, 0]])),
        ),
        shape=(f, f),
    ).tocsr()
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
