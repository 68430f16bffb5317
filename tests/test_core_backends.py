"""The Delaunay backends: CGAL in R^3 (own extension and wheel) against Qhull, and degenerate input.

CGAL's dD extension (R^4, R^5) is tested in ``test_core_backend_dd.py``.
"""

import numpy as np
import pytest
from delaunay_checks import assert_delaunay_of_a_box, lattice

from crustview.core import reconstruct
from crustview.core.delaunay import cgal as delaunay_cgal
from crustview.core.delaunay.triangulation import backend_for, bounding_points, delaunay
from crustview.core.prepare import prepare_points


def _rows(simplices: np.ndarray) -> np.ndarray:
    return np.unique(np.sort(simplices, axis=1), axis=0)


def test_auto_backend_is_cgal_in_r3_to_r5_and_qhull_elsewhere():
    assert backend_for(3) == backend_for(4) == backend_for(5) == "cgal"
    assert backend_for(2) == backend_for(6) == "qhull"


def test_cgal_gives_qhulls_tetrahedra_on_a_generic_sample():
    rng = np.random.default_rng(3)
    pts = rng.uniform(-1, 1, size=(700, 3))
    pts /= np.maximum(1, np.linalg.norm(pts, axis=1, keepdims=True))
    b = bounding_points(3)
    cg = delaunay(pts, b, backend="cgal")
    qh = delaunay(pts, b, backend="qhull")
    assert cg.shape == qh.shape
    assert np.array_equal(_rows(cg), _rows(qh))


def test_the_native_extension_is_built_and_used():
    # scripts/install.sh installs CGAL's headers, so the extension must exist
    # here; without it the fast path would silently be the slow wheel
    assert delaunay_cgal.native_available()
    assert delaunay_cgal.cgal_route() == "extension"


def test_extension_and_wheel_give_the_same_tetrahedra():
    rng = np.random.default_rng(8)
    pts = rng.normal(size=(2000, 3))
    nat = delaunay_cgal.delaunay_3d_native(pts)
    whl = delaunay_cgal.delaunay_3d_wheel(pts)
    assert nat.dtype == np.int32 and nat.flags.writeable
    assert np.array_equal(_rows(nat), _rows(whl))


def test_extension_neighbour_table_is_consistent_and_matches_qhulls_hull():
    rng = np.random.default_rng(13)
    pts = rng.normal(size=(1500, 3))
    simp, nbrs = delaunay_cgal.delaunay_3d_native(pts, neighbors=True)
    assert nbrs.shape == simp.shape and nbrs.dtype == np.int32
    for j in range(4):
        inner = nbrs[:, j] >= 0
        other = simp[nbrs[inner, j]]
        facet = np.delete(simp[inner], j, axis=1)
        # the neighbour holds the facet opposite vertex j, and not vertex j itself
        assert (facet[:, :, None] == other[:, None, :]).any(axis=2).all()
        assert not (simp[inner, j][:, None] == other).any()
    # -1 exactly across the convex hull: as many as Qhull's hull facets
    qh_simp, qh_nbrs = delaunay(pts, np.empty((0, 3)), backend="qhull", neighbors=True)
    assert (nbrs < 0).sum() == (qh_nbrs < 0).sum() > 0


def test_extension_hand_checked_tetrahedron_and_octahedron():
    # one tetrahedron: a single cell on rows 0..3
    tet = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    assert _rows(delaunay_cgal.delaunay_3d_native(tet)).tolist() == [[0, 1, 2, 3]]
    # a slightly squashed octahedron: the short axis (rows 4, 5) is the
    # diagonal shared by all four tetrahedra
    octa = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 0.9], [0, 0, -0.9]])
    got = _rows(delaunay_cgal.delaunay_3d_native(octa))
    assert got.tolist() == [[0, 2, 4, 5], [0, 3, 4, 5], [1, 2, 4, 5], [1, 3, 4, 5]]


