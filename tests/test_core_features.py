"""Handles, holes and components of M_S, their sizes, and when the sample cannot support them."""

import json
import math

import numpy as np

from crustview.core import reconstruct
from crustview.core.analysis.dispute import disagreement
from crustview.core.analysis.features import (
    GAP_MIN,
    HOLE_SUPPORTED,
    LOOP_MIN,
    enclosing_cover,
    enclosing_radii,
    features,
    local_spacing,
    summary_suffix,
)
from crustview.core.analysis.loops import short_basis
from crustview.core.analysis.topology import analyse
from crustview.core.samples.manifolds import get_manifold
from crustview.report import report_dict


def _torus_mesh(nu: int, nv: int, r_big: float = 1.0, r_small: float = 0.4):
    """A triangulated torus on an nu x nv grid (genus 1, every vertex of degree 6)."""
    u, v = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a, b = 2 * np.pi * u.ravel() / nu, 2 * np.pi * v.ravel() / nv
    pts = np.c_[
        (r_big + r_small * np.cos(b)) * np.cos(a), (r_big + r_small * np.cos(b)) * np.sin(a), r_small * np.sin(b)
    ]
    idx = lambda i, j: (i % nu) * nv + (j % nv)  # noqa: E731
    tris = []
    for i in range(nu):
        for j in range(nv):
            tris += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
    return pts, np.array(tris)


def _torus_cocycles(nu: int, nv: int, r_big: float = 1.0, r_small: float = 0.4):
    """A grid torus (:func:`_torus_mesh`) and the cocycles of its short basis (every edge's class)."""
    from crustview.core.analysis.loops import capped, short_basis, triangle_edges

    pts, tris = _torus_mesh(nu, nv, r_big, r_small)
    edges, tri_edges = triangle_edges(tris)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    cocycles: dict = {}
    short_basis(*capped(pts, tris, edges, tri_edges, count), cocycles=cocycles)
    return pts, tris, cocycles


def test_enclosing_radius_on_paper():
    """Equilateral triangle of side 1: circumradius 1/sqrt(3); an obtuse one: half its longest edge."""
    p = np.array([[0, 0, 0], [1, 0, 0], [0.5, math.sqrt(3) / 2, 0], [0.5, 0.05, 0]], float)
    r = enclosing_radii(p, np.array([[0, 1, 2], [0, 1, 3]]))
    assert np.allclose(r, [1 / math.sqrt(3), 0.5])


def test_compiled_enclosing_cover_matches_numpy_on_paper_and_on_a_noisy_torus():
    """The compiled largest-radius-per-sample equals numpy's to rounding; 0 at a sample in no simplex."""
    p = np.array([[0, 0, 0], [1, 0, 0], [0.5, math.sqrt(3) / 2, 0], [0.5, 0.05, 0], [9, 9, 9]], float)
    tris = np.array([[0, 1, 2], [0, 1, 3]])
    cover = enclosing_cover(p, tris)
    assert np.allclose(cover, [1 / math.sqrt(3)] * 3 + [0.5, 0.0], rtol=1e-14, atol=0)
    rng = np.random.default_rng(5)
    pts, tris = _torus_mesh(400, 80)  # 64,000 triangles: the two-thread split
    pts = pts + rng.normal(scale=0.003, size=pts.shape)
    for simplices in (tris, tris[:, :2], np.c_[tris, (tris[:, 0] + 1) % len(pts)]):  # d = 2, 1, 3
        fast = enclosing_cover(pts, simplices)
        slow = enclosing_cover(pts, simplices, compiled=False)
        assert fast.flags.writeable and (fast > 0).all()
        assert np.allclose(fast, slow, rtol=1e-12, atol=0)


def test_local_spacing_of_samples_in_no_simplex_is_their_nearest_neighbour():
    """Covered samples get their largest enclosing radius, the others their nearest-neighbour distance."""
    p = np.array([[0, 0, 0], [1, 0, 0], [0.5, math.sqrt(3) / 2, 0], [5, 0, 0], [5, 0.25, 0]], float)
    h = local_spacing(p, np.array([[0, 1, 2]]))
    assert np.allclose(h, [1 / math.sqrt(3)] * 3 + [0.25, 0.25])
    q = np.r_[p, p[3:4]]  # a duplicate of an uncovered sample: the median positive distance, 1 (of 1, 1, 1, 0.25)
    h = local_spacing(q, np.array([[0, 1, 2]]))
    assert np.allclose(h, [1 / math.sqrt(3)] * 3 + [1.0, 0.25, 1.0])


def test_torus_loops_are_its_two_circles():
    """A grid torus has a basis of two loops: around the tube (nv edges) and around the hole (nu)."""
    pts, tris = _torus_mesh(24, 10)
    edges = np.unique(np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]]), axis=1), axis=0)
    key = {tuple(e): i for i, e in enumerate(edges.tolist())}
    tri_edges = np.array([[key[tuple(sorted(t[[a, b]]))] for a, b in ((0, 1), (1, 2), (0, 2))] for t in tris])
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    basis = short_basis(pts, tris, edges, tri_edges, count, len(pts))
    lengths = sorted(length for _, length in basis)
    assert len(basis) == 2
    tube = 10 * 2 * 0.4 * math.sin(math.pi / 10)  # the tube circle, 10 chords
    assert lengths[0] == pytest_approx(tube)
    assert lengths[1] < 2 * math.pi * 1.4


def pytest_approx(x, rel: float = 1e-9):
    import pytest

    return pytest.approx(x, rel=rel)


