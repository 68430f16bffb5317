"""The robust extraction: identity with the paper, hand-made holes and cascades, real scans, bad samples."""

from pathlib import Path

import numpy as np
import pytest

from crustview.core import reconstruct, reextract
from crustview.core.analysis.topology import analyse
from crustview.core.paper.extraction import extract
from crustview.core.robust.driver import SECOND_OPINION_N, extract_robust
from crustview.core.samples.manifolds import get_manifold
from crustview.core.steps import RULE_FILL, RULE_GROW, RULE_PRUNE, RULE_RELAX, RULE_SEED
from crustview.io import read_mesh

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def scan_points(name):
    return read_mesh(RESOURCES / name).points


OCTA_PTS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
OCTA = np.sort(np.array([[a, b, c] for a in (0, 1) for b in (2, 3) for c in (4, 5)]), axis=1)
THETA = np.pi / 8


def final(ext):
    return ext.simplices[ext.alive(ext.n_steps)]


def same_rows(a, b):
    return {tuple(r) for r in np.sort(a, axis=1).tolist()} == {tuple(r) for r in np.sort(b, axis=1).tolist()}


# -- hand-made cases, checkable on paper -----------------------------------------


def test_paper_success_is_returned_unchanged():
    # the whole octahedron is in T_S: the paper's loop keeps it in 0 steps, and so must robust
    ext = extract_robust(OCTA_PTS, OCTA, np.zeros(8), THETA, spacing=1.4)
    assert ext.mode == "robust" and ext.n_steps == 0 and ext.stopped == "closed"
    assert same_rows(final(ext), OCTA)
    assert "not needed" in ext.notes[-1]


def test_octahedron_with_a_hole_cascades_in_paper_mode():
    # T_S = the octahedron less face (0, 2, 4): its three edges are holes of T_S
    tset = OCTA[1:]
    ext = extract(OCTA_PTS, tset)
    assert ext.stopped == "empty"
    assert {tuple(h) for h in ext.holes.tolist()} == {(0, 2), (0, 4), (2, 4)}
    # every prune step goes back, through its causes, to a prune of one of the holes
    assert all(s.rule == RULE_PRUNE for s in ext.steps)
    origins = ext.cascades()
    assert sum(c.removed for c in origins) == 7
    assert all(c.hole and c.tau in {(0, 2), (0, 4), (2, 4)} for c in origins)
    assert sorted(i for c in origins for i in c.steps.tolist()) == list(range(ext.n_steps))
    for s in ext.steps:
        if s.cause >= 0:
            assert s.cause < s.index
            exposed = set(ext.steps[s.cause].removed)
            # the exposing step removed a simplex that contained this step's face
            assert any(set(s.tau) <= set(tset[i]) for i in exposed)


def test_hole_closed_with_a_delaunay_face_outside_t_s():
    # the missing face is a Delaunay face whose score (0.5 rad) fails theta: relaxed growth takes it
    scores = np.array([0.5] + [0.1] * 7)
    ext = extract_robust(OCTA_PTS, OCTA, scores, THETA, spacing=1.4)
    assert ext.stopped == "closed" and same_rows(final(ext), OCTA)
    added = [s for s in ext.steps if s.rule == RULE_RELAX]
    assert len(added) == 1 and tuple(ext.simplices[added[0].added[0]]) == (0, 2, 4)
    assert not ext.in_candidates[added[0].added[0]]
    assert "abandoned" in ext.notes[0]
    rep = analyse(final(ext), 6, 2)
    assert rep.closed_manifold and rep.betti == (1, 0, 1)


def test_hole_closed_by_an_ear_when_no_delaunay_face_fits():
    # the missing face is not offered at all: fill-hole closes the triangular hole itself
    ext = extract_robust(OCTA_PTS, OCTA[1:], np.full(7, 0.1), THETA, spacing=1.4)
    assert ext.stopped == "closed" and same_rows(final(ext), OCTA)
    assert [s.rule for s in ext.steps].count(RULE_FILL) == 1


