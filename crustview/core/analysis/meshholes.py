"""The holes of a truth mesh that no sample of its vertices can show, and what the mesh says without them.

A file's mesh judges the reconstruction of its vertices (:mod:`.compare`), but only as far as a sample
can show.  A hole whose rim is shorter than :data:`~.features.LOOP_MIN` = 2 pi local sampling radii (a
missing triangle, a scanner's pinhole; two adjacent missing triangles already measure about 2 pi) is
below the resolution of an eps = 1 sample: no
reconstruction from the vertices alone can tell it from surface.  Each such hole may be closed or open in
a right answer, so the mesh admits every Betti vector it has with any set of them capped.

A rim is a piece of the boundary's edge graph; a piece of E edges on V vertices holds E - V + 1 holes
(two pinholes that share a vertex: two holes of three edges, not one of six), each measured on its own:
a shortest basis of the piece's cycles (a pinhole at a large opening's rim is its own three edges).  A
pinch (two sheets of the mesh at a vertex, :func:`pinched_vertices`) makes the mesh no manifold: it is
then not measured, and judges nothing.  Capping holes of one connected surface
lowers b1 by one each, except the last hole of a component, which closes it: b1 then stays and b2 gains
one (Z/2 coefficients, orientable or not: b1 = 1 - chi for a connected surface with boundary).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..result import TopologyReport

#: Rim pieces of more edges than this are not split into holes (each edge's cycle is a shortest-path
#: search on the piece): left whole, they count as no small hole, so the mesh judges as it stands.
MAX_PIECE = 400


@dataclass(frozen=True)
class UnresolvedHoles:
    """A mesh's holes below the resolution of a sample of its vertices.

    Attributes
    ----------
    count : int
        Rims shorter than LOOP_MIN local sampling radii.
    longest : float
        The longest of them, in local sampling radii.
    edges : int
        Their rim edges in all.
    betti : tuple of int
        The mesh's Z/2 Betti numbers with all of them capped.
    mesh_betti : tuple of int
        The mesh's own.
    closing : tuple of int
        For each component of the mesh all of whose holes are small, what closing all of them takes from
        b1 (its holes less one; b2 gains one), smallest first.
    most : int
        The most b1 can lose: every small hole closed but each component's last.
    """

    count: int
    longest: float
    edges: int
    betti: tuple[int, ...]
    mesh_betti: tuple[int, ...] = ()
    closing: tuple[int, ...] = ()
    most: int = 0

    def allows(self, betti: tuple[int, ...]) -> bool:
        """Whether ``betti`` are the mesh's with some of these holes closed.

        With y components closed (b2 up by y) and holes closed elsewhere one by one, b1 falls by anything
        from the y cheapest closings' sum up to :attr:`most` (each hole closed, or not, one at a time).
        """
        b = tuple(int(v) for v in betti)
        if b == self.betti:
            return True
        m = self.mesh_betti
        if len(b) != 3 or len(m) != 3 or b[0] != m[0]:
            return False
        x, y = m[1] - b[1], b[2] - m[2]
        return 0 <= y <= len(self.closing) and sum(self.closing[:y]) <= x <= self.most

    def words(self) -> str:
        """E.g. "1 hole the sample cannot show (a rim of 3 edges, 1.2 sampling radii around, under ...)"."""
        if self.count == 1:
            return (
                f"1 hole the sample cannot show (a rim of {self.edges} edges, {self.longest:.2g} sampling radii "
                f"around, under the 2 pi a sample resolves)"
            )
        return (
            f"{self.count} holes the sample cannot show (rims of {self.edges} edges in all, at most "
            f"{self.longest:.2g} sampling radii around, under the 2 pi a sample resolves)"
        )


def pinched_vertices(rows: np.ndarray, n: int) -> int:
    """How many vertices of a triangle mesh are where two sheets meet: no manifold, with or without boundary.

    Such a vertex has a fan of triangles closed around it and another fan there too.  Holes that touch at
    a vertex leave it two *open* fans, each ending at the holes' rims: one sheet with missing triangles, not
    a pinch (the topology report counts pinches on closed complexes only).
    """
    from .cotree import triangle_edges
    from .topology import graph_components

    f = len(rows)
    if f == 0:
        return 0
    edges, tri_edges = triangle_edges(rows)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    # corner t * 3 + p (vertex rows[t, p] of triangle t); corners of one vertex joined across the edges
    # at it that two triangles share: the fans
    flat = tri_edges.ravel()
    order = np.argsort(flat, kind="stable")
    shared = np.flatnonzero(count == 2)
    starts = np.searchsorted(flat[order], shared)
    t1, t2 = order[starts] // 3, order[starts + 1] // 3

    def corner(t: np.ndarray, v: np.ndarray) -> np.ndarray:
        return t * 3 + np.argmax(rows[t] == v[:, None], axis=1)

    u, w = edges[shared, 0], edges[shared, 1]
    links = np.concatenate([np.c_[corner(t1, u), corner(t2, u)], np.c_[corner(t1, w), corner(t2, w)]])
    _, fan = graph_components(3 * f, links)
    vert = rows.ravel()
    # a fan is open where an edge of one triangle only leaves its vertex
    rim = np.flatnonzero(count == 1)
    rs = np.searchsorted(flat[order], rim)
    tr = order[rs] // 3
    open_fan = np.zeros(fan.max() + 1, bool)
    open_fan[fan[corner(tr, edges[rim, 0])]] = True
    open_fan[fan[corner(tr, edges[rim, 1])]] = True
    pairs = np.unique(np.c_[vert, fan], axis=0)  # (vertex, fan) once each
    fans = np.bincount(pairs[:, 0], minlength=n)
    closed = np.bincount(pairs[:, 0], weights=~open_fan[pairs[:, 1]], minlength=n)
    return int(((fans >= 2) & (closed >= 1)).sum())


def _piece_holes(edge_ids: np.ndarray, ends: np.ndarray, length: np.ndarray, holes: int) -> list[np.ndarray]:
    """The holes of a rim piece of ``holes`` > 1 cycles: a shortest basis of its cycles (as ``edge_ids``).

    ``ends`` are the piece's edges (vertex pairs), ``length`` every rim edge's length.  Each edge's cycle
    is the edge and the shortest path between its ends without it; the shortest independent ones (over
    Z/2) are the holes: a pinhole touching a large opening is its own 3 edges, not an average with the
    opening (a reviewer's case).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    _, local = np.unique(ends, return_inverse=True)
    local = local.reshape(-1, 2)
    m, k = int(local.max()) + 1, len(edge_ids)
    w = length[edge_ids]
    which = {frozenset((int(a), int(b))): j for j, (a, b) in enumerate(local.tolist())}
    candidates = set()
    for i in range(k):
        keep = np.arange(k) != i
        g = coo_matrix((w[keep], (local[keep, 0], local[keep, 1])), shape=(m, m)).tocsr()
        dist, pred = dijkstra(g, directed=False, indices=int(local[i, 0]), return_predecessors=True)
        a, b = int(local[i, 0]), int(local[i, 1])
        if not np.isfinite(dist[b]):
            continue
        cyc, x = [i], b
        while x != a:  # parallel edges aside (a triangle mesh's rim has none), the path's edges by their ends
            y = int(pred[x])
            cyc.append(which[frozenset((x, y))])
            x = y
        candidates.add((float(dist[b] + w[i]), tuple(sorted(cyc))))
    basis: dict[int, int] = {}
    chosen: list[np.ndarray] = []
    for _, cyc in sorted(candidates):
        vec = sum(1 << j for j in cyc)
        while vec:
            top = vec.bit_length() - 1
            if top not in basis:
                basis[top] = vec
                chosen.append(edge_ids[list(cyc)])
                break
            vec ^= basis[top]
        if len(chosen) == holes:
            break
    return chosen


def unresolved_holes(points: np.ndarray, rows: np.ndarray, topology: TopologyReport) -> UnresolvedHoles | None:
    """:class:`UnresolvedHoles` of a triangle mesh that is a surface with boundary; None where it has none.

    Only a mesh without non-manifold edges is measured (its Betti numbers are a surface's).  The local
    sampling radius is :func:`~.radii.local_spacing`'s on the mesh (what the features measure on M_S).
    """
    from .cotree import triangle_edges
    from .features import LOOP_MIN
    from .radii import local_spacing
    from .topology import analyse, graph_components

    if rows.shape[1] != 3 or topology.boundary_faces == 0 or topology.nonmanifold_faces > 0:
        return None
    n = len(points)
    edges, tri_edges = triangle_edges(rows)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    rim = edges[count == 1]
    # the rims: pieces of the boundary's edge graph; a piece of E edges on V vertices holds E - V + 1 holes
    # (two pinholes that share a vertex: 6 edges, 5 vertices, 2 holes of 3 edges each)
    _, label = graph_components(n, rim)
    piece = label[rim[:, 0]]
    pieces, piece = np.unique(piece, return_inverse=True)
    n_edges = np.bincount(piece, minlength=len(pieces))
    on = np.zeros(n, bool)
    on[rim.ravel()] = True
    verts = np.flatnonzero(on)
    n_verts = np.bincount(np.searchsorted(pieces, label[verts]), minlength=len(pieces))
    holes = np.maximum(n_edges - n_verts + 1, 1)
    h = local_spacing(points, rows)
    length = np.linalg.norm(points[rim[:, 0]] - points[rim[:, 1]], axis=1)
    # every hole on its own: a piece that is one cycle is one hole; a piece of several, a shortest basis of
    # its cycles (up to MAX_PIECE edges; a larger piece, rare, is left whole, so it counts as no small hole)
    by_piece = np.argsort(piece, kind="stable")
    bounds = np.searchsorted(piece[by_piece], np.arange(len(pieces) + 1))
    hole_edges: list[np.ndarray] = []
    for q in range(len(pieces)):
        mine = by_piece[bounds[q] : bounds[q + 1]]
        if holes[q] == 1 or len(mine) > MAX_PIECE:
            hole_edges.append(mine)
        else:
            hole_edges.extend(_piece_holes(mine, rim[mine], length, int(holes[q])))
    sizes = np.array([length[e].sum() / np.median(h[np.unique(rim[e])]) for e in hole_edges])
    many = [len(e) > MAX_PIECE for e in hole_edges]
    small = np.flatnonzero((sizes < LOOP_MIN) & ~np.asarray(many, bool))
    if len(small) == 0:
        return None
    # every small hole with a cone of its own, for the Betti numbers with all of them closed
    cone = np.concatenate([np.c_[rim[hole_edges[i]], np.full(len(hole_edges[i]), n + j)] for j, i in enumerate(small)])
    closed = tuple(int(b) for b in analyse(np.vstack([rows, cone]).astype(np.int64), n + len(small), 2).betti)
    # what closing them can do, component by component of the mesh (see UnresolvedHoles.allows)
    _, comp = graph_components(n, edges)
    comp_of = np.array([comp[rim[e[0], 0]] for e in hole_edges])
    is_small = np.zeros(len(hole_edges), bool)
    is_small[small] = True
    all_holes = np.bincount(comp_of).astype(np.int64)
    tiny = np.bincount(comp_of, weights=is_small, minlength=len(all_holes)).astype(np.int64)
    with_holes = all_holes > 0
    most = int(np.minimum(tiny, all_holes - 1)[with_holes].sum())
    closable = with_holes & (tiny == all_holes)
    return UnresolvedHoles(
        count=len(small),
        longest=float(sizes[small].max()),
        edges=int(sum(len(hole_edges[i]) for i in small)),
        betti=closed,
        mesh_betti=tuple(int(b) for b in topology.betti),
        closing=tuple(int(c) for c in np.sort(all_holes[closable] - 1)),
        most=most,
    )