def test_well_sampled_torus_handle_is_supported_and_a_thin_one_is_not():
    """Loop length in sampling radii: 10 samples around the tube pass, 4 around it do not."""
    pts, tris = _torus_mesh(40, 10)
    f = [x for x in features(pts, tris, 2) if x.kind == "handle"]
    assert len(f) == 2 and not any(x.uncertain for x in f)
    assert min(x.size_spacings for x in f) > LOOP_MIN
    thin, ttris = _torus_mesh(40, 4, r_small=0.12)
    g = [x for x in features(thin, ttris, 2) if x.kind == "handle"]
    short = min(g, key=lambda x: x.size_spacings)
    assert short.uncertain and short.size_spacings < LOOP_MIN and len(short.vertices) >= 4


def test_two_spheres_that_nearly_touch_are_uncertain_components():
    """Two unit spheres whose surfaces are 0.02 apart, far below the spacing: joined into one closed surface,
    and the join is named (never a sure answer), between the two spheres' samples, under GAP_MIN; 5 radii
    apart: two spheres, nothing named."""
    m = get_manifold("sphere")
    s = m.sample(400, seed=0).points
    rng_gap = 2.0 + 0.02  # the spheres' surfaces 0.02 apart, far below the spacing
    pts = np.vstack([s, s + [rng_gap, 0, 0]])
    rec = reconstruct(pts, 2)
    assert rec.topology.components == 1 and rec.topology.closed_manifold  # joined: what the sample shows
    comps = [x for x in rec.features if x.kind == "component"]
    assert comps and all(x.uncertain for x in comps)
    (join,) = [x for x in comps if x.reason.startswith("joined (rule join-parts)")]
    ends = np.asarray(rec.point_input)[np.asarray(join.vertices)]
    assert sorted(e >= 400 for e in ends) == [False, True]  # one sample of each sphere
    assert join.size_spacings < GAP_MIN
    far = reconstruct(np.vstack([s, s + [5.0, 0, 0]]), 2)
    assert far.topology.components == 2 and not far.uncertain_features


def test_clean_builtins_carry_no_uncertain_feature_and_the_report_says_so():
    for name in ("torus", "sphere"):
        m = get_manifold(name)
        rec = reconstruct(m.sample(m.default_n, seed=0).points, 2)
        assert rec.uncertain_features == []
        rep = report_dict(rec)
        assert rep["uncertain_features"] == []
        assert rep["features"]["handle"] == sum(m.betti[1:2])
        assert summary_suffix(rec.features) == ""
        json.dumps(rep)


def test_holes_of_an_open_surface_are_measured():
    """A grid cylinder (an annulus) has two boundary loops, each as wide as the cylinder."""
    pts, tris = _torus_mesh(24, 10)
    keep = ~np.isin(tris, np.arange(10)).any(axis=1)  # cut the ring u = 0 away: a tube open at both ends
    hol = [x for x in features(pts, tris[keep], 2) if x.kind == "hole"]
    assert len(hol) == 2 and not any(x.uncertain for x in hol)
    # the rings next to the cut (u = 1 and u = 23), each a regular 10-gon of radius 0.4: 0.8 across
    rims = sorted(sorted(np.asarray(x.vertices).tolist()) for x in hol)
    assert rims == [list(range(10, 20)), list(range(230, 240))]
    assert all(x.size_spacings > 2 for x in hol)


def test_summary_suffix_and_json():
    pts, tris = _torus_mesh(40, 4, r_small=0.12)
    f = features(pts, tris, 2)
    text = summary_suffix(f)
    # the torus's two loops: round the thin tube, its 4 samples (under LOOP_MIN: uncertain), and round the
    # ring, through 40 (sure)
    tube, ring = sorted((x for x in f if x.kind == "handle"), key=lambda x: x.size_spacings)
    assert len(tube.vertices) == 4 and tube.uncertain and not ring.uncertain and len(set(ring.vertices)) >= 40
    assert text == "(uncertain: 1 handles, 0 holes, 0 components)"
    d = f[0].as_dict()
    assert set(d) >= {"kind", "location", "size_spacings"} and len(d["location"]) == 3


def test_disagreement_places_a_handle_where_the_two_differ():
    pts, tris = _torus_mesh(24, 10)
    # a sphere-like alternative: the same grid with one ring of the tube pinched shut is not closed,
    # so compare with itself minus one face and plus another: only the Betti numbers matter here
    other = tris[1:]
    feats = disagreement(pts, tris, other, (1, 2, 1), (1, 0, 1))
    assert [x.kind for x in feats] == ["handle"] and feats[0].uncertain and feats[0].disputed
    # where the two differ: the one face only the first has, its samples and their middle
    assert sorted(np.asarray(feats[0].vertices).tolist()) == sorted(tris[0].tolist())
    assert np.allclose(feats[0].location, pts[tris[0]].mean(axis=0))


def test_a_dispute_over_a_whole_surface_marks_its_middle_not_every_sample():
    """Two triangulations of the same grid torus, the squares cut along opposite diagonals: every face
    differs, so the differing faces say nothing local.  The handle's samples are those within REACH local
    spacings of the middle (a new user's footbones dispute selected 1,388 of 2,154 samples)."""
    from crustview.core.analysis.dispute import REACH

    pts, tris = _torus_mesh(48, 16)
    nv = 16
    idx = lambda i, j: (i % 48) * nv + (j % nv)  # noqa: E731
    flipped = np.array(
        [
            t
            for i in range(48)
            for j in range(nv)
            for t in ((idx(i, j), idx(i + 1, j), idx(i, j + 1)), (idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)))
        ]
    )
    (f,) = disagreement(pts, tris, flipped, (1, 2, 1), (1, 0, 1))
    h = local_spacing(pts, tris)
    assert f.kind == "handle" and f.disputed and 3 <= len(f.vertices) < len(pts) // 4
    middle = pts[f.vertices]
    reach = np.linalg.norm(middle[:, None] - middle[None], axis=2).max()
    assert reach <= 2 * REACH * np.median(h) + 1e-9  # within REACH of one sample, in the group's median spacing


