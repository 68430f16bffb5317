"""The robust extension's labelling path: label-cells, repair-vertex, sculpt-sample, open-cap, its step log."""

import numpy as np
import pytest
from labelled_helpers import cells_of as _cells
from labelled_helpers import noisy_torus_editor as _noisy_torus_editor

from crustview.core import reconstruct
from crustview.core.analysis.topology import analyse
from crustview.core.delaunay import adjacency
from crustview.core.robust import labelling
from crustview.core.robust.cells import CAP_RATIO, OPEN_MIN_FACES, cap_patches, caps, extract_by_labels
from crustview.core.robust.label_repair import LabelEditor
from crustview.core.robust.labelling import Labelling, cell_adjacency, label_python
from crustview.core.robust.steplog import StepLog
from crustview.core.samples.manifolds import get_manifold
from crustview.core.steps import RULE_LABEL, RULE_OPEN


def test_greedy_labelling_on_paper():
    """Four nodes, ties taken most confident first; the weakest tie that contradicts the others is
    the one violated, and each node's confidence is the weakest tie on its path to node 0."""
    # edges in decreasing confidence: 0=1 (same), 1!=2 (opposite), 2!=3, then 0=3 contradicts
    a = np.array([0, 1, 2, 0])
    b = np.array([1, 2, 3, 3])
    sign = np.array([1, -1, -1, 1], np.int8)
    lab, when, viol = label_python(4, a, b, sign)
    assert lab.tolist() == [0, 0, 1, 0]  # 3 is opposite of 2, which is opposite of 1 = 0
    assert viol.tolist() == [0, 0, 0, 0]  # 0 = 3 holds already: consistent, not violated
    assert when.tolist() == [-1, 0, 1, 2]
    # the contradicting version: 0 != 3 is then violated
    lab2, _, viol2 = label_python(4, a, b, np.array([1, -1, -1, -1], np.int8))
    assert lab2.tolist() == [0, 0, 1, 0] and viol2.tolist() == [0, 0, 0, 1]


def test_kernel_gives_the_python_labels():
    assert labelling._kernel is not None  # the kernel is part of the install (scripts/install.sh builds it)
    rng = np.random.default_rng(3)
    for n, e in ((2, 1), (30, 80), (500, 3000)):
        a = rng.integers(0, n, e)
        b = rng.integers(0, n, e)
        sign = rng.choice(np.array([-1, 1], np.int8), e)
        want = label_python(n, a, b, sign)
        got = labelling._label(n, a, b, sign)
        for x, y in zip(want, got):
            assert np.array_equal(x, y)


def test_kernel_rejects_bad_edges():
    assert labelling._kernel is not None
    with pytest.raises(ValueError):
        labelling._kernel.label(3, np.array([0, 5]), np.array([1, 2]), np.array([1, 1], np.int8), 0)


def test_cell_adjacency_of_two_tetrahedra():
    """Two tetrahedra glued along one triangle share exactly that face."""
    s = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
    a, b, faces = cell_adjacency(s)
    assert a.tolist() == [0] and b.tolist() == [1] and faces.tolist() == [[1, 2, 3]]
    a, b, faces = cell_adjacency(s.astype(np.int32))  # by the compiled face listing
    assert a.tolist() == [0] and b.tolist() == [1] and faces.tolist() == [[1, 2, 3]]


def test_cell_adjacency_compiled_equals_numpy(monkeypatch):
    """The compiled face listing and numpy give the same shared faces in the same order, each with its
    two cells lower-numbered first (not left to numpy's unstable sort, whose order differs by CPU)."""
    from crustview.core.delaunay.triangulation import bounding_points, delaunay

    simp = delaunay(np.random.default_rng(5).normal(size=(3000, 3)), bounding_points(3))
    assert simp.dtype == np.int32 and adjacency._faces_native is not None
    a, b, faces = cell_adjacency(simp)
    assert np.all(a < b)
    monkeypatch.setattr(adjacency, "_faces_native", None)
    a0, b0, faces0 = cell_adjacency(simp)
    assert np.array_equal(faces, faces0) and np.array_equal(a, a0) and np.array_equal(b, b0)
    assert faces.dtype == faces0.dtype == np.int32 and a.dtype == a0.dtype == np.int64
    # the faces found twice among all cells' four faces, listed directly
    srt = np.sort(simp, axis=1)
    every = np.concatenate([np.delete(srt, j, axis=1) for j in range(4)])
    rows, counts = np.unique(every, axis=0, return_counts=True)
    assert counts.max() == 2 and np.array_equal(faces, rows[counts == 2])