def test_left_out_sample_is_inserted_by_stellar_subdivision():
    # sample 6 sits just above the centre of face (0, 2, 4), and no offered face uses it
    pts = np.vstack([OCTA_PTS, [[0.34, 0.34, 0.34]]])
    ext = extract_robust(pts, OCTA, np.zeros(8), THETA, spacing=1.4)
    m = final(ext)
    rep = analyse(m, 7, 2)
    assert rep.closed_manifold and rep.unused_samples == 0 and rep.betti == (1, 0, 1)
    assert len(m) == 10 and same_rows(m[(m == 6).any(axis=1)], [[0, 2, 6], [0, 4, 6], [2, 4, 6]])


def test_a_chain_of_left_out_samples_comes_in_one_link_a_pass():
    """Seven left-out samples in a column above a flat sheet, 1.2 and 1.3 spacings apart in turn and
    numbered from the top: each is within the insertion limit (2 x its nearest-neighbour distance,
    2.4) only once the one below it is in, so the passes go on until the whole column is in (a fixed
    four passes left three out), and the sheet stays a manifold."""
    from crustview.core.robust.patcher import Patcher

    x, y = np.meshgrid(np.arange(10.0), np.arange(10.0), indexing="ij")
    sheet = np.c_[x.ravel(), y.ravel(), np.zeros(100)]
    idx = lambda i, j: i * 10 + j  # noqa: E731
    tris = [tuple(sorted((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)))) for i in range(9) for j in range(9)]
    tris += [tuple(sorted((idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))) for i in range(9) for j in range(9)]
    heights = np.cumsum([1.2, 1.3, 1.2, 1.3, 1.2, 1.3, 1.2])[::-1]  # the highest first
    column = np.c_[4.3 + 0.05 * np.sin(heights), 4.6 + 0.05 * np.cos(heights), heights]
    pts = np.vstack([sheet, column])
    pt = Patcher(pts, tris, np.array(tris), 1.0)
    left = pt.insert_unused()
    assert left == []
    m = np.array([pt.simp[i] for i in range(len(pt.simp)) if pt.alive[i]])
    assert set(range(100, 107)) <= set(m.ravel().tolist())
    rep = analyse(m, len(pts), 2)
    assert rep.nonmanifold_faces == 0 and rep.singular_vertices == 0 and rep.components == 1


def _unit_sheet(m: int = 10) -> tuple[np.ndarray, list]:
    """A flat m x m grid of spacing 1 in the plane z = 0 and its triangles."""
    x, y = np.meshgrid(np.arange(float(m)), np.arange(float(m)), indexing="ij")
    sheet = np.c_[x.ravel(), y.ravel(), np.zeros(m * m)]
    idx = lambda i, j: i * m + j  # noqa: E731
    tris = [tuple(sorted((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)))) for i in range(m - 1) for j in range(m - 1)]
    tris += [tuple(sorted((idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))) for i in range(m - 1) for j in range(m - 1)]
    return sheet, tris