def test_a_disputed_component_is_placed_where_the_parts_come_closest():
    """Two grid tori side by side: where one answer has two components and the other one, the dispute is
    the closest two vertices of different tori (brute force), its size their distance in local spacings."""
    a, ta = _torus_mesh(24, 10)
    b = a + np.array([2.9, 0.3, 0.1])
    pts, tris = np.vstack([a, b]), np.vstack([ta, ta + len(a)])
    (f,) = disagreement(pts, tris, tris, (2, 4, 2), (1, 4, 1))
    d = np.linalg.norm(a[:, None] - b[None], axis=2)
    i, j = np.unravel_index(np.argmin(d), d.shape)
    assert f.kind == "component" and sorted(f.vertices.tolist()) == [i, len(a) + j]
    assert np.allclose(f.location, (a[i] + b[j]) / 2)
    h = local_spacing(pts, tris)
    assert np.isclose(f.size_spacings, d[i, j] / np.median(h[[i, len(a) + j]]))


def test_a_disputed_component_is_where_the_other_result_joins_not_the_closest_pair():
    """Three tori A, B, C, A and B closest; the other result joins B and C by one triangle: the dispute is at
    B-C (a review found the closest pair A-B marked instead)."""
    a, ta = _torus_mesh(24, 10)
    n = len(a)
    b, c = a + np.array([2.9, 0, 0]), a + np.array([6.0, 0, 0])
    pts, kept = np.vstack([a, b, c]), np.vstack([ta, ta + n, ta + 2 * n])
    d = np.linalg.norm(b[:, None] - c[None], axis=2)
    i, j = np.unravel_index(np.argmin(d), d.shape)
    k = next(v for v in next(t for t in ta if i in t) if v != i)
    other = np.vstack([kept, [[n + i, 2 * n + j, n + k]]])
    (f,) = disagreement(pts, kept, other, (3, 6, 3), (2, 6, 2))
    assert f.kind == "component" and sorted((f.vertices // n).tolist()) == [1, 2]
    assert np.allclose(f.location, (b[i] + c[j]) / 2)


def test_disagreement_of_two_open_results_names_the_extra_hole():
    """Two manifolds with boundary: a grid sheet (a disk) and the same sheet with one inner triangle
    missing (an annulus, b1 = 1).  They differ by a hole, not a handle: one uncertain hole, at the
    missing triangle."""
    pts, tris = _sheet(8, 8, 1.0, 1.0, 0.0)
    centre = np.flatnonzero(np.all(np.isin(tris, [27, 28, 35, 36]), axis=1))[0]  # a triangle in the middle
    holed = np.delete(tris, centre, axis=0)
    assert analyse(holed, len(pts), 2).betti == (1, 1, 0) and analyse(tris, len(pts), 2).betti == (1, 0, 0)
    (f,) = disagreement(pts, holed, tris, (1, 1, 0), (1, 0, 0))
    assert f.kind == "hole" and f.uncertain and f.disputed and "boundary loops = 2 kept, 1 in the other" in f.reason
    assert np.allclose(f.location, pts[tris[centre]].mean(axis=0))


def test_disagreement_where_rims_pinch_compares_b1():
    """Two holes touching at a vertex count as one boundary loop, and the topology report counts pinched
    vertices on closed complexes only: the genus from b0 + b1 - b2 - loops comes out odd.  Then the
    difference is named by b1, as for curves (a review's case: "2 g = 3 kept" before)."""
    pts, tris = _sheet(8, 8, 1.0, 1.0, 0.0)
    a = np.flatnonzero(np.all(np.isin(tris, [18, 19, 26, 27]), axis=1))[0]
    b = np.flatnonzero(np.all(np.isin(tris, [27, 28, 35, 36]), axis=1))
    b = next(int(t) for t in b if len(set(tris[t]) & set(tris[a])) == 1)  # shares the vertex 27 only
    pinched = np.delete(tris, [a, b], axis=0)
    betti = analyse(pinched, len(pts), 2).betti
    assert betti == (1, 2, 0) and not analyse(pinched, len(pts), 2).closed_manifold
    (f,) = disagreement(pts, pinched, tris, betti, (1, 0, 0))
    assert f.kind == "handle" and "b1 = 2 kept, 0 in the other" in f.reason
    # and on curves (two Betti numbers) the same comparison, no genus
    t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    ring = np.c_[np.cos(t), np.sin(t)]
    edges = np.c_[np.arange(12), (np.arange(12) + 1) % 12]
    (g,) = disagreement(ring, edges, edges[:6], (1, 1), (1, 0))
    assert g.kind == "handle" and g.disputed


def test_local_spacing_sees_the_sparse_direction():
    """On long thin triangles the nearest neighbour is along the ring; the sampling radius is across."""
    pts, tris = _torus_mesh(200, 6)  # 200 around the hole (dense), 6 around the tube (sparse)
    nn = local_spacing(pts)
    h = local_spacing(pts, tris)
    assert np.median(h) > 3 * np.median(nn)
    assert analyse(tris, len(pts), 2).betti == (1, 2, 1)


def _sheet(nx: int, ny: int, ax: float, ay: float, z: float):
    """A flat grid sheet at height z, ax apart along x and ay along y, as points and triangles."""
    x, y = np.meshgrid(np.arange(nx) * ax, np.arange(ny) * ay, indexing="ij")
    pts = np.c_[x.ravel(), y.ravel(), np.full(nx * ny, z)]
    idx = lambda i, j: i * ny + j  # noqa: E731
    tris = [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)) for i in range(nx - 1) for j in range(ny - 1)]
    tris += [(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)) for i in range(nx - 1) for j in range(ny - 1)]
    return pts, np.array(tris)