def test_labelled_noisy_torus_is_a_torus_through_every_sample():
    """Noise of 10 % of the spacing: the cut between inside and outside cells, repaired and sculpted,
    is a closed torus through every sample, and every step replays."""
    m = get_manifold("torus")
    s = m.sample(1500, seed=4)
    rng = np.random.default_rng(0)
    pts = s.points + rng.normal(scale=0.03, size=s.points.shape)
    rec = reconstruct(pts, 2, mode="paper")
    faces = rec.candidates.faces
    ts = np.sort(rec.candidates.select("cocone"), axis=1)
    ext = extract_by_labels(rec.points, *_cells(rec), faces, ts, rec.spacing)
    final = ext.complex_at(ext.n_steps)
    top = analyse(final, rec.n, 2)
    assert top.closed_manifold and top.betti == (1, 2, 1) and top.unused_samples == 0
    assert ext.steps[0].rule == RULE_LABEL
    # replay: after the first step the complex is exactly the raw cut
    lab = Labelling(rec.points, *_cells(rec))
    raw, _ = lab.surface()
    first = {tuple(r) for r in ext.complex_at(1).tolist()}
    assert first == {tuple(r) for r in np.sort(raw, axis=1).tolist()}
    # the rows of T_S come first, as in paper mode
    assert np.array_equal(ext.simplices[: len(ts)], ts)

    # every later step replays: the complex after it is the one before, less its removed, plus its added
    def rows(a):
        return {tuple(r) for r in np.sort(np.asarray(a).reshape(-1, 3), axis=1).tolist()}

    assert ext.n_steps > 1  # repairs or sculpting ran after the labelling
    for i, st in enumerate(ext.steps[1:], start=1):
        want = (rows(ext.complex_at(i)) - rows(ext.simplices[list(st.removed)])) | rows(ext.simplices[list(st.added)])
        assert rows(ext.complex_at(i + 1)) == want, (i, st.rule)


def test_repair_leaves_no_pinched_vertex():
    """repair-vertex until every surface vertex has one inside and one outside piece in its star."""
    rec, lab, ed, _ = _noisy_torus_editor()  # noise of about half the spacing: the raw cut pinches at 10 samples
    before, _ = ed.pieces()
    steps = ed.repair()
    after, _ = ed.pieces()
    assert (before > 2).any() and steps  # there was something to repair
    assert not (after > 2).any()
    top = analyse(lab.surface()[0], rec.n, 2)
    assert top.singular_vertices == 0 and top.nonmanifold_faces == 0 and top.boundary_faces == 0


@pytest.mark.parametrize("name,seed", [("torus", 4), ("sphere", 8)])
def test_repair_ends_a_ping_pong_between_two_neighbours(name, seed):
    """A built-in with Gaussian noise whose labelling pinches at two neighbouring vertices, each one's
    repair pinching the other: the rule flipped the same cells there and back for all REPAIR_ROUNDS and
    left a non-manifold edge (the turbine blade at 0.3 h, draw 23, did the same).  After PING_PONG flips
    the cells keep their label, the rule flips the stars' other pieces, and no vertex pinches."""
    from collections import Counter

    from crustview.core.robust.label_repair import PING_PONG

    m = get_manifold(name)
    s = m.sample(1500, seed=seed)
    noisy = s.points + np.random.default_rng(seed + 50).normal(
        scale=0.08 if name == "torus" else 0.06, size=s.points.shape
    )
    rec = reconstruct(noisy, 2, mode="paper")
    lab = Labelling(rec.points, *_cells(rec))
    ed = LabelEditor(lab)
    steps = ed.repair()
    flips = Counter(c for _, cells, _, _ in steps for c in cells.tolist())
    assert max(flips.values()) == PING_PONG  # the case this test is about: a ping-pong, stopped
    after, _ = ed.pieces()
    assert not (after > 2).any()
    top = analyse(lab.surface()[0], rec.n, 2)
    assert top.singular_vertices == 0 and top.nonmanifold_faces == 0 and top.boundary_faces == 0


def test_compiled_star_pieces_are_the_python_ones():
    """The compiled star_pieces gives the Python reference's pieces, ids and all, at every sample of a
    noisy torus, before and after 300 cells take the other label (pinches and all); the compiled
    piece counts are the numpy pass's.  The kernel is part of the install: without it this would
    compare the numpy pass with itself."""
    from crustview.core.robust import label_repair

    assert label_repair._kernel is not None
    rec, lab, ed, rng = _noisy_torus_editor()
    several = 0
    for rnd in range(2):
        if rnd:
            ed.flip(rng.choice(np.flatnonzero(~lab.outside), 300, replace=False))
        ed._pieces.clear()
        assert np.array_equal(ed.piece_counts(), ed.pieces()[0])
        for v in range(rec.n):
            cells, comp = ed.star_pieces(v)
            ref = ed._star_pieces_py(v, cells)
            assert comp.dtype == ref.dtype and np.array_equal(comp, ref), v
            several += comp.max() > 1
    assert several > 10  # pinched stars (three pieces or more) were compared too


