"""The holes of a truth mesh that no sample of its vertices can show, and what the mesh says without them.

A file's mesh judges the reconstruction of its vertices (:mod:`.compare`), but only as far as a sample
can show.  A hole whose rim is shorter than :data:`~.features.LOOP_MIN` = 2 pi local sampling radii (a
missing triangle or two, a scanner's pinhole) is below the resolution of an eps = 1 sample: no
reconstruction from the vertices alone can tell it from surface.  Each such hole may be closed or open in
a right answer, so the mesh admits every Betti vector it has with any set of them capped.

A rim is a piece of the boundary's edge graph; a piece of E edges on V vertices holds E - V + 1 holes
(two pinholes that share a vertex: two holes of three edges, not one of six), each measured by the
piece's length over that count.  Capping holes of one connected surface
lowers b1 by one each, except the last hole of a component, which closes it: b1 then stays and b2 gains
one (Z/2 coefficients, orientable or not: b1 = 1 - chi for a connected surface with boundary).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..result import TopologyReport


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
    h_piece = np.bincount(np.searchsorted(pieces, label[verts]), weights=h[verts], minlength=len(pieces)) / n_verts
    size = np.bincount(piece, weights=length, minlength=len(pieces)) / holes / h_piece  # a hole's rim, on average
    small = np.flatnonzero(size < LOOP_MIN)
    if len(small) == 0:
        return None
    # every small piece with a cone of its own, for the Betti numbers with all of them closed
    mine = np.isin(piece, small)
    cone = np.c_[rim[mine], n + np.searchsorted(small, piece[mine])]
    closed = tuple(int(b) for b in analyse(np.vstack([rows, cone]).astype(np.int64), n + len(small), 2).betti)
    # what closing them can do, component by component of the mesh (see UnresolvedHoles.allows)
    _, comp = graph_components(n, edges)
    comp_of = comp[rim[np.unique(piece, return_index=True)[1], 0]]
    is_small = np.zeros(len(pieces), bool)
    is_small[small] = True
    all_holes = np.bincount(comp_of, weights=holes).astype(np.int64)
    tiny = np.bincount(comp_of, weights=holes * is_small, minlength=len(all_holes)).astype(np.int64)
    with_holes = all_holes > 0
    most = int(np.minimum(tiny, all_holes - 1)[with_holes].sum())
    closable = with_holes & (tiny == all_holes)
    return UnresolvedHoles(
        count=int(holes[small].sum()),
        longest=float(size[small].max()),
        edges=int(n_edges[small].sum()),
        betti=closed,
        mesh_betti=tuple(int(b) for b in topology.betti),
        closing=tuple(int(c) for c in np.sort(all_holes[closable] - 1)),
        most=most,
    )
