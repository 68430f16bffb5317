"""Algorithms 1 and 2 on cases checkable by hand or by brute force."""

import numpy as np
import pytest

from crustview.core.delaunay.triangulation import bounding_points, circumcenters, delaunay
from crustview.core.paper import candidates as cand
from crustview.core.paper import conemin, dualcells
from crustview.core.paper.normals import complete_bases, greedy_poles


def _dual_cells(pts: np.ndarray, d: int):
    """Delaunay with bounding points, circumcentres, Algorithm 1's normals and the d-faces with their
    dual cells: what Algorithm 2 scores, for a sample ``pts`` of a d-manifold."""
    k = pts.shape[1]
    b = bounding_points(k)
    simp = delaunay(pts, b)
    allp = np.vstack([pts, b])
    cc = circumcenters(allp, simp)
    _, nrm, _ = greedy_poles(allp, simp, cc, len(pts), k - d)
    faces, ptr, cs = cand.enumerate_faces(simp, len(pts), d)
    return allp, simp, cc, nrm, faces, ptr, cs


def test_circumcentres_are_equidistant_from_simplex_vertices():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(60, 4))
    simp = delaunay(pts, bounding_points(4))
    allp = np.vstack([pts, bounding_points(4)])
    c = circumcenters(allp, simp)
    dist = np.linalg.norm(allp[simp] - c[:, None, :], axis=2)
    assert np.allclose(dist, dist[:, :1], rtol=1e-7)


def test_bounding_points_enclose_the_data_so_sample_cells_are_bounded():
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1, 1, size=(80, 3))
    pts /= np.maximum(1, np.linalg.norm(pts, axis=1, keepdims=True))
    b = bounding_points(3)
    simp = delaunay(pts, b)
    # hull of all points consists of bounding points only: every facet on the
    # hull (a simplex with a neighbour missing) contains no sample
    from scipy.spatial import Delaunay

    tri = Delaunay(np.vstack([pts, b]))
    hull_vertices = np.unique(tri.convex_hull)
    assert hull_vertices.min() >= len(pts)
    assert len(simp) > 0
    # and crustview's own triangulation: every sample a vertex, and every facet through a sample shared by two
    # tetrahedra (no sample on the boundary of the triangulated region: its Voronoi cell is bounded)
    n = len(pts)
    assert np.isin(np.arange(n), simp).all()
    facets = np.sort(np.concatenate([np.delete(simp, j, axis=1) for j in range(4)]), axis=1)
    rows, count = np.unique(facets, axis=0, return_counts=True)
    assert (count[(rows < n).any(axis=1)] == 2).all()


def test_greedy_poles_by_hand():
    # one sample at the origin whose cell has the Voronoi vertices below;
    # first pole: farthest (3,0,0); second: longest projection orthogonal to
    # x among (0,2,0) [2], (1,1,0) [1], (0,0,1) [1], (2,0,.5) [.5] -> (0,2,0).
    work = np.zeros((1, 3))
    centres = np.array([[0, 0, 1.0], [1, 1, 0], [3, 0, 0], [0, 2, 0], [2, 0, 0.5]])
    simplices = np.zeros((5, 4), dtype=np.int64)  # every simplex contains sample 0
    pole, normals, _ = greedy_poles(work, simplices, centres, 1, 2)
    assert list(pole[0]) == [2, 3]
    assert np.allclose(np.abs(normals[0]), [[1, 0], [0, 1], [0, 0]])
    nrm, tan = complete_bases(normals)
    assert np.allclose(np.abs(tan[0, :, 0]), [0, 0, 1])


def test_normals_of_a_sphere_are_radial():
    rng = np.random.default_rng(2)
    x = rng.normal(size=(800, 3))
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    from crustview.core import reconstruct

    rec = reconstruct(x, 2)
    cosang = np.abs(np.einsum("nk,nk->n", rec.normals[:, :, 0], x[rec.point_input]))
    err = np.degrees(np.arccos(np.clip(cosang, 0, 1)))
    # hull samples use the direction at infinity, not a truncated corner
    assert np.median(err) < 4 and err.max() < 12