def test_piece_counts_refuse_unsorted_stars():
    """The compiled piece counts find a star's cells by bisection: a star out of order is one clear
    error, not a wrong count."""
    from crustview.core.robust import label_repair

    m = get_manifold("sphere")
    rec = reconstruct(m.sample(200, seed=0).points, 2, mode="paper")
    ed = LabelEditor(Labelling(rec.points, *_cells(rec)))
    k = list(ed._k_arrays)
    cells = k[1].copy()
    lo, hi = k[0][0], k[0][1]
    cells[lo:hi] = cells[lo:hi][::-1]
    k[1] = cells
    with pytest.raises(ValueError, match="sorted"):
        label_repair._kernel.piece_counts(ed.lab.faces.shape[1], *k, ed.lab.inside)


def test_compiled_pole_cells_are_the_numpy_ones():
    """The compiled pole cells are the numpy reference's, cell for cell, on a noisy torus and on a
    sample with coincident-radius ties (a cube's corners and centre, with flat cells whose centres are
    NaN); and on a tiny case checked by hand: a square's centre has the far corners' cells."""
    assert labelling._kernel is not None
    m = get_manifold("torus")
    rng = np.random.default_rng(3)
    s = m.sample(1200, seed=4).points
    grid = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    for pts in (s + rng.normal(scale=0.05, size=s.shape), np.vstack([grid, grid + [2, 0, 0], [[0.5, 0.5, 0.5]]])):
        rec = reconstruct(pts, 2, mode="paper")
        dp, simp, centres = _cells(rec)
        radius = np.linalg.norm(centres - dp[simp[:, 0]], axis=1)
        got = labelling.pole_cells(simp, rec.n, radius, centres, rec.points)
        ref = labelling.pole_cells_python(simp, rec.n, radius, centres, rec.points)
        assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])
        assert (got[0] >= 0).all() and (got[1] >= 0).mean() > 0.5
    # by hand: sample 0 in three cells of radii 1, 3, 2 whose centres lie at +x, +x, -x of it
    simp = np.array([[0, 1, 2, 3], [0, 1, 2, 4], [0, 2, 3, 4]], np.int64)
    centres = np.array([[1.0, 0, 0], [3.0, 0, 0], [-2.0, 0, 0]])
    pts = np.zeros((5, 3))
    radius = np.array([1.0, 3.0, 2.0])
    for fn in (labelling.pole_cells, labelling.pole_cells_python):
        plus, minus = fn(simp, 5, radius, centres, pts)
        assert plus[0] == 1 and minus[0] == 2  # the largest ball, then the largest one on the other side


def test_sculpt_brings_a_buried_sample_onto_the_surface():
    """A sample just inside a sphere's sample is no vertex of the labelled surface until
    sculpt-sample flips one cell of its star (Boissonnat's rule keeps a manifold)."""
    m = get_manifold("sphere")
    s = m.sample(600, seed=0).points
    inner = 0.97 * s[0]  # a sample buried 3 % below the surface, under sample 0
    rec = reconstruct(np.vstack([s, inner]), 2, mode="paper")
    lab = Labelling(rec.points, *_cells(rec))
    ed = LabelEditor(lab)
    ed.repair()
    surf, _ = lab.surface()
    unused_before = analyse(surf, rec.n, 2).unused_samples
    steps = ed.sculpt()
    top = analyse(lab.surface()[0], rec.n, 2)
    assert unused_before >= 1 and len(steps) >= 1
    assert top.unused_samples < unused_before and top.closed_manifold


def test_cap_patches_need_eight_adjacent_big_faces():
    """A fan of 8 big triangles is one patch; 7 are none; 8 that share no edge are none; small
    faces never count."""
    assert OPEN_MIN_FACES == 8
    fan = np.array([[0, i, i + 1] for i in range(1, 9)])
    (patch,) = cap_patches(fan, np.ones(8, bool), 30)
    assert sorted(patch.tolist()) == list(range(8))
    assert cap_patches(fan[:7], np.ones(7, bool), 30) == []
    apart = np.arange(24).reshape(8, 3)
    assert cap_patches(apart, np.ones(8, bool), 30) == []
    some = np.ones(8, bool)
    some[3] = False  # the fan is cut in two runs of 3 and 4
    assert cap_patches(fan, some, 30) == []