def test_two_walls_closer_than_the_sparse_spacing_are_uncertain_components():
    """Two parallel sheets 2.5 dense spacings apart.  Sampled 3 times sparser across rows than along
    them (thin triangles), they are closer than two sampling radii (h = the triangles' circumradius,
    1.58 dense spacings): uncertain, though 2.5 nearest-neighbour distances apart.  Sampled evenly
    (h = 0.71), the same gap is resolved."""
    for ay, flagged in ((3.0, True), (1.0, False)):
        a, ta = _sheet(30, int(30 / ay), 1.0, ay, 0.0)
        b, tb = _sheet(30, int(30 / ay), 1.0, ay, 2.5)
        pts, tris = np.vstack([a, b]), np.vstack([ta, tb + len(a)])
        comps = [f for f in features(pts, tris, 2) if f.kind == "component"]
        assert len(comps) == 2
        assert all(f.uncertain == flagged for f in comps), (ay, [f.size_spacings for f in comps])


def test_two_holes_with_a_strip_narrower_than_two_spacings_between_them_are_uncertain():
    """Two square holes cut in a grid sheet (spacing 1), one row of faces apart: the strip between
    them is 1 spacing wide, below GAP_MIN, so both are uncertain (one opening with a ribbon left
    across it, or a strip the sample cannot resolve); 4 spacings apart, neither is."""
    pts, tris = _sheet(20, 24, 1.0, 1.0, 0.0)
    cen = pts[tris].mean(axis=1)

    def cut(y0: float, y1: float):
        return (cen[:, 0] > 3) & (cen[:, 0] < 8) & (cen[:, 1] > y0) & (cen[:, 1] < y1)

    for second, flagged in ((9.0, True), (12.0, False)):
        keep = ~(cut(3, 8) | cut(second, second + 5))
        holes = [f for f in features(pts, tris[keep], 2) if f.kind == "hole" and f.size_spacings < 20]
        assert len(holes) == 2
        assert all(f.uncertain == flagged for f in holes), (second, [f.reason for f in holes])


def test_the_loop_search_is_skipped_exactly_when_b1_is_zero():
    """no_loops by Euler-Poincare: an octahedron and two octahedra sharing a vertex (b1 = 0) skip the
    loop basis; a torus (b1 = 2) and an open sheet do not, and the torus keeps its two handles."""
    from crustview.core.analysis import loops
    from crustview.core.analysis.loops import triangle_edges

    octa = np.array([[0, 2, 4], [0, 2, 5], [0, 3, 4], [0, 3, 5], [1, 2, 4], [1, 2, 5], [1, 3, 4], [1, 3, 5]])
    wedge = np.vstack([octa, np.where(octa == 0, 0, octa + 5)])  # the second one shares vertex 0

    def no_loops(tris, n):
        e, te = triangle_edges(tris)
        return loops.no_loops(tris, e, te, np.bincount(te.ravel(), minlength=len(e)), n)

    assert no_loops(octa, 6) and no_loops(wedge, 11)
    assert analyse(wedge, 11, 2).betti[1] == 0
    pts, tris = _torus_mesh(24, 12)
    assert not no_loops(tris, len(pts))
    assert len([f for f in features(pts, tris, 2) if f.kind == "handle"]) == 2
    _, sheet = _sheet(5, 5, 1.0, 1.0, 0.0)
    assert not no_loops(sheet, 25)


def test_is_closed_manifold_agrees_with_the_full_report():
    """The quick test gives analyse()'s closed_manifold on closed, open, pinched and non-manifold complexes."""
    from crustview.core.analysis.topology import analyse, is_closed_manifold

    tet = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])
    pinched = np.vstack([tet, tet + 3])  # two tetrahedra sharing vertex 3
    fin = np.vstack([tet, [[0, 1, 4]]])  # an extra triangle on edge 0-1: non-manifold
    for cx in (tet, tet[:3], pinched, fin, np.zeros((0, 3), np.int64)):
        assert is_closed_manifold(cx, 2) == analyse(cx, 8, 2).closed_manifold
    assert is_closed_manifold(tet, 2) and not is_closed_manifold(pinched, 2) and not is_closed_manifold(fin, 2)


def test_the_report_names_the_samples_left_out():
    """left_out_samples: the input rows of exactly the samples that are no vertex of M_S, with a
    duplicate input row reported by its first occurrence."""
    from crustview.core import reconstruct
    from crustview.report import report_dict

    pts = get_manifold("sphere").sample(400, seed=3).points
    pts = np.vstack([pts, pts[:1]])  # row 400 duplicates row 0
    rec = reconstruct(pts, 2, mode="paper")
    rep = report_dict(rec)
    assert rep["left_out_samples"] == []  # the paper's sphere uses every sample
    # drop the simplices of three samples: those and only those are named, as input rows
    gone = [5, 17, 0]
    keep = ~np.isin(rec.manifold, [int(rec.input_index[g]) for g in gone]).any(axis=1)
    from dataclasses import replace

    cut = replace(rec, manifold=rec.manifold[keep])
    used = np.zeros(rec.n, bool)
    used[cut.manifold.ravel()] = True
    want = sorted(int(rec.point_input[i]) for i in np.flatnonzero(~used))
    got = report_dict(cut)["left_out_samples"]
    assert got == want and set(gone) <= set(got) and 400 not in got


