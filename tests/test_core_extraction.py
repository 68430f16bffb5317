"""Algorithm 3 rules and the topology report on hand-made complexes."""

import itertools

import numpy as np
import pytest

from crustview.core.analysis.topology import all_faces, analyse, boundary_rank_gf2
from crustview.core.paper.extraction import extract
from crustview.core.steps import RULE_PRUNE, RULE_RESOLVE

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


def teardrop_and_pentagon():
    """A big teardrop loop and a small regular pentagon, both through the origin.

    The teardrop's corner at the origin is 60 deg (folded: its two edges meet
    within 90 deg), every other corner of both loops is > 90 deg.  At the
    origin the pentagon's edges meet at 108 deg, and a teardrop edge meets a
    pentagon edge at 96 deg or more.  Vertex 0 is the origin.
    """
    # circle of radius 3 at (0, -6): the tangents from the origin touch it at
    # polar angles 30 and 150 deg (cos 60 = 3/6) and meet at 60 deg
    arc = np.radians(np.linspace(150, 390, 11))
    big = np.c_[3 * np.cos(arc), -6 + 3 * np.sin(arc)]
    # regular pentagon of side 1 with a vertex at the origin, above it
    rp = 1 / (2 * np.sin(np.pi / 5))
    ang = np.radians(-90 + 72 * np.arange(1, 5))
    penta = np.c_[rp * np.cos(ang), rp + rp * np.sin(ang)]
    pts = np.vstack([[0.0, 0.0], big, penta])
    nb, npn = len(big), len(penta)
    loop_big = [0] + list(range(1, nb + 1))
    loop_pen = [0] + list(range(nb + 1, nb + npn + 1))
    edges = [[a, b] for loop in (loop_big, loop_pen) for a, b in zip(loop, loop[1:] + loop[:1])]
    return pts, np.array(edges), nb + 1, npn + 1


def corner_angle(pts, loop_edges, v):
    """Angle at vertex v between its two edges in loop_edges, degrees."""
    other = [b if a == v else a for a, b in loop_edges if v in (a, b)]
    u = pts[other] - pts[v]
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return np.degrees(np.arccos(np.clip(u[0] @ u[1], -1, 1)))


def test_line_4_a_folded_pair_is_never_kept_even_if_it_would_cascade_least():
    """Paper, Algorithm 3 line 4: keep a pair meeting at more than 90 deg.

    Counting only what is dropped at the vertex, keeping the teardrop's
    folded pair (60 deg) looks cheapest: the pentagon (5 edges) is lost,
    against the whole teardrop (12 edges) for the pentagon's pair (108 deg).
    Line 4 forbids the folded pair; crustview enforces it twice (the
    eligibility filter, and the cascade simulation, in which a kept folded
    pair is itself sharp and pruned), so the pentagon's pair must be kept.
    """
    pts, edges, nbig, npen = teardrop_and_pentagon()
    big, pen = edges[:nbig], edges[nbig:]
    # the drawing is as the docstring says
    assert corner_angle(pts, big, 0) == pytest.approx(60.0, abs=0.5)
    assert corner_angle(pts, pen, 0) == pytest.approx(108.0, abs=1e-6)
    assert all(corner_angle(pts, big, v) > 90 for v in range(1, nbig))
    assert all(corner_angle(pts, pen, v) > 90 for v in range(nbig, nbig + npen - 1))
    ext = extract(pts, edges)
    resolve = [s for s in ext.steps if s.rule == RULE_RESOLVE]
    assert len(resolve) == 1 and resolve[0].tau == (0,)
    assert np.degrees(resolve[0].angle) == pytest.approx(108.0, abs=1e-6)
    kept = {tuple(sorted(edges[i])) for i in resolve[0].kept}
    assert kept == {tuple(sorted(e)) for e in pen if 0 in e}
    final = {tuple(e) for e in ext.complex_at(ext.n_steps)}
    assert final == {tuple(sorted(e)) for e in pen} and ext.stopped == "closed"