def test_literal_angle_of_a_tilted_triangle():
    # triangle tilted by 30 deg about the x axis; AT_s of each vertex is the xy plane
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    work = np.array([[0, 0, 0], [1, 0, 0], [0, c, s]], dtype=float)
    normals = np.tile(np.array([[0.0], [0.0], [1.0]]), (3, 1, 1))
    ang = cand.literal_angles(work, normals, np.array([[0, 1, 2]]))
    assert np.degrees(ang[0]) == pytest.approx(30.0)


def test_literal_angle_in_codimension_2_and_3_and_the_some_vertex_quantifier():
    """Hand-made: an edge in R^3 (codim 2) and a triangle in R^5 (codim 3).

    Edge (0,0,0)-(1,0,1): its direction makes 45 deg with the x axis (AT of
    vertex 0) and 0 deg with the direction (1,0,1)/sqrt2 (AT of vertex 1);
    the paper's quantifier ("some sample") takes the smaller, 0 deg.
    Triangle in R^5 spanned by e1 and (cos 20) e2 + (sin 20) e3 at a vertex
    whose AT is span(e1, e2): largest principal angle 20 deg.
    """
    work = np.array([[0.0, 0, 0], [1.0, 0, 1]])
    n0 = np.array([[0.0, 0], [1, 0], [0, 1]])  # AN = span(y, z): AT = x axis
    r = np.sqrt(0.5)
    n1 = np.array([[0.0, -r], [1, 0], [0, r]])  # AN orthogonal to (1, 0, 1)
    ang = cand.literal_angles(work, np.stack([n0, n1]), np.array([[0, 1]]))
    assert np.degrees(ang[0]) == pytest.approx(0.0, abs=1e-6)
    ang0 = cand.literal_angles(work, np.stack([n0, n0]), np.array([[0, 1]]))
    assert np.degrees(ang0[0]) == pytest.approx(45.0)
    c, s = np.cos(np.radians(20)), np.sin(np.radians(20))
    work5 = np.array([[0.0, 0, 0, 0, 0], [1, 0, 0, 0, 0], [0, c, s, 0, 0]])
    eye = np.eye(5)
    normals5 = np.tile(eye[:, 2:], (3, 1, 1))  # AN = span(e3, e4, e5) at every vertex
    ang5 = cand.literal_angles(work5, normals5, np.array([[0, 1, 2]]))
    assert np.degrees(ang5[0]) == pytest.approx(20.0)


def brute_force_min(x, nrm, rng, samples=20000):
    """Smallest sin^2 angle to AT over random convex combinations of the rows of x."""
    w = rng.dirichlet(np.full(len(x), 0.3), size=samples)
    pts = np.vstack([w @ x, x])
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            t = np.linspace(0, 1, 2001)[:, None]
            pts = np.vstack([pts, (1 - t) * x[i] + t * x[j]])
    val = ((pts @ nrm) ** 2).sum(axis=1) / (pts**2).sum(axis=1)
    return val.min()


@pytest.mark.parametrize("r, m", [(3, 1), (4, 2), (4, 1), (5, 2)])
def test_cone_minimum_matches_brute_force_on_simplices(r, m):
    rng = np.random.default_rng(r * 10 + m)
    for _ in range(25):
        j = m + 1
        x = rng.normal(size=(j, r)) + rng.normal(size=r) * 2
        nrm = np.linalg.qr(rng.normal(size=(r, m)))[0]
        v, inside = conemin.cone_min(x[None], nrm[None])
        vals = ((x @ nrm) ** 2).sum(axis=1) / (x**2).sum(axis=1)
        exact = min(vals.min(), v[0] if inside[0] else np.inf)
        for sub in range(2, j):
            import itertools

            for c in itertools.combinations(range(j), sub):
                vv, ii = conemin.cone_min(x[list(c)][None], nrm[None])
                if ii[0]:
                    exact = min(exact, vv[0])
        bf = brute_force_min(x, nrm, rng)
        assert exact <= bf + 1e-9
        assert bf - exact < 2e-3