def test_extension_reports_bad_input_clearly():
    rng = np.random.default_rng(9)
    pts = rng.normal(size=(50, 3))
    with pytest.raises(RuntimeError, match="49 of 50 vertices"):
        delaunay_cgal.delaunay_3d_native(np.vstack([pts[:49], pts[:1]]))  # a duplicate
    with pytest.raises(RuntimeError, match="2-dimensional"):
        delaunay_cgal.delaunay_3d_native(np.c_[pts[:, :2], np.zeros(50)])  # coplanar
    with pytest.raises(ValueError, match="shape"):
        delaunay_cgal.delaunay_3d_native(pts[:, :2])
    from crustview.core.delaunay import _delaunay3

    with pytest.raises(ValueError, match="n x 3"):
        _delaunay3.tetrahedra(np.zeros(7))


def test_delaunay_falls_back_to_qhull_when_cgal_drops_a_vertex():
    # duplicates never reach delaunay() from prepare_points; called directly,
    # CGAL keeps one copy, and the wrapper answers with Qhull's triangulation
    rng = np.random.default_rng(10)
    pts = rng.normal(size=(60, 3))
    pts[7] = pts[3]
    got = delaunay(pts, np.empty((0, 3)), backend="cgal")
    assert np.array_equal(_rows(got), _rows(delaunay(pts, np.empty((0, 3)), backend="qhull")))


def test_cell_block_read_in_tiny_chunks_is_the_same(monkeypatch):
    rng = np.random.default_rng(4)
    pts = rng.normal(size=(200, 3))
    whole = delaunay_cgal.delaunay_3d_wheel(pts)
    monkeypatch.setattr(delaunay_cgal, "CHUNK_BYTES", 7)
    assert np.array_equal(delaunay_cgal.delaunay_3d_wheel(pts), whole)


@pytest.mark.parametrize("route", ["native", "wheel"])
def test_cgal_resolves_an_exactly_degenerate_lattice_into_a_delaunay_triangulation(route):
    # a 5x5x5 grid: every cube's 8 corners are cospherical, so the Delaunay
    # triangulation is not unique and CGAL may split it unlike Qhull; it must
    # still fill the hull (volumes add up) and keep every circumsphere empty
    pts = lattice(5, 3)
    assert_delaunay_of_a_box(pts, getattr(delaunay_cgal, f"delaunay_3d_{route}")(pts), 64.0)


def test_a_cospherical_sample_still_reconstructs_with_cgal():
    # points exactly on a sphere: prepare joggles them, CGAL triangulates
    rng = np.random.default_rng(5)
    x = rng.normal(size=(1500, 3))
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    prep = prepare_points(x, 2)
    b = bounding_points(3)
    assert np.array_equal(_rows(delaunay(prep.work, b, "cgal")), _rows(delaunay(prep.work, b, "qhull")))
    rec = reconstruct(x, 2)
    top = rec.topology
    assert top.closed_manifold and top.betti == (1, 0, 1) and top.unused_samples == 0


def test_unknown_backend_and_cgal_outside_r3_to_r5_are_errors():
    pts = np.random.default_rng(6).normal(size=(30, 6))
    with pytest.raises(ValueError, match="unknown Delaunay backend"):
        delaunay(pts, bounding_points(6), backend="fast")
    with pytest.raises(ValueError, match="R\\^3 to R\\^5 only"):
        delaunay(pts, bounding_points(6), backend="cgal")


def test_the_result_names_the_delaunay_code_that_ran():
    from crustview.core.samples.manifolds import get_manifold
    from crustview.report import report_dict

    m = get_manifold("torus")
    rec = reconstruct(m.sample(400, seed=0).points, 2)
    assert rec.delaunay_backend == "CGAL Delaunay_triangulation_3 (crustview extension)"
    assert report_dict(rec)["delaunay_backend"] == rec.delaunay_backend
    k = get_manifold("flat-klein")
    assert reconstruct(k.sample(300, seed=0).points, 2).delaunay_backend == (
        "CGAL dD Delaunay_triangulation, Epick_d<4> (crustview extension)"
    )
    circle = get_manifold("circle")
    assert reconstruct(circle.sample(50, seed=0).points, 1).delaunay_backend == "Qhull (scipy.spatial.Delaunay)"
    # a flat sample in R^4 whose affine hull is 3-dimensional runs in R^3, so CGAL
    flat = np.c_[m.sample(400, seed=1).points, np.zeros(400)]
    assert reconstruct(flat, 2).delaunay_backend.startswith("CGAL")