def _fan_with_ring(radius, small):
    """A fan of 8 triangles of this radius around a centre, and one triangle of size ``small`` on
    the outside of each rim vertex (the surface around the patch)."""
    ang = np.linspace(0, 2 * np.pi, 9)[:-1]
    rim = np.c_[np.cos(ang), np.sin(ang), np.zeros(8)] * radius
    pts = [np.zeros(3), *rim]
    faces = [[0, 1 + i, 1 + (i + 1) % 8] for i in range(8)]
    for i in range(8):
        out = rim[i] / radius
        side = np.array([-out[1], out[0], 0.0])
        a, b = rim[i] + small * out + small * side / 2, rim[i] + small * out - small * side / 2
        pts += [a, b]
        faces.append([1 + i, len(pts) - 2, len(pts) - 1])
    return np.array(pts), np.array(faces)


def test_a_cap_is_a_patch_much_larger_than_the_faces_around_it():
    """A fan 10 times larger than its ring is a cap; the same fan in a ring of faces of about its
    own size (a sparsely sampled part) is not."""
    pts, faces = _fan_with_ring(10.0, 1.0)
    patch = np.arange(8)
    assert len(caps(faces, [patch], pts)) == 1
    pts, faces = _fan_with_ring(10.0, 10.0)
    assert caps(faces, [patch], pts) == []
    # the bound itself: a fan just above CAP_RATIO times its ring is a cap, just below is not
    from crustview.core.analysis.features import enclosing_radii

    pts, faces = _fan_with_ring(1.0, 1.0)
    r = enclosing_radii(pts, faces)
    r_fan, r_ring = r[:8].max(), np.median(r[8:])  # the fan's radii scale with its radius, the ring's do not
    for factor, want in ((1.05, 1), (0.95, 0)):
        pts, faces = _fan_with_ring(factor * CAP_RATIO * r_ring / r_fan, 1.0)
        assert len(caps(faces, [patch], pts)) == want


def test_open_scan_is_kept_open_by_open_cap():
    """A sphere without its cap z > 0.3: the labelling closes it over the opening with large faces,
    open-cap removes that patch, and no later rule closes it again."""
    m = get_manifold("sphere")
    p = m.sample(2500, seed=0).points
    rec = reconstruct(p[p[:, 2] < 0.3], 2, mode="paper")
    ts = np.sort(rec.candidates.select("cocone"), axis=1)
    ext = extract_by_labels(rec.points, *_cells(rec), rec.candidates.faces, ts, rec.spacing)
    opened = [st for st in ext.steps if st.rule == RULE_OPEN]
    top = analyse(ext.complex_at(ext.n_steps), rec.n, 2)
    assert len(opened) == 1 and len(opened[0].removed) >= OPEN_MIN_FACES
    assert not top.closed_manifold and top.betti == (1, 0, 0) and top.unused_samples == 0
    # the rim left open is the cut: every boundary vertex is near z = 0.3
    tri = ext.complex_at(ext.n_steps)
    edges, count = np.unique(
        np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]), axis=1), axis=0, return_counts=True
    )
    rim = np.unique(edges[count == 1])
    assert len(rim) > 20 and rec.points[rim, 2].min() > 0.15


def test_typical_ratio_on_paper():
    """A cap's largest enclosing radius over the median one of all faces: for a fan of 8 triangles of
    radius 1 in a ring of 8 small ones, the median is the mean of the two middle radii (a small and a fan
    face); with 16 more faces the size of the fan's, the median is the fan's own and the ratio 1."""
    from crustview.core.analysis.features import enclosing_radii
    from crustview.core.robust.cells import CAP_TYPICAL, typical_ratios

    assert CAP_TYPICAL == pytest.approx(3**0.5)
    pts, faces = _fan_with_ring(1.0, 0.1)
    r = enclosing_radii(pts, faces)
    (t,) = typical_ratios(faces, [np.arange(8)], r)
    assert t == pytest.approx(r[:8].max() / ((r[:8].min() + r[8:].max()) / 2))
    big = np.vstack([faces, faces[:8] + 0, faces[:8] + 0])  # the fan's faces again, as other faces of that size
    (t,) = typical_ratios(big, [np.arange(8)], enclosing_radii(pts, big))
    assert t == pytest.approx(1.0)