def polygon_min(cell, s, nrm, n_grid=120, rounds=4):
    """Smallest sin^2 angle to AT_s over a planar convex cell, by grid search.

    Grids over the cell's bounding box, then zooms in around the best point.
    """
    from scipy.spatial import Delaunay

    centre = cell.mean(axis=0)
    _, _, vt = np.linalg.svd(cell - centre)
    uv = (cell - centre) @ vt[:2].T
    tri = Delaunay(uv)

    def value(q):
        x = centre + q @ vt[:2] - s
        return ((x @ nrm) ** 2).sum(axis=1) / (x**2).sum(axis=1)

    t = np.linspace(0, 1, 400)[:, None]
    edges = np.vstack([(1 - t) * uv[i] + t * uv[j] for i in range(len(uv)) for j in range(i + 1, len(uv))])
    on_edges = value(edges)
    best_q = edges[np.argmin(on_edges)]
    best = on_edges.min()
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    for _ in range(rounds):
        g = np.stack(np.meshgrid(*[np.linspace(lo[i], hi[i], n_grid) for i in range(2)]), -1).reshape(-1, 2)
        g = g[tri.find_simplex(g) >= 0]
        if len(g) == 0:
            break
        val = value(g)
        if val.min() < best:
            best, best_q = val.min(), g[np.argmin(val)]
        half = (hi - lo) / n_grid * 4
        lo, hi = best_q - half, best_q + half
    return best


def test_cocone_score_matches_brute_force_on_real_cells():
    """Codimension 2 (a surface in R^4): exact minimum over polygonal cells."""
    rng = np.random.default_rng(5)
    u, v = rng.uniform(0, 2 * np.pi, (2, 300))
    pts = np.c_[np.cos(u), np.sin(u), np.cos(v), np.sin(v)] / np.sqrt(2)
    pts += rng.normal(scale=1e-3, size=pts.shape)
    allp, simp, cc, nrm, faces, ptr, cs = _dual_cells(pts, 2)
    per_vertex = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs)
    assert per_vertex.shape == faces.shape
    score = per_vertex.max(axis=1)
    # a mix of admitted and rejected faces, each checked at every vertex
    pick = np.concatenate(
        [
            rng.choice(np.flatnonzero(score < np.pi / 8), 15, replace=False),
            rng.choice(np.flatnonzero(score >= np.pi / 8), 15, replace=False),
        ]
    )
    exact = 0
    for fi in pick:
        cell = cc[cs[ptr[fi] : ptr[fi + 1]]]
        for a, vertex in enumerate(faces[fi]):
            bf = np.arcsin(np.sqrt(polygon_min(cell, allp[vertex], nrm[vertex])))
            got = per_vertex[fi, a]
            if bf < cand.SCORE_LIMIT - 0.02:
                exact += 1
                assert got <= bf + 1e-6  # never above the true minimum
                assert bf - got < 0.01  # and the grid gets close to it
            else:  # rejected for every threshold up to the limit
                assert got >= cand.SCORE_LIMIT - 0.02
    assert exact >= 45