def test_a_handle_between_the_two_bounds_is_uncertain_for_its_own_reason():
    """A tube of 5 samples around: its loop is above 2 pi but below 4 pi sampling radii, resolved only
    by a sample coarser than eps = 1/2, so uncertain with that reason; 9 around is above 4 pi."""
    from crustview.core.analysis.features import LOOP_SUPPORTED

    for around, unc in ((5, True), (9, False)):
        pts, tris = _torus_mesh(40, around)
        short = min((x for x in features(pts, tris, 2) if x.kind == "handle"), key=lambda x: x.size_spacings)
        assert short.uncertain == unc
        if unc:
            assert LOOP_MIN <= short.size_spacings < LOOP_SUPPORTED and "eps = 1/2" in short.reason
        else:
            assert short.size_spacings >= LOOP_SUPPORTED


def test_a_round_loop_never_comes_back_near_itself_and_a_stadium_does_at_its_width():
    """Twelve vertices on the unit circle: the shorter arc between two of them is at most pi / 2 times
    their chord, so no pair counts, whatever the spacing.  A stadium 1 long and 0.2 wide, in radii of
    0.15: its two sides are 1.33 radii apart, and the pairs that count are at least pi * 2 radii apart
    along it (straight across: 0.37 or more from either end); 0.2 wide in radii of 0.05 (4 radii) none."""
    from crustview.core.analysis.necks import close_pairs

    n = 12
    ring = np.c_[np.cos(2 * np.pi * np.arange(n) / n), np.sin(2 * np.pi * np.arange(n) / n), np.zeros(n)]
    for h in (1.0, 0.5, 0.2, 0.05):
        assert close_pairs(ring, np.arange(n), np.full(n, h), GAP_MIN) == []
    x = np.linspace(0, 1, 11)
    stadium = np.r_[np.c_[x, np.zeros(11), np.zeros(11)], np.c_[x[::-1], np.full(11, 0.2), np.zeros(11)]]
    pairs = close_pairs(stadium, np.arange(22), np.full(22, 0.15), GAP_MIN)
    assert pairs and pairs[0][0] == pytest_approx(0.2 / 0.15)
    for _, i, j in pairs:
        assert stadium[i, 1] != stadium[j, 1]  # the two sides, not along one of them
    # straight across only where the loop between them is pi * 2 radii or longer: at 0.4, 0.5 and 0.6
    across = sorted(round(stadium[i, 0], 9) for w, i, j in pairs if w == pytest_approx(0.2 / 0.15))
    assert across == [0.4, 0.5, 0.6]
    assert close_pairs(stadium, np.arange(22), np.full(22, 0.05), GAP_MIN) == []


def test_a_loop_comes_back_near_itself_anywhere_along_it_not_only_half_way():
    """A circle of radius 1 with a finger 0.1 wide and 1 long, in radii of 0.08: the finger's two sides
    are 1.25 radii apart, and the narrowest pairs are across it, while the points half the loop on from
    them are on the far side of the circle (the rule of comparing those alone would not see the finger)."""
    from crustview.core.analysis.necks import close_pairs, walk_length

    t = np.linspace(0.05, 2 * np.pi - 0.05, 60)  # from just above the finger round to just below it
    out = np.linspace(1.0, 2.0, 11)
    xy = np.r_[np.c_[np.cos(t), np.sin(t)], np.c_[out, np.full(11, -0.05)], np.c_[out[::-1], np.full(11, 0.05)]]
    loop = np.c_[xy, np.zeros(len(xy))]
    h = np.full(len(loop), 0.08)
    pairs = close_pairs(loop, np.arange(len(loop)), h, GAP_MIN)
    width, i, j = pairs[0]
    assert width == pytest_approx(0.1 / 0.08, rel=1e-3)  # (the circle's two ends are 0.0999 apart)
    assert loop[i, 0] > 0.99 and loop[j, 0] > 0.99 and loop[i, 1] == pytest_approx(-loop[j, 1])
    half = walk_length(loop, np.arange(len(loop))) / 2
    at = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(loop, axis=0), axis=1))]
    opposite = loop[np.argmin(np.abs(at - (at[i] + half) % (2 * half)))]
    assert np.linalg.norm(opposite - loop[i]) > 9 * GAP_MIN * 0.08  # across the circle: no neck there


def test_a_walk_loses_its_spurs():
    """A step straight back takes both steps out, cyclically too; the class over Z/2 is the same."""
    from crustview.core.analysis.necks import reduced

    assert reduced(np.array([0, 1, 2, 3, 2, 1, 4, 5])).tolist() == [0, 1, 4, 5]
    assert reduced(np.array([9, 0, 1, 2, 0])).tolist() == [0, 1, 2]
    assert reduced(np.array([0, 0, 1, 1, 2])).tolist() == [0, 1, 2]
    # the same closed walk from any start reduces to the same cycle
    walk = [0, 1, 2, 0, 5]
    for k in range(len(walk)):
        assert sorted(reduced(np.roll(walk, k)).tolist()) == [0, 1, 2]