def test_a_sample_too_far_is_not_searched_again_while_its_neighbourhood_stays_the_same():
    """A column like the chain test's comes in one link a pass, so the passes repeat; a 3 x 3 patch 3 below the
    sheet stays out in every one.  Its samples' nearest vertices and their simplices do not change, so their
    search is skipped after the first pass, and everything comes out as when every pass searches again."""
    from crustview.core.robust import insert_sample
    from crustview.core.robust.patcher import Patcher

    sheet, tris = _unit_sheet()
    heights = np.cumsum([1.2, 1.3, 1.2, 1.3])[::-1]
    column = np.c_[4.3 + 0.05 * np.sin(heights), 4.6 + 0.05 * np.cos(heights), heights]
    # off the grid's symmetry lines: no two sheet vertices equally near (a tie may be ordered otherwise when the
    # k-d tree is built again with more vertices, which changes a sample's nearest eight)
    px, py = np.meshgrid([1.37, 2.41, 3.29], [5.43, 6.58, 7.36], indexing="ij")
    patch = np.c_[px.ravel(), py.ravel(), np.full(9, -3.0)]
    pts = np.vstack([sheet, column, patch])
    searched: list[int] = []
    nearest = insert_sample._nearest_triangle_face

    def counting(points, x, cand):
        searched.append(int(np.flatnonzero((points == x).all(axis=1))[0]))
        return nearest(points, x, cand)

    runs = []
    for forget in (False, True):
        searched.clear()
        pt = Patcher(pts, tris, np.array(tris), 1.0)
        if forget:  # the plain passes: nothing remembered between them
            plain = pt._insert_pass
            pt._insert_pass = lambda plain=plain, pt=pt: (pt.__dict__.pop("_far_before", None), plain())[1]
        insert_sample._nearest_triangle_face = counting
        try:
            left = pt.insert_unused()
        finally:
            insert_sample._nearest_triangle_face = nearest
        m = sorted(pt.simp[i] for i in range(len(pt.simp)) if pt.alive[i])
        runs.append((sorted(left), m, [x for x in searched if x >= 104]))
    (left, m, patch_searches), (left0, m0, patch_searches0) = runs
    assert left == left0 == list(range(104, 113)) and m == m0
    assert set(range(100, 104)) <= {v for s in m for v in s}
    # four passes (the column's links): the patch searched in each without the memory; with it once, and again
    # only where a link changed a nearest vertex's simplices (the patch's corner nearest the column)
    assert len(patch_searches0) == 4 * 9 and sorted(set(patch_searches)) == list(range(104, 113))
    assert patch_searches.count(104) == 1 and len(patch_searches) < len(patch_searches0) / 2


def test_insertion_limit_is_the_local_spacing_of_the_surface_not_of_a_cluster():
    """A sheet sampled at spacing 1 in a run whose median spacing is 0.4 (denser elsewhere), and four
    samples 0.1 apart (a marching-cubes corner, a decimated mesh's tiny triangles) 1.5 above it: their
    own nearest-neighbour distance (0.1) and the median (0.4) put the limit at 0.8, and they were left
    out (a lattice ball at 0.1 h noise, 4 of 17,586); the sheet's own spacing there is 1, so the limit
    is 2 and they come in.  A 3 x 3 patch sampled like the sheet, 3 below it, is a part the sheet does
    not stand for: it stays out."""
    from crustview.core.robust.patcher import Patcher

    sheet, tris = _unit_sheet()
    cluster = np.array([[4.3, 4.6, 1.5], [4.4, 4.6, 1.5], [4.3, 4.7, 1.5], [4.4, 4.7, 1.52]])
    px, py = np.meshgrid([1.5, 2.5, 3.5], [5.5, 6.5, 7.5], indexing="ij")
    patch = np.c_[px.ravel(), py.ravel(), np.full(9, -3.0)]
    pts = np.vstack([sheet, cluster, patch])
    pt = Patcher(pts, tris, np.array(tris), 0.4)
    assert sorted(pt.insert_unused()) == list(range(104, 113))
    m = np.array([pt.simp[i] for i in range(len(pt.simp)) if pt.alive[i]])
    assert {100, 101, 102, 103} <= set(m.ravel().tolist())
    rep = analyse(m, len(pts), 2)
    assert rep.nonmanifold_faces == 0 and rep.singular_vertices == 0 and rep.components == 1


