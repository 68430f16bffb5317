"""CGAL's dD Delaunay extension (R^4 and R^5) against Qhull, hand-made cases and degenerate input."""

import itertools

import numpy as np
import pytest
from delaunay_checks import assert_delaunay_of_a_box, lattice

from crustview.core import reconstruct
from crustview.core.delaunay import cgal as delaunay_cgal
from crustview.core.delaunay.triangulation import bounding_points, delaunay
from crustview.core.paper.candidates import SCORE_LIMIT
from crustview.core.samples.manifolds import get_manifold


def _rows(simplices: np.ndarray) -> np.ndarray:
    return np.unique(np.sort(simplices, axis=1), axis=0)


def test_the_dd_extension_is_built():
    # scripts/install.sh installs CGAL's and Eigen's headers, so it must exist here
    assert delaunay_cgal.native_d_available()


@pytest.mark.parametrize("r, n", [(4, 600), (5, 250)])
def test_cgal_dd_gives_qhulls_simplices_on_a_generic_sample(r, n):
    rng = np.random.default_rng(r)
    pts = rng.normal(size=(n, r))
    b = bounding_points(r)
    cg = delaunay(pts, b, backend="cgal")
    qh = delaunay(pts, b, backend="qhull")
    assert cg.dtype == np.int32 and cg.shape == qh.shape
    assert np.array_equal(_rows(cg), _rows(qh))


@pytest.mark.parametrize("r", [4, 5])
def test_dd_neighbour_table_is_consistent_and_matches_qhulls_hull(r):
    rng = np.random.default_rng(20 + r)
    pts = rng.normal(size=(300, r))
    simp, nbrs = delaunay_cgal.delaunay_d(pts, neighbors=True)
    assert nbrs.shape == simp.shape == (len(simp), r + 1)
    for j in range(r + 1):
        inner = nbrs[:, j] >= 0
        other = simp[nbrs[inner, j]]
        facet = np.delete(simp[inner], j, axis=1)
        assert (facet[:, :, None] == other[:, None, :]).any(axis=2).all()
        assert not (simp[inner, j][:, None] == other).any()
    _, qh_nbrs = delaunay(pts, np.empty((0, r)), backend="qhull", neighbors=True)
    assert (nbrs < 0).sum() == (qh_nbrs < 0).sum() > 0


def test_dd_hand_checked_simplex_and_cross_polytope():
    # one 4-simplex: a single cell on rows 0..4
    simplex = np.vstack([np.zeros(4), np.eye(4)])
    assert _rows(delaunay_cgal.delaunay_d(simplex)).tolist() == [[0, 1, 2, 3, 4]]
    # a cross-polytope in R^4 squashed along its last axis: the short diagonal
    # (rows 6, 7) lies in every cell, one cell per sign choice of the other
    # three axes, 2^3 = 8 cells
    eye = np.eye(4)
    eye[3, 3] = 0.9
    pts = np.vstack([eye[:1], -eye[:1], eye[1:2], -eye[1:2], eye[2:3], -eye[2:3], eye[3:], -eye[3:]])
    got = _rows(delaunay_cgal.delaunay_d(pts)).tolist()
    want = sorted(sorted([a, b, c, 6, 7]) for a, b, c in itertools.product((0, 1), (2, 3), (4, 5)))
    assert got == want


def test_dd_resolves_an_exactly_degenerate_lattice_into_a_delaunay_triangulation():
    # a 3^4 grid: every cube's 16 corners are cospherical; whatever split CGAL
    # picks must fill the hull (volumes add up to 2^4) with empty circumspheres
    pts = lattice(3, 4)
    assert_delaunay_of_a_box(pts, delaunay_cgal.delaunay_d(pts), 16.0)


def test_dd_reports_bad_input_clearly():
    rng = np.random.default_rng(9)
    pts = rng.normal(size=(40, 4))
    with pytest.raises(RuntimeError, match="39 of 40 vertices"):
        delaunay_cgal.delaunay_d(np.vstack([pts[:39], pts[:1]]))  # a duplicate
    with pytest.raises(RuntimeError, match="3-dimensional"):
        delaunay_cgal.delaunay_d(np.c_[pts[:, :3], np.zeros(40)])  # in a hyperplane
    with pytest.raises(ValueError, match="shape"):
        delaunay_cgal.delaunay_d(pts[:, :3])
    from crustview.core.delaunay import _delaunay_d

    with pytest.raises(ValueError, match="n x 4"):
        _delaunay_d.full_cells(np.zeros(7), 4)
    with pytest.raises(ValueError, match="R\\^4 and R\\^5 only"):
        _delaunay_d.full_cells(np.zeros(12), 6)


def test_dd_duplicates_fall_back_to_qhull_in_delaunay():
    rng = np.random.default_rng(10)
    pts = rng.normal(size=(60, 4))
    pts[7] = pts[3]
    got = delaunay(pts, np.empty((0, 4)), backend="cgal")
    assert np.array_equal(_rows(got), _rows(delaunay(pts, np.empty((0, 4)), backend="qhull")))


@pytest.mark.parametrize("name, n", [("flat-klein", 600), ("s3", 500)])
def test_cgal_and_qhull_give_the_same_reconstruction_in_r4(name, n, monkeypatch):
    # the same triangulation, so the same candidates and the same M_S; s3 is
    # codimension 1, where the neighbour table feeds the face enumeration
    import crustview.core.delaunay.triangulation as dmod

    m = get_manifold(name)
    pts = m.sample(n, seed=0).points
    rec = reconstruct(pts, m.d)
    assert rec.delaunay_backend.startswith("CGAL dD")
    monkeypatch.setattr(dmod, "backend_for", lambda r: "qhull")
    ref = reconstruct(pts, m.d)
    assert ref.delaunay_backend.startswith("Qhull")
    assert np.array_equal(_rows(rec.delaunay_simplices), _rows(ref.delaunay_simplices))
    assert np.array_equal(rec.candidates.faces, ref.candidates.faces)
    # scores below SCORE_LIMIT are exact minima: equal up to rounding (the cells'
    # vertices come in another order; near 0 the angle is arcsin of the square
    # root of a rounding error, ~1e-8); above it they are lower bounds
    a, b = rec.candidates.angles["cocone"], ref.candidates.angles["cocone"]
    exact = (a < SCORE_LIMIT) | (b < SCORE_LIMIT)
    assert exact.sum() > len(pts) and np.allclose(a[exact], b[exact], rtol=0, atol=1e-7)
    assert (a[~exact] >= SCORE_LIMIT).all() and (b[~exact] >= SCORE_LIMIT).all()
    assert np.array_equal(_rows(rec.manifold), _rows(ref.manifold))
    assert rec.topology.closed_manifold and rec.topology.betti == m.betti


def test_exactly_cospherical_s3_without_joggle_reconstructs_with_cgal_dd():
    # every sample on the unit 3-sphere and no joggle: the Delaunay is highly
    # degenerate; CGAL resolves it by symbolic perturbation into a valid
    # triangulation, and the reconstruction is still S^3
    m = get_manifold("s3")
    pts = m.sample(600, seed=2).points
    pts /= np.linalg.norm(pts, axis=1, keepdims=True)
    rec = reconstruct(pts, 3, joggle=0.0)
    assert rec.delaunay_backend.startswith("CGAL dD") and rec.joggle == 0.0
    top = rec.topology
    assert top.closed_manifold and top.betti == (1, 0, 0, 1) and top.unused_samples == 0