def test_a_handle_around_a_part_thinner_than_two_sheets_resolve_is_uncertain():
    """A torus whose tube is flattened to a ring 2b thick: its short loop goes round the flat tube, and
    its top and bottom points, half the loop apart, are 2b apart.  At 4 % of its height that is about
    1.1 sampling radii, below GAP_MIN, while the loop is 56 radii long (far above 4 pi): uncertain for
    the neck alone.  At 20 % (4.5 radii) and round (21) it is sure."""
    from crustview.core.analysis.features import LOOP_SUPPORTED

    for flat, unc in ((0.05, True), (0.2, False), (1.0, False)):
        pts, tris = _torus_mesh(200, 40)
        pts[:, 2] *= flat
        handles = [x for x in features(pts, tris, 2) if x.kind == "handle"]
        assert len(handles) == 2
        short = min(handles, key=lambda x: x.size_spacings)
        assert short.size_spacings >= LOOP_SUPPORTED
        assert short.uncertain == unc
        assert ("neck" in short.reason) == unc
        assert not max(handles, key=lambda x: x.size_spacings).uncertain  # the loop along the ring is wide
    assert GAP_MIN == 2.0


def test_handles_of_an_open_surface_are_found_whatever_its_holes():
    """A grid torus with square holes cut in it (genus 1, k holes: b1 = 2 + k - 1) has exactly its two
    handle loops, the tube's and the ring's, however many holes there are and wherever they lie; the
    annulus (genus 0, two holes) has none.  The loops are on the surface, not through the holes' caps."""
    pts, tris = _torus_mesh(40, 12)
    cen_u = np.repeat(np.arange(40), 12 * 2)  # each triangle's grid cell (u, v), from _torus_mesh's order
    cen_v = np.tile(np.repeat(np.arange(12), 2), 40)
    for cells in ([(5, 3)], [(5, 3), (20, 8)], [(2, 2), (12, 5), (25, 9), (33, 0)]):
        cut = np.zeros(len(tris), bool)
        for u0, v0 in cells:
            cut |= (np.abs(cen_u - u0) <= 1) & (np.abs(cen_v - v0) <= 1)
        t = tris[~cut]
        assert analyse(t, len(pts), 2).betti == (1, 2 + len(cells) - 1, 0)
        f = features(pts, t, 2)
        handles = [x for x in f if x.kind == "handle"]
        assert len([x for x in f if x.kind == "hole"]) == len(cells)
        assert len(handles) == 2, cells
        assert all(len(x.vertices) and x.vertices.max() < len(pts) for x in handles)
        tube = 12 * 2 * 0.4 * math.sin(math.pi / 12)
        assert min(x.size_spacings for x in handles) * np.median(local_spacing(pts, t)) <= 1.2 * tube
    keep = ~np.isin(tris, np.arange(12)).any(axis=1)  # the annulus: the torus cut open across its tube
    assert not [x for x in features(pts, tris[keep], 2) if x.kind == "handle"]


def test_a_hole_between_the_two_bounds_is_uncertain_for_its_own_reason():
    """A hole's rim is a loop: below LOOP_MIN / pi spacings across no eps < 1 sample shows it, below
    HOLE_SUPPORTED = LOOP_SUPPORTED / pi only a sample coarser than eps = 1/2 does (uncertain), above
    it the hole is sure.  Holes of 1 x 2 cells (span sqrt(5) over the sampling radius sqrt(2) / 2:
    3.16) and 3 x 3 cells (6) in a unit grid sheet."""
    pts, tris = _sheet(24, 24, 1.0, 1.0, 0.0)
    cen = pts[tris].mean(axis=1)
    sizes = {}
    for w, h in ((1, 2), (3, 3)):
        cut = (cen[:, 0] > 8) & (cen[:, 0] < 8 + w) & (cen[:, 1] > 8) & (cen[:, 1] < 8 + h)
        hole = [f for f in features(pts, tris[~cut], 2) if f.kind == "hole" and f.size_spacings < 20]
        assert len(hole) == 1
        f = hole[0]
        sizes[w, h] = f.size_spacings
        assert f.uncertain == (f.size_spacings < HOLE_SUPPORTED)
        assert ("coarser than eps = 1/2" in f.reason) == f.uncertain  # the band's own reason
    assert HOLE_SUPPORTED == 4.0 == 2 * LOOP_MIN / math.pi
    assert sizes[1, 2] == pytest_approx(math.sqrt(5) / (math.sqrt(2) / 2))
    assert sizes[3, 3] == pytest_approx(6.0)


def test_an_open_surface_with_too_many_loops_is_reported_not_indexed_past_its_points(monkeypatch):
    """Past MAX_LOOPS the basis is not searched: an open surface (its caps' apexes appended) gets the one
    placeholder handle, located among its own samples."""
    from crustview.core.analysis import loops

    monkeypatch.setattr(loops, "MAX_LOOPS", 1)
    pts, tris = _torus_mesh(40, 12)
    f = [x for x in features(pts, tris[6:], 2) if x.kind == "handle"]
    assert len(f) == 1 and f[0].uncertain and "too many handles" in f[0].reason
    assert np.all(f[0].location >= pts.min(axis=0)) and np.all(f[0].location <= pts.max(axis=0))


