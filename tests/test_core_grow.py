"""The walk's refusal of handles across undersampling gaps, on flat grids checked by hand."""

import numpy as np

from crustview.core.robust.grow import Grower


def grid(n):
    """An n x n grid of points in the plane z = 0 and its 2 (n-1)^2 triangles."""
    ij = np.array([(i, j) for i in range(n) for j in range(n)], float)
    pts = np.column_stack([ij, np.zeros(len(ij))])
    tris = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            tris += [[a, b, c], [a, c, d]]
    return pts, np.sort(np.array(tris), axis=1)


def grown(pts, tris, keep):
    """A Grower whose grown complex is ``tris[keep]``."""
    f = len(tris)
    gr = Grower(pts, tris, np.zeros(f), np.zeros(f, np.int8))
    ids = np.flatnonzero(keep)
    gr.add_bulk(ids, np.ones(len(ids), np.int64), "seed-core")
    return gr


def boundary_facet(gr, u, v):
    return int(np.flatnonzero((gr.facets == sorted((u, v))).all(axis=1))[0])


def test_a_glue_onto_a_small_hole_is_a_gap_handle_and_one_along_the_same_rim_is_not():
    n = 20
    pts, tris = grid(n)
    centre = 10 * n + 10
    gr = grown(pts, tris, ~(tris == centre).any(axis=1))  # a hexagonal hole of 6 edges at the centre
    outer = boundary_facet(gr, 0, 1)  # on the grid's rim (76 edges: far beyond fill-hole's size)
    on_hole = centre + 1  # a vertex of the hexagon
    assert gr.count[outer] == 1 and gr.vfront[on_hole] == 2
    assert gr.makes_gap_handle(outer, on_hole)  # rim to hole: a handle across a gap fill-hole closes
    assert not gr.makes_gap_handle(outer, n - 1)  # rim to rim: the move only splits the rim
    hexagon = gr.boundary_component(on_hole, cap=50)
    assert hexagon[1] and len(hexagon[0]) == 6


def test_a_glue_between_two_large_rims_is_left_to_the_walk():
    # a frame: 24 x 24 grid without its 14 x 14 middle; both rims have more than 50 edges, so
    # joining them is a real seam (as on a noisy torus), not a gap
    n = 24
    pts, tris = grid(n)
    ij = pts[:, :2]
    middle = ((ij >= 5) & (ij <= 18)).all(axis=1)
    gr = grown(pts, tris, ~middle[tris].all(axis=1))
    outer = boundary_facet(gr, 0, 1)
    inner = 5 * n + 5
    assert gr.vfront[inner] == 2 and not gr.boundary_component(inner, cap=50)[1]
    assert not gr.makes_gap_handle(outer, inner)


def test_a_glue_between_two_pieces_is_no_handle():
    n = 12
    pts, tris = grid(n)
    left = (pts[tris][:, :, 0] <= 4).all(axis=1)
    right = (pts[tris][:, :, 0] >= 6).all(axis=1)
    gr = grown(pts, tris, left | right)
    edge = boundary_facet(gr, 4 * n, 4 * n + 1)  # on the left piece's right rim
    assert not gr.makes_gap_handle(edge, 6 * n + 3)  # a vertex of the right piece