def test_codimension_3_boundary_from_real_cell_faces_matches_all_subsets(monkeypatch):
    """Polygons and edges of 3-dimensional cells give the same exact minimum as
    enumerating every vertex pair and triple (Caratheodory) -- the slow way."""
    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(0, 2 * np.pi, 36))  # 72 scored faces, 390 cells of 5+ vertices (up to 56)
    pts = np.c_[np.cos(t), np.sin(t), 0.4 * np.cos(2 * t), 0.3 * np.sin(3 * t)]
    allp, simp, cc, nrm, faces, ptr, cs = _dual_cells(pts, 1)
    fast = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs, simplices=simp)
    monkeypatch.setattr(cand, "MAX_SUBSET_VERTICES", 10**6)
    slow = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs)
    scored = (fast < cand.SCORE_LIMIT) | (slow < cand.SCORE_LIMIT)
    assert scored.sum() > 50 and (np.diff(ptr) > 4).sum() > 50  # real 3-D cells
    np.testing.assert_allclose(fast[scored], slow[scored], atol=1e-9)


def test_codimension_2_real_cell_edges_match_all_vertex_pairs():
    """Curve in R^3: polygon cells' true edges give the all-pairs minimum."""
    rng = np.random.default_rng(4)
    t = np.sort(rng.uniform(0, 2 * np.pi, 120))
    pts = np.c_[np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t)]
    allp, simp, cc, nrm, faces, ptr, cs = _dual_cells(pts, 1)
    fast = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs, simplices=simp)
    slow = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs)
    scored = (fast < cand.SCORE_LIMIT) | (slow < cand.SCORE_LIMIT)
    assert scored.sum() > 100 and (np.diff(ptr) > 6).sum() > 100
    np.testing.assert_allclose(fast[scored], slow[scored], atol=1e-9)


def test_cell_boundary_with_no_polygon_worth_a_look_returns_nothing():
    """Every polygon vertex leans far to one normal side: no polygon can go
    below the cap, so none is evaluated (and nothing breaks)."""
    from scipy.spatial import cKDTree

    nrm = np.eye(4)[None, :, 1:]  # AN = span(e2, e3, e4): AT = e1 axis
    x = np.array([[[0.1, 1, 1, 1], [0.0, 1, 1.2, 1], [0.1, 1.1, 1, 1], [0.0, 1, 1, 1.3]]])
    polygons = np.array([[0, 0, 1, 2, 0, 3]])
    members = np.array([0, 1, 2])
    out = dualcells.cell_boundary_min(
        x,
        nrm,
        np.zeros((1, 4)),
        np.empty((0, 3), np.int64),
        (polygons, members),
        np.array([0.01]),
        cKDTree(np.zeros((1, 4))),
    )
    assert out.shape == (1,) and np.isinf(out[0])


def test_closed_form_span_minimum_matches_lapack_even_when_ill_conditioned():
    rng = np.random.default_rng(7)
    p, r, m = 3000, 5, 3
    x = rng.normal(size=(p, 3, r))
    nrm = np.linalg.qr(rng.normal(size=(p, r, m)))[0]
    x[:500, 2] = x[:500, 0] + 1e-8 * rng.normal(size=(500, r))  # nearly dependent generators
    full = np.linalg.qr(np.concatenate([nrm, rng.normal(size=(p, r, 2))], axis=2))[0]
    x[500:1000, :2] = np.swapaxes(full[500:1000, :, 3:], 1, 2)  # two generators in AT: double zero
    v1, _, ok1 = conemin.span_min(x, nrm)
    v2, lam, ok2 = conemin.span_min3(x, nrm)
    assert (ok1 == ok2).all()
    np.testing.assert_allclose(v2[ok1], v1[ok1], atol=1e-12)
    y = np.einsum("pj,pjr->pr", lam, x)  # the minimiser is where the value is reached
    reached = (np.einsum("pr,prm->pm", y, nrm) ** 2).sum(axis=1) / (y**2).sum(axis=1)
    np.testing.assert_allclose(reached[ok1], v1[ok1], atol=1e-6)