def test_the_hands_fused_fingers_at_half_density_are_an_uncertain_handle():
    """resources/hand-half-result.npz: M_S as the robust extraction made it from a random half of the hand's
    vertices (../shared/data/scans2/hand.off, numpy's draw 7 keeping each with probability 1/2), renumbered
    to the samples it uses.  The hand (an OK sign) is an open genus 1; this M_S is an open genus 2: two
    fingers about one spacing apart are joined.  The basis search measured the extra handle's loops at 17.7
    and 41.3 sampling radii, above both length bounds: a wrong answer without a flag.  Each of them runs out
    and comes back within two radii of itself; the shortcut there leaves a shorter loop of the same class
    (8.4 and 6.4 radii), which only a sample coarser than eps = 1/2 resolves: uncertain.  The real handle
    (the ring of thumb and finger) and its long loop stay sure."""
    from pathlib import Path

    from crustview.core.analysis.features import LOOP_SUPPORTED

    data = np.load(Path(__file__).resolve().parents[1] / "resources" / "hand-half-result.npz")
    pts, tris = data["points"], data["triangles"].astype(np.int64)
    topo = analyse(tris, len(pts), 2)
    assert tuple(topo.betti) == (1, 4, 0) and not topo.closed_manifold  # the wrong answer
    handles = [f for f in features(pts, tris, 2) if f.kind == "handle"]
    assert len(handles) == 4
    unsure = [f for f in handles if f.uncertain]
    assert len(unsure) == 2
    assert all(f.size_spacings < LOOP_SUPPORTED for f in unsure)  # 8.4 and 6.4: below what eps = 1/2 resolves
    assert all(f.size_spacings > 30 for f in handles if not f.uncertain)


def test_the_camel_heads_false_handle_under_noise_is_uncertain():
    """resources/camelhead-n30-s23-result.npz: M_S as the robust extraction made it from the camel head
    with noise 0.3 h (../shared/tools/noisy.py, draw 23), renumbered to the samples it uses.  The camel head
    is an open disk; this M_S has a handle (b1 = 2, one hole), a false bridge.  Until session 18
    the basis search measured its loops at 22.8 and 82 sampling radii, above both bounds, and neither comes
    back near the point half of it on: a wrong answer without a flag.  Two things now see the bridge's
    short loop, each on its own: tightening where the loop comes back near itself anywhere along it
    (10.8 radii), and the search itself once the hole's cap edges no longer fall among the tree-cotree
    split's leftover edges (4.1 radii): either way under 4 pi, uncertain."""
    from pathlib import Path

    from crustview.core.analysis.features import LOOP_SUPPORTED

    data = np.load(Path(__file__).resolve().parents[1] / "resources" / "camelhead-n30-s23-result.npz")
    pts, tris = data["points"], data["triangles"].astype(np.int64)
    topo = analyse(tris, len(pts), 2)
    assert tuple(topo.betti) == (1, 2, 0) and not topo.closed_manifold  # the wrong answer
    for tightened in (True, False):
        handles = [f for f in features(pts, tris, 2, tighten_loops=tightened) if f.kind == "handle"]
        assert len(handles) == 2
        short = min(handles, key=lambda f: f.size_spacings)
        assert short.uncertain and short.size_spacings < LOOP_SUPPORTED


def test_no_handle_loop_of_an_open_surface_runs_through_a_holes_cap():
    """resources/plastic-vase-n30-s21-grown.npz: an M_S the growing path made from the plastic vase with
    noise 0.3 h (noise draw 21, under a labelling variant that was not kept): open, b1 = 79, 8 holes.  Its
    holes are capped by cones from far apexes before the basis is taken; the tree-cotree split had left a
    cap edge over, and the basis had a handle whose only loop found ran through a cap (an assertion
    stopped the run).  The caps' edges now go into the cotree first: all 36 handles' 72 loops lie on
    M_S."""
    from pathlib import Path

    data = np.load(Path(__file__).resolve().parents[1] / "resources" / "plastic-vase-n30-s21-grown.npz")
    pts, tris = data["points"], data["triangles"].astype(np.int64)
    topo = analyse(tris, len(pts), 2)
    assert tuple(topo.betti) == (1, 79, 0)
    handles = [f for f in features(pts, tris, 2) if f.kind == "handle"]
    assert len(handles) == 72
    assert all("through a hole" not in f.reason and (f.vertices < len(pts)).all() for f in handles)


def test_a_loop_that_comes_back_near_itself_is_shortened_to_its_class():
    """A grid torus's meridian with a detour: it runs 10 columns along the tube and comes back one row
    over.  The detour's two sides are a row (far less than two sampling radii) apart, and closing it
    leaves a null-homologous loop: the excursion is cut off, and what is left is a meridian (the same
    class) within a few edges of the grid's own."""
    from crustview.core.analysis.necks import tighten, walk_class, walk_length

    nu, nv = 60, 12
    pts, tris, cocycles = _torus_cocycles(nu, nv)
    idx = lambda i, j: (i % nu) * nv + (j % nv)  # noqa: E731
    meridian = [idx(0, j) for j in range(nv)]
    detour = [idx(0, 0)] + [idx(i, 1) for i in range(0, 11)] + [idx(i, 2) for i in range(10, -1, -1)]
    detour += [idx(0, j) for j in range(3, nv)]
    h = local_spacing(pts, tris)
    loop, neck = tighten(pts, np.array(detour), h, cocycles, GAP_MIN)
    length = lambda w: walk_length(pts, w)  # noqa: E731
    step = np.linalg.norm(pts[idx(1, 0)] - pts[idx(0, 0)])  # one column along the tube
    # with no round to spare, the detour is not known to be one: its narrow place counts as a neck
    assert tighten(pts, np.array(detour), h, cocycles, GAP_MIN, rounds=0)[1] < GAP_MIN
    assert neck == math.inf
    assert length(np.array(detour)) - length(loop) > 15 * step  # the 2 x 10-column excursion is gone
    assert length(np.array(meridian)) <= length(loop) < length(np.array(meridian)) + 2 * step
    assert (walk_class(loop, cocycles) == walk_class(meridian, cocycles)).all()


