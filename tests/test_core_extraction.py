"""Algorithm 3 rules and the topology report on hand-made complexes."""

import itertools

import numpy as np
import pytest

from crustview.core.extraction import extract
from crustview.core.result import RULE_PRUNE, RULE_RESOLVE
from crustview.core.topology import analyse, boundary_rank_gf2, all_faces

OCTA_PTS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
OCTA = np.array([[a, b, c] for a in (0, 1) for b in (2, 3) for c in (4, 5)])


def grid_surface(nu, nv, klein=False):
    """Triangulated torus (or Klein bottle) on an nu x nv grid."""
    def vid(i, j):
        if klein and i == nu:  # glue with a flip
            return (0 * nv) + (-j) % nv
        return (i % nu) * nv + (j % nv)

    tris = []
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            tris += [[a, b, c], [a, c, d]]
    return np.array(tris)


def test_octahedron_is_kept_untouched():
    ext = extract(OCTA_PTS, OCTA)
    assert ext.steps == [] and ext.stopped == "closed"
    rep = analyse(ext.complex_at(0), 6, 2)
    assert rep.closed_manifold and rep.betti == (1, 0, 1) and rep.euler == 2 and rep.orientable


def test_regular_tetrahedron_is_sharp_everywhere():
    # dihedral angle arccos(1/3) = 70.5 deg < 90 deg: every edge is sharp
    pts = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float)
    tris = np.array(list(itertools.combinations(range(4), 3)))
    ext = extract(pts, tris)
    assert ext.stopped == "empty"
    first = ext.steps[0]
    assert first.rule == RULE_PRUNE and len(first.removed) == 2
    assert np.degrees(first.angle) == pytest.approx(np.degrees(np.arccos(1 / 3)))
    assert all(s.rule == RULE_PRUNE for s in ext.steps)


def test_single_triangle_is_pruned_as_boundary():
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    ext = extract(pts, np.array([[0, 1, 2]]))
    assert len(ext.steps) == 1 and ext.steps[0].rule == RULE_PRUNE
    assert np.isnan(ext.steps[0].angle) and ext.stopped == "empty"


def test_dangling_fin_is_pruned_and_octahedron_survives():
    pts = np.vstack([OCTA_PTS, [[1.5, 1.5, 0.0]]])
    tris = np.vstack([OCTA, [[0, 2, 6]]])
    ext = extract(pts, tris)
    assert sorted(map(tuple, ext.complex_at(ext.n_steps))) == sorted(map(tuple, np.sort(OCTA, axis=1)))
    assert [s.rule for s in ext.steps] == [RULE_PRUNE]
    assert ext.steps[0].removed == (8,)


def test_nonmanifold_edge_keeps_the_pair_whose_cascade_destroys_least():
    """Two octahedra A and B sharing the edge (+x, +y).

    On paper (u = unit vector from the edge to the opposite vertex):
    A's two triangles at the edge meet at arccos(-1/3) = 109.5 deg.  B is A
    mirrored through the plane x + y = 1 and stretched by 1.2 away from it,
    so its pair has u = (.6, .6, +-1)/|.|: 99.4 deg.  Mixed pairs are flatter
    (e.g. 160+ deg) but dropping one triangle of each octahedron lets the
    prune cascade eat both (16 simplices), while keeping A's or B's pair
    loses the other octahedron only (8).  Tie -> the flatter pair: A's.
    """
    a = OCTA_PTS
    n = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    refl = a - 2 * ((a @ n) - 1 / np.sqrt(2))[:, None] * n
    along = (refl @ n - 1 / np.sqrt(2))[:, None] * n
    b = refl + 0.2 * along
    pts = np.vstack([a, b])
    # vertices 0 (+x) and 2 (+y) lie on the mirror plane: B reuses them
    bmap = np.arange(6) + 6
    bmap[0], bmap[2] = 0, 2
    tris = np.vstack([OCTA, bmap[OCTA]])
    ext = extract(pts, tris)
    resolve = [s for s in ext.steps if s.rule == RULE_RESOLVE]
    assert len(resolve) == 1 and resolve[0].tau == (0, 2)
    assert resolve[0].kept == (0, 1)  # A's triangles (0,2,4) and (0,2,5)
    assert np.degrees(resolve[0].angle) == pytest.approx(np.degrees(np.arccos(-1 / 3)))
    final = ext.complex_at(ext.n_steps)
    assert sorted(map(tuple, final)) == sorted(map(tuple, np.sort(OCTA, axis=1)))
    assert ext.stopped == "closed"
    assert sum(len(s.removed) for s in ext.steps) == 8