def test_sharp_fan_of_three_triangles_is_pruned_whole():
    """Three triangles on one edge, their far vertices within 80 deg of each
    other: no pair meets at more than 90 deg, so the sharp rule removes all
    three in one step.  Boundary pruning is off so nothing else acts first."""
    tau = [[0, 0, 0], [1, 0, 0]]
    tips = [[0.5, np.cos(a), np.sin(a)] for a in np.radians([10, 50, 90])]
    pts = np.array(tau + tips, float)
    tris = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4]])
    ext = extract(pts, tris, prune_boundary=False)
    assert len(ext.steps) == 1
    step = ext.steps[0]
    assert step.rule == RULE_PRUNE and step.tau == (0, 1) and sorted(step.removed) == [0, 1, 2]
    assert np.degrees(step.angle) == pytest.approx(80.0)  # the widest pair
    assert ext.stopped == "empty"


def test_open_disc_kept_with_boundary_pruning_off_and_eaten_with_it_on():
    """A flat hexagonal fan: six triangles, six boundary edges."""
    t = np.arange(6) * np.pi / 3
    pts = np.vstack([[0, 0, 0], np.c_[np.cos(t), np.sin(t), np.zeros(6)]])
    tris = np.array([[0, 1 + i, 1 + (i + 1) % 6] for i in range(6)])
    kept = extract(pts, tris, prune_boundary=False)
    assert kept.steps == [] and kept.stopped == "open" and len(kept.complex_at(0)) == 6
    rep = analyse(kept.complex_at(0), 7, 2)
    assert not rep.closed_manifold and rep.betti[:2] == (1, 0)
    eaten = extract(pts, tris)
    assert eaten.stopped == "empty"
    assert all(s.rule == RULE_PRUNE for s in eaten.steps)
    assert sum(len(s.removed) for s in eaten.steps) == 6


def test_with_boundary_pruning_off_the_pair_that_opens_no_hole_is_kept():
    """A hexagon loop with a one-edge spur at vertex 0, pruning of boundary off.

    At vertex 0 the spur is exactly opposite one hexagon edge (180 deg, the
    flattest pair), the hexagon's own pair meets at 120 deg.  Keeping the
    flattest pair drops a hexagon edge and opens a hole at its far end;
    keeping the hexagon's pair only drops the spur, whose tip already was a
    boundary face.  The pair that leaves the curve whole must win.
    """
    t = np.arange(6) * np.pi / 3
    hexagon = np.c_[np.cos(t), np.sin(t)]
    tip = hexagon[0] - (hexagon[1] - hexagon[0])  # opposite the edge 0-1
    pts = np.vstack([hexagon, tip])
    edges = np.array([[i, (i + 1) % 6] for i in range(6)] + [[0, 6]])
    ext = extract(pts, edges, prune_boundary=False)
    assert len(ext.steps) == 1
    step = ext.steps[0]
    assert step.rule == RULE_RESOLVE and step.tau == (0,) and step.removed == (6,)
    assert np.degrees(step.angle) == pytest.approx(120.0)
    assert ext.stopped == "closed" and len(ext.complex_at(1)) == 6


def test_replay_is_exact_and_clamps():
    pts = np.vstack([OCTA_PTS, [[1.5, 1.5, 0.0]]])
    ext = extract(pts, np.vstack([OCTA, [[0, 2, 6]]]))
    assert ext.alive(0).all()
    # after the one step, exactly the octahedron's eight triangles: the fin (row 8) is the one removed
    want = np.ones(9, bool)
    want[8] = False
    assert np.array_equal(ext.alive(1), want)
    assert np.array_equal(ext.alive(99), want)  # clamps


