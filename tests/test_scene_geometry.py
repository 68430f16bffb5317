"""Geometry helpers of the layers (numpy only)."""

import numpy as np

from crustview.scene import geometry as geo
from crustview.scene.voronoi import clipped_cell, planar_voronoi_edges


def test_clip_segments():
    lo, hi = np.zeros(2), np.ones(2)
    a = np.array([[0.5, 0.5], [-1.0, 0.5], [2.0, 2.0], [0.5, -1.0]])
    b = np.array([[0.6, 0.6], [2.0, 0.5], [3.0, 3.0], [0.5, 0.5]])
    a2, b2, keep = geo.clip_segments(a, b, lo, hi)
    assert keep.tolist() == [True, True, False, True]
    assert np.allclose(a2, [[0.5, 0.5], [0, 0.5], [0.5, 0]])
    assert np.allclose(b2, [[0.6, 0.6], [1, 0.5], [0.5, 0.5]])


def test_normal_glyphs_by_codimension():
    rng = np.random.default_rng(0)
    n = 4
    pts = rng.standard_normal((n, 3))
    # c = 1: one segment per sample, centred on it, of half-length = scale
    nrm = np.tile(np.array([0.0, 0.0, 1.0])[None, :, None], (n, 1, 1))
    v, lines, polys = geo.normal_glyphs(pts, nrm, np.full(n, 0.5))
    assert lines.shape == (n, 2) and polys.size == 0
    assert np.allclose((v[lines[:, 0]] + v[lines[:, 1]]) / 2, pts)
    assert np.allclose(np.linalg.norm(v[lines[:, 1]] - v[lines[:, 0]], axis=1), 1.0)
    # c = 2: a disc in the normal plane
    nrm2 = np.tile(np.eye(3)[:, :2][None], (n, 1, 1))
    v, lines, polys = geo.normal_glyphs(pts, nrm2, np.ones(n), sides=12)
    assert polys.shape == (n, 12) and lines.size == 0
    assert np.allclose(v[polys[0]][:, 2], pts[0, 2])  # lies in the x-y plane
    # c = 3 in R^5: three axes
    nrm3 = np.tile(np.eye(5)[:, :3][None], (n, 1, 1))
    v, lines, polys = geo.normal_glyphs(rng.standard_normal((n, 5)), nrm3, np.ones(n))
    assert lines.shape == (3 * n, 2)


def test_facets_and_counts():
    simp = np.array([[0, 1, 2], [1, 2, 3], [1, 2, 4]])
    faces, inc = geo.facets(simp)
    counts = geo.face_counts(inc, np.ones(3, bool), len(faces))
    got = {tuple(f): c for f, c in zip(faces.tolist(), counts)}
    assert got[(1, 2)] == 3 and got[(0, 1)] == 1 and len(got) == 7
    counts = geo.face_counts(inc, np.array([True, True, False]), len(faces))
    assert dict(zip(map(tuple, faces.tolist()), counts))[(1, 2)] == 2


def test_find_rows():
    table = np.array([[0, 1, 2], [2, 3, 5], [1, 4, 6]])
    assert geo.find_rows(table, np.array([[5, 3, 2], [0, 1, 3], [1, 4, 6]])).tolist() == [1, -1, 2]


def test_shrink_and_triangles():
    pts = np.eye(4)[:, :3]
    tri = geo.simplex_triangles(3)
    assert len(tri) == 4
    s = geo.shrink_simplices(pts, np.array([[0, 1, 2, 3]]), 0.5)
    c = pts.mean(axis=0)
    assert np.allclose(s, c + 0.5 * (pts - c))


def test_clipped_cell_of_a_cube():
    # the cell spanned by a cube's corners, clipped by a smaller box
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    lo, hi = np.full(3, -0.5), np.array([0.5, 0.5, 2.0])
    verts, edges, tris = clipped_cell(corners, np.zeros(3), lo, hi)
    assert np.all(verts >= lo - 1e-9) and np.all(verts <= hi + 1e-9)
    assert len(verts) == 8 and len(edges) == 12 and len(tris) == 12
    # in R^4: a tesseract has 32 edges
    c4 = np.array([[a, b, c, d] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1) for d in (-1, 1)], float)
    verts, edges, tris = clipped_cell(c4, np.zeros(4), np.full(4, -2.0), np.full(4, 2.0))
    assert len(verts) == 16 and len(edges) == 32 and len(tris) == 48  # its 24 square 2-faces, as patches


def test_planar_voronoi_edges_match_scipy():
    """Every finite Voronoi edge of a sample, endpoint for endpoint, as scipy's Voronoi has it."""
    from scipy.spatial import Delaunay, Voronoi

    rng = np.random.default_rng(2)
    pts = rng.random((40, 2))
    ring = 10 * np.stack(
        [np.cos(np.linspace(0, 2 * np.pi, 12, endpoint=False)), np.sin(np.linspace(0, 2 * np.pi, 12, endpoint=False))],
        axis=1,
    )
    allp = np.vstack([pts, ring])
    tri = Delaunay(allp)
    vor = Voronoi(allp)
    a, b = planar_voronoi_edges(
        tri.simplices, _circumcentres(allp, tri.simplices), len(pts), np.full(2, -100.0), np.full(2, 100.0)
    )

    def key(p, q):
        return tuple(sorted([tuple(np.round(p, 6)), tuple(np.round(q, 6))]))

    # each finite ridge between two points with at least one sample
    want = {
        key(*vor.vertices[r])
        for (p, q), r in zip(vor.ridge_points, vor.ridge_vertices)
        if min(p, q) < len(pts) and -1 not in r
    }
    got = [key(p, q) for p, q in zip(a, b)]
    assert len(got) == len(set(got)) == len(want)
    assert set(got) == want


def _circumcentres(p, simp):
    out = []
    for s in simp:
        a, b, c = p[s]
        m = 2 * np.array([b - a, c - a])
        rhs = np.array([b @ b - a @ a, c @ c - a @ a])
        out.append(np.linalg.solve(m, rhs))
    return np.array(out)