def test_chord_of_a_hexagon_is_resolved_in_codimension_two():
    t = np.arange(6) * np.pi / 3
    pts = np.c_[np.cos(t), np.sin(t), np.zeros(6)]
    edges = np.array([[i, (i + 1) % 6] for i in range(6)] + [[0, 3]])
    ext = extract(pts, edges)
    assert [s.rule for s in ext.steps] == [RULE_RESOLVE]
    step = ext.steps[0]
    assert step.tau == (0,) and step.removed == (6,)
    assert np.degrees(step.angle) == pytest.approx(120.0)
    assert len(ext.complex_at(1)) == 6 and len(ext.complex_at(0)) == 7


def test_replay_is_exact_and_cheap():
    pts = np.vstack([OCTA_PTS, [[1.5, 1.5, 0.0]]])
    ext = extract(pts, np.vstack([OCTA, [[0, 2, 6]]]))
    assert ext.alive(0).all()
    assert ext.alive(1).sum() == 8
    assert ext.alive(99).sum() == 8  # clamps


@pytest.mark.parametrize(
    "tris, n, betti, euler, orient",
    [
        (grid_surface(4, 5), 20, (1, 2, 1), 0, True),
        (grid_surface(4, 5, klein=True), 20, (1, 2, 1), 0, False),
        # minimal 6-vertex RP^2: Z/2 Betti numbers (1, 1, 1)
        (np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 1],
                   [1, 2, 4], [2, 3, 5], [3, 4, 1], [4, 5, 2], [5, 1, 3]]), 6, (1, 1, 1), 1, False),
        (OCTA, 6, (1, 0, 1), 2, True),
    ],
)
def test_topology_of_known_surfaces(tris, n, betti, euler, orient):
    rep = analyse(tris, n, 2)
    assert rep.closed_manifold
    assert rep.betti == betti and rep.euler == euler and rep.orientable is orient
    # the shortcut for rank d_2 agrees with plain GF(2) elimination
    faces = all_faces(tris)
    assert len(faces[2]) - boundary_rank_gf2(faces[2], faces[1]) == betti[2]


def test_boundary_of_4_simplex_is_s3():
    tets = np.array(list(itertools.combinations(range(5), 4)))
    rep = analyse(tets, 5, 3)
    assert rep.closed_manifold and rep.betti == (1, 0, 0, 1) and rep.orientable


def test_two_circles_and_pinched_and_open_complexes():
    two = np.array([[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3]])
    rep = analyse(two, 6, 1)
    assert rep.closed_manifold and rep.betti == (2, 2) and rep.components == 2
    # two octahedra sharing one vertex: pseudo-manifold, pinched vertex
    pts_b = OCTA + 5
    pts_b[pts_b == 5] = 0
    rep = analyse(np.vstack([OCTA, pts_b]), 11, 2)
    assert not rep.closed_manifold and rep.singular_vertices == 1 and rep.boundary_faces == 0
    # a disc: boundary, unused samples reported
    rep = analyse(np.array([[0, 1, 2], [0, 2, 3]]), 6, 2)
    assert not rep.closed_manifold and rep.boundary_faces == 4 and rep.unused_samples == 2
    assert rep.betti == (1, 0, 0)
