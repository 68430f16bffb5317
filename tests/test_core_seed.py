"""The manifold core of T_S (rule ``seed-core``) on complexes small enough to check by hand."""

import numpy as np
from test_core_extraction import grid_surface

from crustview.core.paper.facets import facet_structure
from crustview.core.robust.grow import COS_PAPER, Grower, unit_normals_to_facets
from crustview.core.robust.seed_core import manifold_core

OCTA_PTS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
OCTA = np.sort(np.array([[a, b, c] for a in (0, 1) for b in (2, 3) for c in (4, 5)]), axis=1)


def core_of(points, faces, in_ts=None, cost=None, cos_limit=COS_PAPER, orientable=True):
    faces = np.sort(faces, axis=1)
    _, facet_of, _, _ = facet_structure(faces)
    u = unit_normals_to_facets(points, faces)
    f = len(faces)
    in_ts = np.ones(f, bool) if in_ts is None else in_ts
    cost = np.ones(f) if cost is None else cost
    return manifold_core(faces, facet_of, u, in_ts, np.ones(f, bool), cost, cos_limit, orientable)


def oriented_edges(faces, ids, orient):
    """Directed edges of the core's triangles, each triangle turned by its orientation."""
    out = []
    for i, o in zip(ids, orient):
        a, b, c = faces[i] if o > 0 else faces[i][[1, 0, 2]]
        out += [(a, b), (b, c), (c, a)]
    return out


def test_closed_octahedron_is_its_own_core_and_consistently_oriented():
    ids, orient = core_of(OCTA_PTS, OCTA)
    assert ids.tolist() == list(range(8))
    edges = oriented_edges(OCTA, ids, orient)
    # consistent: every edge is run once in each direction
    assert len(set(edges)) == 12 * 2 and all((b, a) in edges for a, b in edges)


def test_a_fin_takes_the_faces_at_its_edge_out_of_the_core():
    # a ninth triangle on edge (0, 2): three faces of T_S there, so all three leave the core;
    # the star of vertex 0 (and of 2) in the rest is still one fan
    pts = np.vstack([OCTA_PTS, [[1.0, 1.0, 0.2]]])
    faces = np.vstack([OCTA, [[0, 2, 6]]])
    ids, _ = core_of(pts, faces)
    kept = {tuple(faces[i]) for i in ids}
    assert kept == {tuple(t) for t in OCTA.tolist() if not {0, 2} <= set(t)}
    assert len(kept) == 6


def test_a_cheaper_face_outside_t_s_leaves_the_choice_to_the_walk():
    pts = np.vstack([OCTA_PTS, [[1.0, 1.0, 0.2]]])
    faces = np.vstack([OCTA, [[0, 2, 6]]])
    in_ts = np.r_[np.ones(8, bool), False]
    expensive = core_of(pts, faces, in_ts=in_ts, cost=np.r_[np.ones(8), 5.0])[0]
    cheap = core_of(pts, faces, in_ts=in_ts, cost=np.r_[np.ones(8), 0.5])[0]
    assert len(expensive) == 8  # the walk would take the octahedron's faces at (0, 2) anyway
    assert len(cheap) == 6  # the cheaper fin could win there: those two are left to the walk


def test_sharp_pair_is_not_core():
    # squash the octahedron: vertices 4 and 5 close to the equator plane, so faces across
    # the equator edges meet at a sharp angle (phi < 90 deg) and every face has such an edge
    pts = OCTA_PTS.copy()
    pts[4, 2], pts[5, 2] = 0.2, -0.2
    ids, _ = core_of(pts, OCTA)
    assert len(ids) == 0