def test_open_cap_passes_over_a_patch_no_larger_than_the_surface_in_general():
    """A turned vase (``bench_shapes.py``: as many vertices on each ring as on the widest, rings 1.5 times
    farther apart than the vertices along them) with noise of 0.1 h: the flat base and lid are dense near
    the axis, and their faces a few rings out stand out only against that.  open-cap passes them over (a
    note names them), so the result is the closed sphere through every sample with no uncertain hole;
    with CAP_TYPICAL at 0 (every patch over CAP_RATIO a cap) the same sample keeps caps as uncertain holes."""
    import sys
    from pathlib import Path

    from scipy.spatial import cKDTree

    from crustview.core.robust import cells

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from bench_shapes import lathe, profile_vase

    verts, _ = lathe(profile_vase(), 96, 1.5)
    h = np.median(cKDTree(verts).query(verts, k=2)[0][:, 1])
    pts = verts + np.random.default_rng(1).normal(scale=0.1 * h, size=verts.shape)
    rec = reconstruct(pts, 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 0, 1) and rec.topology.unused_samples == 0
    assert not [f for f in rec.uncertain_features if f.kind == "hole"]
    assert any("times the median face of M_S" in note for note in rec.extraction.notes)
    saved = cells.CAP_TYPICAL
    try:
        cells.CAP_TYPICAL = 0.0
        again = reconstruct(pts, 2)
    finally:
        cells.CAP_TYPICAL = saved
    assert [f for f in again.uncertain_features if f.kind == "hole" and "open-cap" in f.reason]


def test_steplog_rows_and_replay():
    """A face removed and added again gets a new row; T_S rows are reused once."""
    ts = np.array([[0, 1, 2], [0, 2, 3]])
    log = StepLog(ts, 5)
    log.step("a", (), np.array([[0, 1, 2], [1, 2, 4]]), np.zeros((0, 3), int), np.nan, "add")
    log.step("b", (), np.zeros((0, 3), int), np.array([[0, 1, 2]]), np.nan, "remove")
    log.step("c", (), np.array([[2, 1, 0]]), np.zeros((0, 3), int), np.nan, "add again")
    ext = log.extraction("open")
    assert ext.simplices.tolist() == [[0, 1, 2], [0, 2, 3], [1, 2, 4], [0, 1, 2]]
    assert {tuple(r) for r in ext.complex_at(1).tolist()} == {(0, 1, 2), (1, 2, 4)}
    assert {tuple(r) for r in ext.complex_at(2).tolist()} == {(1, 2, 4)}
    assert {tuple(r) for r in ext.complex_at(3).tolist()} == {(1, 2, 4), (0, 1, 2)}
    assert ext.complex_at(0).shape == (0, 3)


def test_extraction_progress_moves_between_the_rules():
    """The robust extraction reports increasing fractions while it runs, not only 0 and the end."""
    m = get_manifold("torus")
    s = m.sample(1500, seed=4)
    rng = np.random.default_rng(0)
    seen = []
    reconstruct(s.points + rng.normal(scale=0.06, size=s.points.shape), 2, progress=lambda st, f: seen.append((st, f)))
    fr = [f for st, f in seen if st == "extraction"]
    assert len(set(fr)) >= 4 and fr == sorted(fr) and 0 < max(fr) <= 1


def test_cap_ratios_on_paper_and_weak_openings():
    """The fan of radius R in a ring of unit triangles: its ratio is R's enclosing radius over the
    ring's, the same number that decides caps().  A hole whose samples meet a cap under CAP_SURE
    becomes uncertain and says why; one that meets only a sure cap, or none, stays as it was."""
    from crustview.core.analysis.features import Feature, enclosing_radii
    from crustview.core.robust.cap_holes import weak_openings
    from crustview.core.robust.cells import CAP_SURE, cap_ratios

    pts, faces = _fan_with_ring(10.0, 1.0)
    r = enclosing_radii(pts, faces)
    (q,) = cap_ratios(faces, [np.arange(8)], pts)
    assert q == pytest.approx(r[:8].max() / np.median(r[8:]))
    assert CAP_SURE == 2 * CAP_RATIO

    def hole(verts):
        return Feature("hole", np.zeros(3), 9.0, False, np.array(verts), "hole with 8 rim edges, 9 spacings across")

    feats = [hole([1, 2, 3]), hole([20, 21, 22]), hole([40, 41])]
    openings = [(np.array([0, 1, 2, 3]), 0.9 * CAP_SURE), (np.array([20, 21, 22]), 1.1 * CAP_SURE)]
    out = weak_openings(feats, openings)
    assert [f.uncertain for f in out] == [True, False, False]
    assert "open-cap" in out[0].reason and f"{0.9 * CAP_SURE:.2g}" in out[0].reason
    assert out[1] is feats[1] and out[2] is feats[2]
    assert weak_openings(feats, [(np.array([1, 2]), 1.1 * CAP_SURE)]) == feats