def test_segment_minimum_survives_nearly_parallel_generators():
    rng = np.random.default_rng(8)
    x1 = rng.normal(size=(200, 4))
    x2 = x1 * 1.5 + 1e-7 * rng.normal(size=(200, 4))
    nrm = np.linalg.qr(rng.normal(size=(200, 4, 2)))[0]
    v, _ = conemin.segment_min(x1, x2, np.einsum("pr,prm->pm", x1, nrm), np.einsum("pr,prm->pm", x2, nrm))
    ref, _, ok = conemin.span_min(np.stack([x1, x2], axis=1), nrm)
    np.testing.assert_allclose(v[ok], ref[ok], atol=1e-6)


def test_codimension_1_segment_minimum_by_hand():
    """Seen from s = 0 with normal e3: a segment crossing the tangent plane scores 0; one on one side
    scores at its nearer end (sin^2 = 1/2 at (1, 0, 1) against 4/5 at (0, 1, 2)), never inside."""
    work = np.zeros((1, 3))
    normals = np.array([[[0.0], [0.0], [1.0]]])
    faces = np.zeros((2, 1), np.int64)
    centres = np.array([[1.0, 0, 1], [1.0, 0, -1], [0.0, 1, 2]])
    cells = np.array([[0, 1], [0, 2]])
    ((best, lean),) = cand._segment_ends(work, normals, centres, faces, cells)
    sin2 = cand.segment_sin2(best, lean, np.sin(cand.SCORE_LIMIT))
    assert sin2[0] == 0.0
    assert np.isclose(sin2[1], 0.5)
    # the same segments sampled densely: no point of the one-sided segment beats its ends
    t = np.linspace(0, 1, 2001)[:, None]
    y = centres[0] + t * (centres[2] - centres[0])
    dense = (y[:, 2] ** 2 / (y**2).sum(axis=1)).min()
    assert dense >= 0.5 - 1e-12  # the premise: the minimum over the segment is at its nearer end
    assert np.isclose(sin2[1], dense)  # and the product's score is that minimum


def test_codimension_1_scores_are_the_minimum_over_each_dual_segment():
    """A noisy torus in R^3: an edge that crosses the tangent plane scores exactly 0; every other
    (face, vertex) score below the limit is the minimum of sin^2 angle(y - s, AT_s) over 400 points of
    the face's Voronoi edge, its ends included (no point inside beats them); scores at the limit are
    at least the limit there."""
    from crustview.core.samples.manifolds import get_manifold

    rng = np.random.default_rng(7)
    pts = get_manifold("torus").sample(700, seed=3).points
    pts = pts + rng.normal(scale=0.01, size=pts.shape)
    allp, simp, cc, nrm, faces, ptr, cs = _dual_cells(pts, 2)
    got = cand.cocone_angles(allp, nrm, cc, faces, ptr, cs, simplices=simp)
    ends = cs.reshape(-1, 2)
    pick = rng.choice(len(faces), 600, replace=False)
    t = np.linspace(0.0, 1.0, 400)[None, :, None]
    crossing = 0
    for a in range(3):
        s = allp[faces[pick, a]]
        n = nrm[faces[pick, a], :, 0]
        x = cc[ends[pick, 0]][:, None, :] + t * (cc[ends[pick, 1]] - cc[ends[pick, 0]])[:, None, :] - s[:, None, :]
        sin2 = np.einsum("ftr,fr->ft", x, n) ** 2 / (x**2).sum(axis=2)
        dense = np.arcsin(np.sqrt(sin2.min(axis=1)))
        sides = np.sign(
            np.einsum("fr,fr->f", cc[ends[pick, 0]] - s, n) * np.einsum("fr,fr->f", cc[ends[pick, 1]] - s, n)
        )
        cross = sides < 0
        crossing += int(cross.sum())
        assert (got[pick, a][cross] == 0.0).all()
        one_side = ~cross & (dense < cand.SCORE_LIMIT - 1e-9)
        assert np.allclose(got[pick, a][one_side], dense[one_side], rtol=0, atol=1e-9)
        assert (got[pick, a][~cross & ~one_side] >= cand.SCORE_LIMIT - 1e-9).all()
    assert crossing > 100  # the case the closed form is about