def _figure_eight(n: int):
    """A grid torus with R = 2 r and n x n vertices (its inner equator as long as a meridian), its cocycles,
    and the meridian and the inner equator through one vertex (vertex lists)."""
    pts, tris, cocycles = _torus_cocycles(n, n, 1.0, 0.5)
    idx = lambda i, j: (i % n) * n + (j % n)  # noqa: E731
    return pts, tris, cocycles, [idx(0, n // 2 + k) for k in range(n)], [idx(k, n // 2) for k in range(n)]


def test_a_loop_that_is_two_handle_loops_meeting_at_a_point_has_a_neck():
    """A figure eight on a grid torus whose inner equator is as long as its meridians (R = 2 r, as many
    columns as rows): the meridian through a vertex of the inner equator, then the inner equator.  Half the
    loop on from that vertex is the vertex itself, and both halves go round the torus: a neck of width 0."""
    from crustview.core.analysis.necks import tighten, walk_class

    n = 40
    pts, tris, cocycles, meridian, equator = _figure_eight(n)
    eight = np.array(meridian + equator)
    assert walk_class(meridian, cocycles).any() and walk_class(equator, cocycles).any()
    loop, neck = tighten(pts, eight, local_spacing(pts, tris), cocycles, GAP_MIN)
    assert neck < 1e-9 and len(loop) == 2 * n  # (rounding of the interpolation)


def test_a_basis_loop_round_two_handles_is_replaced_by_the_part_the_others_do_not_span():
    """The same figure eight as one loop of a basis whose other loop is the meridian: of its two halves
    the meridian is in the others' span and the equator is not, so the equator replaces the figure eight
    (the basis stays a basis, its loop for this handle half as long) and there is no neck.  With the
    equator as the other loop, the meridian is kept instead."""
    from crustview.core.analysis.necks import tighten, walk_class, walk_length

    pts, tris, cocycles, meridian, equator = _figure_eight(40)
    eight = np.array(meridian + equator)
    h = local_spacing(pts, tris)
    for other, kept in ((meridian, equator), (equator, meridian)):
        loop, neck = tighten(pts, eight, h, cocycles, GAP_MIN, others=[walk_class(other, cocycles)])
        assert neck == math.inf
        assert (walk_class(loop, cocycles) == walk_class(kept, cocycles)).all()
        assert walk_length(pts, loop) == pytest_approx(walk_length(pts, np.array(kept)))


def test_the_features_measured_beside_the_analysis_are_those_measured_after_it():
    # where the paper's loop gives the result, the robust driver begins measuring its features on the
    # other core while it analyses it; the report takes them, and they are what features() gives after
    # the run; the pending measurement is not left on the extraction, which stays picklable
    import pickle

    from crustview.core.prepare import prescale

    rec = reconstruct(get_manifold("torus").sample(1200, seed=3).points, 2)
    assert "extension was not needed" in " ".join(rec.extraction.notes)
    pickle.loads(pickle.dumps(rec.extraction))  # no measurement in flight is left on it
    scale = prescale(rec.points)
    after = features(rec.points / scale, rec.manifold, rec.d)
    assert len(after) == len(rec.features) == 2  # the torus's two handles
    for f, g in zip(rec.features, after):
        assert (f.kind, f.size_spacings, f.uncertain) == (g.kind, g.size_spacings, g.uncertain)
        assert np.array_equal(f.location, g.location * scale)


def test_a_missing_tetrahedron_of_a_3_sphere_is_an_uncertain_hole():
    """The boundary of a 4-simplex (five tetrahedra, a 3-sphere) less one: one hole of four faces, sqrt 6 across."""
    pts = np.vstack([np.eye(4), np.full((1, 4), (1 - math.sqrt(5)) / 4)])  # a regular 4-simplex
    tets = np.array([[j for j in range(5) if j != i] for i in range(5)])
    assert [f for f in features(pts, tets, 3) if f.kind == "hole"] == []
    (hole,) = [f for f in features(pts, tets[1:], 3) if f.kind == "hole"]
    assert hole.uncertain and sorted(hole.vertices.tolist()) == [1, 2, 3, 4]
    # span 2 R = a sqrt(3/2) (R the regular tetrahedron's circumradius), h = a / 2 (half its longest edge)
    assert "4 boundary faces" in hole.reason and math.isclose(hole.size_spacings, math.sqrt(6))


def test_holes_of_a_3_manifold_small_and_large(s3_run):
    """S^3 from 600 samples: closed, no hole; a cavity one tetrahedron wide is uncertain, a hemisphere cut away sure."""
    rec, _ = s3_run
    ms = rec.manifold
    assert rec.topology.closed_manifold and [f for f in features(rec.points, ms, 3) if f.kind == "hole"] == []
    (small,) = [f for f in features(rec.points, ms[1:], 3) if f.kind == "hole"]
    assert small.uncertain and len(small.vertices) == 4
    centre = rec.points[ms].mean(axis=1)
    cut = ms[centre[:, 0] > 0]  # half of S^3 away: one hole, its rim the great 2-sphere x = 0, two radii across
    (big,) = [f for f in features(rec.points, cut, 3) if f.kind == "hole"]
    assert not big.uncertain and big.size_spacings > 4
    assert abs(big.location[0]) < 0.2 and np.linalg.norm(rec.points[big.vertices], axis=1).min() > 0.5