def test_cap_ratios_on_paper_and_kept_caps():
    """The fan of radius R in a ring of unit triangles: its ratio is R's enclosing radius over the
    ring's, the same number that decides caps().  A cap kept closed becomes an uncertain, removed hole
    at its samples' centre, as wide as their span in their nearest-neighbour distances."""
    from crustview.core.analysis.features import enclosing_radii
    from crustview.core.robust.cap_holes import kept_caps
    from crustview.core.robust.cells import CAP_SURE, cap_ratios

    pts, faces = _fan_with_ring(10.0, 1.0)
    r = enclosing_radii(pts, faces)
    (q,) = cap_ratios(faces, [np.arange(8)], pts)
    assert q == pytest.approx(r[:8].max() / np.median(r[8:]))
    assert CAP_SURE == 2 * CAP_RATIO
    assert kept_caps(pts, []) == []
    # the fan's centre and rim: span 20 (the rim's diameter); nearest neighbours: the centre's is 10
    # away, each rim vertex's is the small triangle's corner, 1.118 away (sqrt(1 + 1/4))
    (hole,) = kept_caps(pts, [(np.arange(9), 4.0)])
    assert hole.kind == "hole" and hole.uncertain and hole.removed
    np.testing.assert_allclose(hole.location, pts[:9].mean(axis=0))
    assert hole.size_spacings == pytest.approx(20.0 / np.sqrt(1.25))
    assert "kept closed (rule open-cap)" in hole.reason and "4 times" in hole.reason


@pytest.mark.parametrize("top, kept", [(0.9, False), (0.97, True)])
def test_a_cap_the_sample_does_not_decide_stays_closed_and_is_an_uncertain_hole(top, kept):
    """A sphere without its cap z > top.  Over 125 missing samples (z > 0.9) the labelling's cap is
    8.3 times its ring, over CAP_SURE: open-cap removes it.  Over 36 (z > 0.97) it is 4.5 times, between
    CAP_RATIO and CAP_SURE, and no cap of the sample is over CAP_SURE: it stays, M_S is the closed
    sphere, and the possible opening is an uncertain removed hole at the cut.  (``reconstruct`` keeps
    the paper's result here: its Algorithm 3 closes this sphere through every sample.)"""
    from crustview.core.robust.cells import CAP_SURE

    m = get_manifold("sphere")
    p = m.sample(2500, seed=0).points
    p = p[p[:, 2] < top]
    rec = reconstruct(p, 2, mode="paper")
    ts = np.sort(rec.candidates.select("cocone"), axis=1)
    ext = extract_by_labels(rec.points, *_cells(rec), rec.candidates.faces, ts, rec.spacing)
    top_ = analyse(ext.complex_at(ext.n_steps), rec.n, 2)
    holes = [f for f in ext.removed_features if f.kind == "hole"]
    if not kept:
        assert [q > CAP_SURE for _, q in ext.opened] == [True] and not holes
        assert top_.betti == (1, 0, 0)
        return
    assert [CAP_RATIO < q <= CAP_SURE for _, q in ext.undecided] == [True]  # the band, and no sure cap
    assert ext.opened == [] and not [st for st in ext.steps if st.rule == RULE_OPEN]
    assert top_.closed_manifold and top_.betti == (1, 0, 1) and top_.unused_samples == 0
    (hole,) = holes
    assert hole.uncertain and hole.removed and hole.location[2] > top - 0.05
    assert any("kept 1 cap closed" in n for n in ext.notes)


def test_noise_caps_beside_a_sure_opening_become_uncertain_holes_and_the_real_opening_stays_sure():
    """The camel head (an open scan, one opening at the neck) with noise of 0.3 h
    (``resources/camelhead-n30.xyz``, written by ``../shared/tools/noisy.py``): open-cap removes the
    neck's cap (ratio about 9) and, as the scan is open, two caps that noise made (about 4 and 5), so the
    result has three holes.  The neck is sure; the two others are uncertain, and the result is flagged.  The two
    are also holes through a part thinner than the sample resolves (the ear), and say so."""
    from pathlib import Path

    from crustview.core.robust.cells import CAP_SURE
    from crustview.io import read_points

    pts = read_points(Path(__file__).resolve().parents[1] / "resources" / "camelhead-n30.xyz")
    rec = reconstruct(pts, 2)
    assert getattr(rec.extraction, "undecided", []) == []  # beside a sure opening no cap is kept closed
    opened = rec.extraction.opened
    assert len(opened) >= 2 and max(q for _, q in opened) > CAP_SURE  # the case this test is about
    holes = sorted((f for f in rec.features if f.kind == "hole"), key=lambda f: -f.size_spacings)
    assert len(holes) >= 2
    assert not holes[0].uncertain  # the neck
    weak = [f for f in holes if f.uncertain and "open-cap" in f.reason]
    assert len(weak) == sum(q < CAP_SURE for _, q in opened)
    assert rec.uncertain_features
    # the noise caps' holes go through the camel's ear, whose two sides lie 0.56 of a spacing apart on the true
    # mesh: their rims lie where M_S has two sheets closer than GAP_MIN (analysis.sheets), the neck's does not
    assert all("two sheets" in f.reason for f in weak) and "two sheets" not in holes[0].reason