def test_pinched_vertex_and_a_second_sheet_are_left_to_the_walk():
    # two octahedra sharing vertex 0: its star is two fans, so the faces at 0 leave the core;
    # the two remaining caps are separate sheets and only the first-largest stays
    second = OCTA_PTS + [2.0, 0, 0]  # its vertex 1 is our vertex 0, (1, 0, 0)
    remap = np.array([6, 0, 7, 8, 9, 10])
    pts = np.vstack([OCTA_PTS, second[[0, 2, 3, 4, 5]]])
    faces = np.vstack([OCTA, np.sort(remap[OCTA], axis=1)])
    ids, _ = core_of(pts, faces)
    verts = set(faces[ids].ravel().tolist())
    assert len(ids) == 4 and (verts == {1, 2, 3, 4, 5} or verts == {6, 7, 8, 9, 10})


def test_non_orientable_core_is_cut_to_an_orientable_part_in_codimension_one_only():
    klein = np.sort(grid_surface(4, 5, klein=True), axis=1)
    pts = np.random.default_rng(0).normal(size=(20, 4))
    # flatness off (cos limit above 1): only the orientation decides
    ids, orient = core_of(pts, klein, cos_limit=2.0, orientable=True)
    assert 0 < len(ids) < len(klein)
    # what is left is consistently oriented: no directed edge is run twice
    edges = oriented_edges(klein, ids, orient)
    assert len(set(edges)) == len(edges)
    assert len(core_of(pts, klein, cos_limit=2.0, orientable=False)[0]) == len(klein)
    torus = np.sort(grid_surface(4, 5), axis=1)
    ids, orient = core_of(pts, torus, cos_limit=2.0, orientable=True)
    assert len(ids) == len(torus)
    edges = oriented_edges(torus, ids, orient)
    assert all((b, a) in edges for a, b in edges)


def test_the_two_cheapest_faces_at_a_non_manifold_edge_are_its_core_pair():
    # the fin on edge (0, 2) is in T_S too: three candidates there.  Costlier than the two
    # octahedron faces at that edge, it stays out and the whole octahedron is the core;
    # cheaper, it leaves a tie for second place, so the edge's three faces are left to the walk
    pts = np.vstack([OCTA_PTS, [[1.0, 1.0, 0.2]]])
    faces = np.vstack([OCTA, [[0, 2, 6]]])
    ids, _ = core_of(pts, faces, cost=np.r_[np.ones(8), 2.0])
    assert ids.tolist() == list(range(8))
    ids, _ = core_of(pts, faces, cost=np.r_[np.ones(8), 0.5])
    assert {tuple(faces[i]) for i in ids} == {tuple(t) for t in OCTA.tolist() if not {0, 2} <= set(t)}


def test_bulk_add_leaves_the_state_of_adding_one_by_one():
    faces = OCTA
    tier = np.zeros(8, np.int8)
    ids = np.array([0, 1, 2, 3, 4])  # part of the octahedron: a disc with a boundary
    one = Grower(OCTA_PTS, faces, np.zeros(8), tier)
    one.add(0, "seed", -1, 0.0)
    todo = [1, 2, 3, 4]
    while todo:  # add each across a facet it shares with what is there
        for f in todo:
            shared = [g for g in one._facets_of(f) if one.count[g] == 1]
            if shared:
                one.add(f, "grow", shared[0], 0.0)
                todo.remove(f)
                break
    bulk = Grower(OCTA_PTS, faces, np.zeros(8), tier)
    _, orient = core_of(OCTA_PTS, faces)
    bulk.add_bulk(ids, orient[ids] * orient[0], "seed-core")
    assert bulk.count == one.count and bulk.xor == one.xor
    assert bulk.vcount == one.vcount and bulk.vfront == one.vfront
    assert bytes(bulk.alive) == bytes(one.alive)
    assert bulk.orient == one.orient
    # the same pieces: two vertices share a root in one exactly when they do in the other
    verts = range(len(OCTA_PTS))
    assert [[bulk._find(a) == bulk._find(b) for b in verts] for a in verts] == [
        [one._find(a) == one._find(b) for b in verts] for a in verts
    ]