@pytest.mark.parametrize(
    "tris, n, betti, euler, orient",
    [
        (grid_surface(4, 5), 20, (1, 2, 1), 0, True),
        (grid_surface(4, 5, klein=True), 20, (1, 2, 1), 0, False),
        # minimal 6-vertex RP^2: Z/2 Betti numbers (1, 1, 1)
        (
            np.array(
                [
                    [0, 1, 2],
                    [0, 2, 3],
                    [0, 3, 4],
                    [0, 4, 5],
                    [0, 5, 1],
                    [1, 2, 4],
                    [2, 3, 5],
                    [3, 4, 1],
                    [4, 5, 2],
                    [5, 1, 3],
                ]
            ),
            6,
            (1, 1, 1),
            1,
            False,
        ),
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


@pytest.mark.parametrize("seed", range(4))
def test_betti_numbers_of_open_surfaces_agree_with_elimination(seed):
    """With boundary and no non-manifold edge, rank d_2 comes from the dual graph: check it by GF(2)."""
    rng = np.random.default_rng(seed)
    closed = [grid_surface(4, 5), grid_surface(4, 5, klein=True), OCTA + 20]
    tris = np.vstack([closed[0], closed[1] + 20, OCTA + 40])
    # punch holes: drop random triangles, so some components stay closed and others open
    keep = np.ones(len(tris), dtype=bool)
    drop = rng.choice(len(tris) - 8, size=1 + seed, replace=False)
    keep[drop] = False
    n_torus = len(closed[0])
    untouched = 1 + int(not (drop < n_torus).any()) + int(not (drop >= n_torus).any())
    tris = tris[keep]
    rep = analyse(tris, 46, 2)
    faces = all_faces(tris)
    r2 = boundary_rank_gf2(faces[2], faces[1])
    r1 = boundary_rank_gf2(faces[1], faces[0])
    expected = (len(faces[0]) - r1, len(faces[1]) - r1 - r2, len(faces[2]) - r2)
    assert rep.nonmanifold_faces == 0 and rep.boundary_faces > 0
    assert rep.betti == expected
    assert rep.betti[2] == untouched  # the octahedron (last 8 rows) is never punched


def test_initial_sharp_set_matches_the_per_facet_rule_on_a_thin_scan():
    # the horse's T_S has facets in 3, 4 and more candidate triangles; the
    # vectorised first sharp set must be exactly what is_sharp says per facet
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.core.paper.extraction import _Extractor, _initial_sharp
    from crustview.io import read_mesh

    pts = np.asarray(read_mesh(Path(__file__).parents[1] / "resources" / "horse-quads.obj").points, float)
    rec = reconstruct(pts, 2, mode="paper")
    ex = _Extractor(rec.points, rec.candidates.select(rec.test, rec.theta))
    assert (ex.count > 3).sum() > 10  # the case the grouping is for is present
    expected = [g for g in range(len(ex.facets)) if ex.is_sharp(g)[0]]
    assert _initial_sharp(ex) == expected
    assert 0 < len(expected) < len(ex.facets)


def test_analyse_remembers_the_last_complex_by_its_rows(torus_run, monkeypatch):
    # the robust extraction's check and the pipeline's report analyse the same
    # M_S; the second call must not analyse again, and a changed complex must
    from crustview.core.analysis import topology

    rec, _ = torus_run
    m_s = np.asarray(rec.manifold, dtype=np.int64)
    assert len(m_s) >= topology.REMEMBER_MIN
    calls = []
    real = topology._analyse
    monkeypatch.setattr(topology, "_analyse", lambda *a: calls.append(1) or real(*a))
    monkeypatch.setattr(topology, "_LAST", None)
    first = topology.analyse(m_s, rec.n, 2)
    second = topology.analyse(m_s.copy(), rec.n, 2)
    assert len(calls) == 1 and second == first and second.messages is not first.messages
    changed = m_s[1:]  # one triangle fewer: an open surface now
    third = topology.analyse(changed, rec.n, 2)
    assert len(calls) == 2 and not third.closed_manifold and first.closed_manifold


def test_compiled_graph_components_give_scipys_labels(torus_run):
    # graph_components' union-find (core/analysis/_components.cpp) numbers components as scipy does
    from crustview.core.analysis import topology

    rng = np.random.default_rng(0)
    graphs = [(1, np.array([[0, 0]])), (6, np.array([[5, 4], [3, 3], [1, 5]]))]
    graphs += [(n, rng.integers(0, n, size=(m, 2))) for n, m in ((50, 20), (2000, 1500), (100_000, 99_000))]
    tris = torus_run[0].manifold
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]]]).astype(np.int32)  # int32, as some callers pass
    graphs += [(int(tris.max()) + 1, edges), (int(tris.max()) + 1, edges[: len(edges) // 3])]
    for n, edges in graphs:
        count, labels = topology.graph_components(n, edges)
        want_count, want = topology.scipy_components(n, edges)
        assert count == want_count and labels.dtype == want.dtype and np.array_equal(labels, want)
    assert topology._components is not None  # the compiled one ran (setup.py builds it)


def test_the_pair_dot_of_initial_sharp_is_the_matrix_entry_bit_for_bit(torus_run):
    # _initial_sharp takes a facet of two simplices' dot product from einsum over k alone; the matrix of
    # every pair (still used for three simplices and more) must give the same bits, or the sharp set of
    # a facet at exactly pi/2 could change
    from crustview.core.paper.extraction import _Extractor, _initial_sharp

    rng = np.random.default_rng(2)
    for k in (2, 3, 4, 5):  # every ambient dimension crustview reconstructs in
        vec = rng.normal(size=(100_000, 2, k))
        vec[:, 1] -= (vec[:, 1] * vec[:, 0]).sum(axis=1)[:, None] * vec[:, 0] / (vec[:, 0] ** 2).sum(axis=1)[:, None]
        vec[:, 1] += rng.normal(scale=1e-9, size=(100_000, k))  # nearly orthogonal pairs, dots near 0
        vec /= np.linalg.norm(vec, axis=2, keepdims=True)
        pair = np.einsum("gk,gk->g", vec[:, 0], vec[:, 1])
        matrix = np.einsum("gik,gjk->gij", vec, vec)
        assert np.array_equal(pair, matrix[:, 0, 1]) and np.array_equal(pair, matrix[:, 1, 0]), k
    rec, _ = torus_run
    ex = _Extractor(rec.points, rec.candidates.select(rec.test, rec.theta))
    two = np.flatnonzero(ex.count == 2)
    sample = two[:: max(1, len(two) // 3000)]
    assert set(_initial_sharp(ex)) & set(sample.tolist()) == {g for g in sample.tolist() if ex.is_sharp(g)[0]}
    # the torus's T_S has no sharp facet of two simplices; the decimated knight's has (48 of 426), so both
    # ways of getting it wrong (a sharp facet missed, a flat one taken) show there
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.io import read_mesh

    knight = read_mesh(Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off").points
    rec = reconstruct(knight, 2, mode="paper")
    ex = _Extractor(rec.points, rec.candidates.select(rec.test, rec.theta))
    two = np.flatnonzero(ex.count == 2)
    want = {g for g in two.tolist() if ex.is_sharp(g)[0]}
    assert want and len(want) < len(two)
    assert set(_initial_sharp(ex)) & set(two.tolist()) == want


def test_the_facet_table_built_beside_the_opposite_vectors_is_the_same(torus_run, monkeypatch):
    # from BESIDE_MIN simplices the facet table is built on another thread; the tables must not depend on it
    from crustview.core.paper import extraction

    rec, _ = torus_run
    t_s = rec.candidates.select(rec.test, rec.theta)
    monkeypatch.setattr(extraction, "BESIDE_MIN", 10**12)
    alone = extraction._Extractor(rec.points, t_s)
    monkeypatch.setattr(extraction, "BESIDE_MIN", 0)
    beside = extraction._Extractor(rec.points, t_s)
    for name in ("facets", "facet_of", "ptr", "inc", "u", "count"):
        assert np.array_equal(getattr(alone, name), getattr(beside, name)), name
    assert extraction._initial_sharp(alone) == extraction._initial_sharp(beside)