def test_beside_a_sure_opening_a_cap_in_the_band_is_removed_too():
    """A torus with its x > 0.6 part cut away: the two ends of the cut tube are both real openings, and
    their caps measure about 6.0 and 5.9 times their rings.  The first is over CAP_SURE, so the scan is
    open and the second is removed as well (its hole flagged), not kept closed as a ribbon."""
    from crustview.core.analysis.features import features
    from crustview.core.robust.cap_holes import weak_openings
    from crustview.core.robust.cells import CAP_SURE

    pts = get_manifold("torus").sample(1500, seed=0).points
    rec = reconstruct(pts[pts[:, 0] <= 0.6], 2, mode="paper")
    ts = np.sort(rec.candidates.select("cocone"), axis=1)
    ext = extract_by_labels(rec.points, *_cells(rec), rec.candidates.faces, ts, rec.spacing)
    ratios = sorted(q for _, q in ext.opened)
    # the case this test is about (the ratios measure 5.88 and 6.04: a change of the labelling could move
    # them, which would change the case, not the rule)
    assert len(ratios) == 2 and CAP_RATIO < ratios[0] <= CAP_SURE < ratios[1], ratios
    assert ext.undecided == [] and not [f for f in ext.removed_features if f.kind == "hole"]
    m_s = ext.complex_at(ext.n_steps)
    top = analyse(m_s, rec.n, 2)
    assert top.betti == (1, 1, 0) and top.unused_samples == 0  # the cut tube: two rims
    holes = [f for f in weak_openings(features(rec.points, m_s, 2), ext.opened) if f.kind == "hole"]
    assert len(holes) == 2 and sum(f.uncertain for f in holes) == 1


def test_a_kept_cap_reaches_the_result_and_the_report_in_input_coordinates(tmp_path):
    """The elk (``resources/elk.off``) with noise of 0.1 h, numpy's draw 13 (``../shared/tools/noisy.py``'s
    model): the labelled M_S has one cap 3.7 times its ring and none over CAP_SURE, so open-cap keeps it
    closed.  The result is the closed genus-1 elk through every sample; the cap is an uncertain removed
    hole of ``rec.features``, at its samples in the input's coordinates, in the JSON report's
    ``uncertain_features`` and ``removed_features``, and counted in the summary's uncertain holes."""
    from pathlib import Path

    from scipy.spatial import cKDTree

    from crustview.cli_reconstruct import result_summary
    from crustview.io import read_points
    from crustview.report import report_dict

    pts = read_points(Path(__file__).resolve().parents[1] / "resources" / "elk.off")
    h = float(np.median(cKDTree(pts).query(pts, k=2)[0][:, 1]))
    noisy = pts + np.random.default_rng(13).normal(scale=0.1 * h, size=pts.shape)
    rec = reconstruct(noisy, 2, resample=False)
    top = rec.topology
    assert top.closed_manifold and top.betti == (1, 2, 1) and top.unused_samples == 0
    kept = [f for f in rec.features if f.kind == "hole"]
    assert len(kept) == 1 and kept[0].removed and kept[0].uncertain and "kept closed" in kept[0].reason
    # input coordinates: the location is the mean of the cap's samples, as given
    np.testing.assert_allclose(kept[0].location, rec.input_points[rec.point_input[kept[0].vertices]].mean(axis=0))
    rep = report_dict(rec)
    assert [u["kind"] for u in rep["uncertain_features"]].count("hole") == 1
    assert [u["kind"] for u in rep["removed_features"]].count("hole") == 1
    assert rep["features"]["hole"] == 0  # M_S itself has no hole
    assert "1 hole" in result_summary(rec, 1.0, tmp_path / "out.npz").split("(uncertain:")[1]