def test_a_left_out_cluster_beyond_the_limit_stays_out_and_keeps_its_flag():
    """Two noisy circles side by side (``bench_curves.py``: gap 1, noise of one spacing, seed 0) come out as
    one closed curve, wrong; two samples of the other circle stay out, and that part is the result's only
    flag.  Judging a cluster narrower than half a spacing as one sample (tried in session 28) took them in
    and left the wrong curve without a word; the limit judges clusters by the surface's spacing only."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from bench_curves import circle_pair

    from crustview.core import reconstruct

    rec = reconstruct(circle_pair("side by side", 1.0, 1.0, 0), 1)
    assert rec.topology.betti == (1, 1)  # one curve for two: wrong
    out = np.setdiff1d(np.arange(len(rec.points)), np.asarray(rec.manifold))
    assert rec.topology.unused_samples == len(out) == 2
    # the only flag: the part left out, at those samples
    (flag,) = rec.uncertain_features
    assert flag.kind == "component" and sorted(np.asarray(flag.vertices).tolist()) == out.tolist()


def test_nearest_face_of_a_collinear_triangle_is_its_long_edge():
    """A triangle whose three corners lie on a line has no plane: the nearest face is its longest
    edge, at the distance to that segment (no division by its zero area)."""
    from crustview.core.robust.insert_sample import _nearest_triangle_face

    pts = np.array([[0.0, 0, 0], [1.0, 0, 0], [3.0, 0, 0], [0.0, 5, 0], [1.0, 5, 0], [0.0, 5, 1]])
    dist, face = _nearest_triangle_face(pts, np.array([2.0, 1.0, 0.0]), [(0, 1, 2), (3, 4, 5)])
    assert face == (0, 2) and dist == 1.0


def test_curve_with_a_gap_is_closed_by_joining_its_ends():
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    pts = np.c_[np.cos(t), np.sin(t)]
    edges = np.array([[i, i + 1] for i in range(39)])  # the edge (39, 0) is missing
    ext = extract_robust(pts, edges, np.zeros(39), THETA, spacing=0.16)
    rep = analyse(final(ext), 40, 1)
    assert rep.closed_manifold and rep.betti == (1, 1)
    assert any(s.rule == RULE_FILL and set(s.tau) <= {0, 39} for s in ext.steps)


def _grid(m):
    xs, ys = np.meshgrid(np.arange(float(m)), np.arange(float(m)))
    pts = np.c_[xs.ravel(), ys.ravel(), 0.01 * np.sin(xs.ravel() * 1.3 + ys.ravel())]
    tris = []
    for i in range(m - 1):
        for j in range(m - 1):
            a, b, c, d = i * m + j, i * m + j + 1, (i + 1) * m + j + 1, (i + 1) * m + j
            tris += [[a, b, c], [a, c, d]]
    return pts, np.array(tris)


def test_real_hole_of_an_open_surface_stays_open():
    # a 16 x 16 grid (an open disc): its rim has 60 edges and spans 21 spacings, beyond any gap
    pts, tris = _grid(16)
    ext = extract_robust(pts, tris, np.zeros(len(tris)), THETA, spacing=1.0)
    rep = analyse(final(ext), len(pts), 2)
    assert ext.stopped == "open" and rep.boundary_faces == 60 and rep.betti == (1, 0, 0)
    assert not any(s.rule == RULE_FILL for s in ext.steps)


def test_small_gap_of_a_surface_is_closed():
    # the 16 x 16 grid with the two triangles of one middle square missing: its 4-edge hole is
    # a gap and is closed (by two triangles); the 60-edge rim stays open
    pts, tris = _grid(16)
    square = {7 * 16 + 7, 7 * 16 + 8, 8 * 16 + 7, 8 * 16 + 8}
    centre = [t for t in range(len(tris)) if set(tris[t]) <= square]
    keep = np.setdiff1d(np.arange(len(tris)), centre)
    ext = extract_robust(pts, tris[keep], np.zeros(len(keep)), THETA, spacing=1.0)
    rep = analyse(final(ext), len(pts), 2)
    assert len(centre) == 2 and rep.boundary_faces == 60 and rep.unused_samples == 0
    assert rep.betti == (1, 0, 0)
    assert [s.rule for s in ext.steps].count(RULE_FILL) == 2


# -- built-ins: identity with the paper, and bad samples --------------------------


@pytest.mark.parametrize("name", ["torus", "trefoil", "clifford-torus", "s3"])
def test_builtins_are_identical_to_the_paper(name):
    m = get_manifold(name)
    paper = reconstruct(m.sample(m.default_n, seed=0).points, m.d, mode="paper")
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    assert robust.mode == "robust" and robust.topology.closed_manifold
    assert np.array_equal(robust.manifold, paper.manifold)
    assert [(s.rule, s.tau, s.removed) for s in robust.extraction.steps] == [
        (s.rule, s.tau, s.removed) for s in paper.extraction.steps
    ]


def _noisy(name, sigma, seed=1):
    m = get_manifold(name)
    pts = m.sample(m.default_n, seed=seed).points
    size = np.ptp(pts, axis=0).max()
    return m, pts + np.random.default_rng(seed).normal(scale=sigma * size, size=pts.shape)


@pytest.mark.parametrize("name", ["torus", "trefoil", "ellipsoid", "circle-r4"])
def test_noisy_builtins_fail_in_paper_mode_and_succeed_robustly(name):
    m, pts = _noisy(name, 0.005)
    paper = reconstruct(pts, m.d, mode="paper")
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    assert not (paper.topology.closed_manifold and paper.topology.unused_samples == 0)
    t = robust.topology
    assert t.closed_manifold and t.unused_samples == 0 and t.betti == m.betti


@pytest.mark.parametrize(
    "name,reach,frac,seed",
    [("torus", 0.45, 0.03, 1), ("torus", 0.45, 0.03, 2), ("sphere", 1.0, 0.03, 1), ("sphere", 1.0, 0.03, 2)],
)
def test_builtins_with_noise_of_three_percent_of_the_reach(name, reach, frac, seed):
    """Gaussian noise of 3 % of the reach (torus: its tube radius 0.45; sphere: 1): the paper's loop
    gives up, the robust extraction is right through every sample."""
    m = get_manifold(name)
    s = m.sample(m.default_n, seed=seed)
    pts = s.points + np.random.default_rng(seed + 100).normal(scale=frac * reach, size=s.points.shape)
    rec = reconstruct(pts, m.d)
    t = rec.topology
    assert "abandoned" in rec.extraction.notes[0]  # the case is one the paper's loop does not solve
    assert t.closed_manifold and t.unused_samples == 0 and t.betti == m.betti
    # a sound labelled result that cut no handle the sample may resolve is not grown a second time
    assert len(pts) <= SECOND_OPINION_N and "grew M_S" not in rec.extraction.notes[0]
    assert not any(s.rule in (RULE_GROW, RULE_SEED) for s in rec.extraction.steps)


def test_a_large_sound_result_that_is_unsure_is_not_grown_again():
    """Above SECOND_OPINION_N samples (the casting's 5,096) a sound labelled result through every
    sample is kept as it is, uncertain features and all: they already say where it is unsure, and
    the growing path is not run a second time.  (resample-check, which runs after the extraction and
    has its own tests, is off: it would double the run and decide nothing here.)"""
    rec = reconstruct(read_mesh(RESOURCES / "casting.off").points, 2, resample=False)
    t = rec.topology
    assert len(rec.points) > SECOND_OPINION_N
    assert t.closed_manifold and t.unused_samples == 0 and rec.uncertain_features
    assert "grew M_S" not in rec.extraction.notes[0]
    assert not any(s.rule in (RULE_GROW, RULE_SEED) for s in rec.extraction.steps)


def test_sparse_torus_in_r3():
    m = get_manifold("torus")
    rec = reconstruct(m.sample(350, seed=2).points, 2)
    t = rec.topology
    assert t.closed_manifold and t.unused_samples == 0 and t.betti == (1, 2, 1)


# -- real scans (copies of ../shared/data/scans in resources/) --------------------


@pytest.mark.parametrize("name,genus", [("fertility.off", 4), ("horse-quads.obj", 0)])
def test_scans_the_paper_loses_are_closed_with_the_right_genus(name, genus):
    pts = scan_points(name)
    paper = reconstruct(pts, 2, mode="paper")
    assert len(paper.manifold) == 0  # the prune cascade empties T_S
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    t = robust.topology
    assert t.closed_manifold and t.unused_samples == 0 and t.betti == (1, 2 * genus, 1)
    assert robust.extraction.stopped == "closed"


@pytest.mark.parametrize("name,genus", [("bumpy.off", 0), ("3holes.off", 3)])
def test_scans_the_paper_gets_right_are_unchanged(name, genus):
    pts = scan_points(name)
    paper = reconstruct(pts, 2, mode="paper")
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    assert np.array_equal(robust.manifold, paper.manifold)
    assert robust.topology.betti == (1, 2 * genus, 1) and robust.topology.unused_samples == 0


def test_knight_closes_into_a_sphere_through_every_sample():
    # 502 samples of a spiky figure whose legs and arms are a few slivers wide (158 of its
    # 1,000 true triangles are not even Delaunay faces; CGAL's advancing front leaves 98
    # boundary edges and 3 components).  Robust closes it into a sphere through every sample:
    # the walk refuses the handles that would bridge arm and torso across holes fill-hole
    # closes, and samples left beyond the insertion limit come in once their neighbours are in.
    pts = scan_points("decimated-knight.off")
    paper = reconstruct(pts, 2, mode="paper")
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    t = robust.topology
    assert paper.topology.unused_samples > 480
    assert t.closed_manifold and t.betti == (1, 0, 1) and t.orientable
    assert t.unused_samples == 0


def _grown(rec):
    """The growing path alone on a reconstruction's own T_S (the labelling path is not given cells)."""
    ext = extract_robust(
        rec.points, rec.candidates.faces, rec.candidates.angles[rec.test], rec.theta, spacing=rec.spacing
    )
    return ext, analyse(ext.complex_at(ext.n_steps), rec.n, rec.d)


def _frozen(obj) -> None:
    """Make the numpy arrays held by a dataclass (and its candidates) read-only: a test that wrote into a
    module fixture's result would fail instead of changing the next test's input."""
    import dataclasses

    for holder in (obj, getattr(obj, "candidates", None)):
        if dataclasses.is_dataclass(holder):
            for field in dataclasses.fields(holder):
                value = getattr(holder, field.name)
                if isinstance(value, np.ndarray):
                    value.flags.writeable = False


@pytest.fixture(scope="module")
def camelhead(camelhead_run):
    """``reconstruct(scan_points("camelhead.off"), 2)`` (11,381 samples), shared by the tests below, which
    only read it (tests/conftest.py: its arrays are read-only)."""
    return camelhead_run


@pytest.fixture(scope="module")
def camelhead_grown(camelhead):
    """``_grown(camelhead)`` with the growing path as it is (built before any test patches it)."""
    ext, t = _grown(camelhead)
    _frozen(ext)
    return ext, t


def test_open_scan_keeps_its_cut_open_and_zips_the_slit_of_a_thin_ear(monkeypatch, camelhead, camelhead_grown):
    # camelhead.off is open (its neck is cut: 56 boundary edges).  The cut stays open, while the
    # rim of an ear, a thin plate whose two sides were grown but not its edge, is a slit: a long
    # hole only a spacing or two wide, closed by ears.  Slits are a rule of the growing path's
    # last phase, run here on its own; the default result keeps the cut open too.
    from crustview.core.robust import fill_hole as holes

    rec = camelhead  # reconstruct(scan_points("camelhead.off"), 2)
    assert rec.topology.components == 1 and rec.topology.unused_samples == 0
    # one opening, the cut (a disc: b1 = 0), whose rim runs through about the cut's 56 samples
    # (the labelled rim may cut a corner of it)
    assert not rec.topology.closed_manifold and rec.topology.betti[:2] == (1, 0)
    assert 50 <= rec.topology.boundary_faces <= 62
    ext, t = camelhead_grown  # _grown(rec), unpatched
    slits = [s for s in ext.steps if s.rule == RULE_FILL and "slit" in s.reason]
    assert slits and t.components == 1 and t.unused_samples == 0
    assert not t.closed_manifold and t.boundary_faces >= 56
    monkeypatch.setattr(holes, "SLIT_MAX_WIDTH", 0.0)
    unzipped, tu = _grown(rec)
    assert not any("slit" in s.reason for s in unzipped.steps)
    assert tu.boundary_faces >= t.boundary_faces + 40


def test_a_slit_whose_rim_folds_in_its_plane_is_zipped_in_space(monkeypatch, camelhead, camelhead_grown):
    # a lip of camelhead.off: a 68-edge slit about 2.6 spacings wide whose best-fit plane folds
    # its rim over itself, so planar ear clipping cannot start; the zipper closes it in space
    # (the growing path's last phase, run on its own as above)
    from crustview.core.robust import patcher as holes

    rec = camelhead  # reconstruct(scan_points("camelhead.off"), 2)
    ext, t = camelhead_grown  # _grown(rec), unpatched
    zipped = [s for s in ext.steps if "chosen in space" in s.reason]
    assert len(zipped) >= 40 and all(s.rule == RULE_FILL and "slit" in s.reason for s in zipped)
    assert t.components == 1 and t.unused_samples == 0 and t.nonmanifold_faces == 0
    monkeypatch.setattr(holes.Patcher, "_zip", lambda self, loop, why: None)
    _, flat = _grown(rec)
    assert flat.boundary_faces >= t.boundary_faces + 40


def test_an_open_scan_labelled_soundly_is_not_grown_again(camelhead):
    """camelhead (11,381 samples): the labelled result is open only at the opening open-cap found,
    through every sample, nothing uncertain: it is kept at once (no growing rule ran), with the cut
    as its one hole."""
    from crustview.core.steps import RULE_GROW, RULE_OPEN, RULE_SEED

    rec = camelhead  # reconstruct(scan_points("camelhead.off"), 2)
    rules = {s.rule for s in rec.extraction.steps}
    assert RULE_OPEN in rules and not rules & {RULE_SEED, RULE_GROW}
    assert "grew M_S" not in rec.extraction.notes[0]
    t = rec.topology
    assert t.betti[:2] == (1, 0) and t.unused_samples == 0 and rec.uncertain_features == []
    assert [f.kind for f in rec.features] == ["hole"]
    # an open result says that holes below the sample's resolution cannot be told apart
    assert any("does not show in a sample" in m for m in t.messages)


def test_choose_puts_topology_doubts_before_samples_left_out():
    """The camel head at 0.3 h (noise draw 26): the labelled M_S was the right open disk with 2 of 11,381
    samples left out and no uncertain feature; the grown one used every sample but had 43 handle loops,
    33 of them uncertain.  Samples left out came first, and the grown answer was kept."""
    from types import SimpleNamespace as NS

    from crustview.core.robust.verdict import problems

    labelled = NS(closed_manifold=False, unused_samples=2, boundary_faces=40)
    grown = NS(closed_manifold=False, unused_samples=0, boundary_faces=584)
    assert problems(labelled, []) < problems(grown, [object()] * 33)
    # with topology equal, fewer samples left out wins, then fewer boundary faces; closed beats all
    assert problems(grown, []) < problems(labelled, [])
    assert problems(NS(closed_manifold=True, unused_samples=9, boundary_faces=0), [object()] * 5) < problems(
        labelled, []
    )


def test_six_samples_whose_labelling_gives_no_vertex_are_grown_without_an_error():
    """Six points in R^3 (a reviewer's batch input): the labelling leaves M_S without a vertex, and the left-out
    samples' search had no k-d tree to build ("zero-size array" before); the grown answer is used instead."""
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1], [2, 0, 1], [0, 2, 1]], float)
    rec = reconstruct(pts, 2)
    assert rec.topology.n_simplices > 0 and rec.topology.unused_samples == 0
    assert "the grown result is kept" in rec.extraction.notes[0]
    # a closed surface through six samples with eight triangles: Euler characteristic 6 - 12 + 8 = 2, a sphere
    assert rec.topology.closed_manifold and rec.topology.n_simplices == 8 and rec.topology.betti == (1, 0, 1)