def test_boundary_vertices_of_a_complex():
    """The driver's rim test: vertices of ridges in one face (none on a closed tetrahedron's surface)."""
    from crustview.core.robust.verdict import _boundary_vertices

    assert _boundary_vertices(np.zeros((0, 3), np.int64)) == set()
    assert _boundary_vertices(np.array([[0, 1, 2]])) == {0, 1, 2}
    assert _boundary_vertices(np.array([[0, 1, 2], [1, 2, 3]])) == {0, 1, 2, 3}
    assert _boundary_vertices(np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])) == set()
    assert _boundary_vertices(np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3]])) == {1, 2, 3}


def test_descending_order_is_numpys_stable_argsort_of_the_negated_values():
    # by hand: 0.5 twice (in index order), then 0.0 and -0.0 as equals (index order), then -1
    v = np.array([0.0, 0.5, -1.0, -0.0, 0.5])
    assert labelling.descending_order(v).tolist() == [1, 4, 0, 3, 2]
    rng = np.random.default_rng(11)
    w = rng.random(200_000)
    w[rng.integers(0, len(w), 50_000)] = 0.25  # many ties
    w[:4] = [np.inf, -np.inf, 5e-324, -0.0]
    # the kernel's radix sort itself, which descending_order takes wherever it is built
    assert hasattr(labelling._kernel, "descending_order")
    for values in (v, w, w[:1], w[:0]):
        want = np.argsort(-values, kind="stable")
        assert np.array_equal(np.frombuffer(labelling._kernel.descending_order(values), np.int64), want)
        assert np.array_equal(labelling.descending_order(values), want)
    # NaN: numpy's order, and the kernel is not asked (it refuses NaN)
    nan = np.array([0.1, np.nan, 0.3])
    with pytest.raises(ValueError):
        labelling._kernel.descending_order(nan)
    assert labelling.descending_order(nan).tolist() == [2, 0, 1]  # by hand: 0.3, 0.1, then NaN last


@pytest.mark.parametrize("name", ["cow-head.off", "camelhead.off"])
def test_sculpting_never_carves_a_medial_ball_out(name, request):
    """Two open scans (their faces the truth) whose right results used to carry a fin of sliver faces
    where sculpt-sample carved a Delaunay ball spanning the head out (the cow's from an ear to the chin,
    51 spacings; the camel's 24): no face sculpt-sample adds, and no edge of M_S, is longer than twice the
    longest edge of the file's own mesh."""
    from pathlib import Path

    from crustview.core.steps import RULE_SCULPT
    from crustview.io import read_mesh

    mesh = read_mesh(Path(__file__).parent.parent / "resources" / name)
    pts = np.asarray(mesh.points, float)
    tris = np.asarray(mesh.simplices(2))
    # reconstruct(pts, 2); the camel's is tests/conftest.py's shared (read-only) run of the same file
    rec = request.getfixturevalue("camelhead_run") if name == "camelhead.off" else reconstruct(pts, 2)
    assert not rec.topology.closed_manifold and rec.topology.unused_samples == 0  # open, every sample a vertex
    assert tuple(rec.topology.betti) == tuple(analyse(tris, len(pts), 2).betti)
    ext = rec.extraction
    sculpted = [i for i, s in enumerate(ext.steps) if s.rule == RULE_SCULPT]
    assert sculpted  # the rule ran

    def longest(points, faces):
        p = points[faces]
        return max(float(np.linalg.norm(p[:, a] - p[:, b], axis=1).max()) for a, b in ((0, 1), (1, 2), (0, 2)))

    # another triangulation of the same samples may have somewhat longer edges; a carved ball's are 3.4 (camel)
    # and 11 (cow) times the mesh's longest
    bound = 2 * longest(pts, tris)
    for i in sculpted:
        assert longest(rec.points, ext.simplices[list(ext.steps[i].added)]) <= bound
    assert longest(rec.points, np.asarray(rec.manifold)) <= bound


def test_samples_the_size_bound_holds_back_are_not_left_out():
    """The horse (quads) at half its samples (numpy's draw 7, as ``bench_scans.py --subsample 0.5 --seed 7``):
    with sculpt-sample's size bound alone 11 samples ended up left out of a closed sphere; the labelled path
    then runs again with the held samples sculpted as before, and every sample is a vertex."""
    from pathlib import Path

    from crustview.io import read_mesh

    mesh = read_mesh(Path(__file__).parent.parent / "resources" / "horse-quads.obj")
    pts = np.asarray(mesh.points, float)
    half = pts[np.random.default_rng(7).random(len(pts)) < 0.5]
    rec = reconstruct(half, 2)
    t = rec.topology
    assert t.closed_manifold and tuple(t.betti) == (1, 0, 1) and t.unused_samples == 0
