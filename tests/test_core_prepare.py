"""Input preparation: validation, merging, subspaces, normalisation."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from crustview.core import InputError, reconstruct
from crustview.core.prepare import prepare_points


def circle(n, k=2, offset=0.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    p = np.zeros((n, k))
    p[:, 0], p[:, 1] = np.cos(t), np.sin(t)
    return p + offset


@pytest.mark.parametrize(
    "points, d, match",
    [
        (np.array([[0.0, 0.0], [1.0, np.nan], [2, 2], [3, 1], [0, 3]]), 1, "NaN"),
        (np.array([[0.0, 0.0], [1.0, np.inf], [2, 2], [3, 1], [0, 3]]), 1, "NaN or infinity"),
        (np.zeros((3, 2)), 1, r"too few points: 3; points in R\^2 need at least 4 \(k \+ 2\)"),
        (circle(20), 0, "between 1 and k-1"),
        (circle(20), 2, "between 1 and k-1"),
        (circle(20)[:, :1], 1, "at least 2 coordinates"),
        (np.ones(5), 1, "2-D"),
        (np.zeros((10, 3)), 1, "coincide"),
        (np.c_[np.linspace(0, 1, 20), np.linspace(0, 2, 20), np.zeros(20)], 1, "1-dimensional affine subspace"),
        ([["a", "b"]], 1, "numeric"),
    ],
)
def test_bad_input_gives_clear_error(points, d, match):
    with pytest.raises(InputError, match=match):
        reconstruct(points, d)


def test_d_must_be_integer():
    with pytest.raises(InputError, match="integer"):
        reconstruct(circle(20), 1.5)


def test_duplicates_and_near_duplicates_are_merged_with_a_map_back():
    base = circle(40)
    rng = np.random.default_rng(0)
    spacing = 2 * np.sin(np.pi / 40)
    extra = base[[3, 7, 7]] + rng.normal(scale=1e-7 * spacing, size=(3, 2))
    pts = np.vstack([base, extra, base[[0]]])
    prep = prepare_points(pts, 1)
    assert len(prep.points) == 40
    # samples are numbered in spatial order; the maps lead back to the input rows
    assert np.array_equal(prep.point_input[prep.input_index[:40]], np.arange(40))
    assert np.array_equal(prep.input_index[40:], prep.input_index[[3, 7, 7, 0]])
    assert np.array_equal(prep.points, pts[prep.point_input])
    # a point at a tenth of the spacing is a real sample, not a duplicate
    pts2 = np.vstack([base, base[[5]] + [0.1 * spacing, 0]])
    assert len(prepare_points(pts2, 1).points) == 41
    rec = reconstruct(pts, 1)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 1)
    assert rec.input_points.shape == (44, 2)


def test_a_file_that_repeats_every_row_many_times_is_its_distinct_points():
    """Every row 20 times (a file written in a loop): "all points coincide" was said, since a point's 7
    nearest others were all its own copies.  The spacing and the samples are those of the distinct points."""
    from crustview.core.prepare import merge_duplicates

    base = circle(40)
    once = prepare_points(base, 1)
    many = prepare_points(np.repeat(base, 20, axis=0), 1)
    assert len(many.points) == 40 and np.array_equal(np.sort(many.points, axis=0), np.sort(once.points, axis=0))
    assert merge_duplicates(np.repeat(base, 20, axis=0), 1e-6)[2] == merge_duplicates(base, 1e-6)[2]
    with pytest.raises(InputError, match="all points coincide"):
        prepare_points(np.repeat(base[:1], 30, axis=0), 1)


def test_nearest_other_point_is_the_plain_query_point_for_point():
    """merge_duplicates asks the k-d tree in its own leaf order; each point still gets the distance
    of a plain query in input order (0 where it has an exact copy), on shuffled points with copies."""
    from scipy.spatial import cKDTree

    from crustview.core.prepare import merge_duplicates
    from crustview.core.util.nearest import nearest_other

    rng = np.random.default_rng(5)
    pts = rng.normal(size=(3000, 3))
    pts = np.vstack([pts, pts[rng.choice(3000, 40, replace=False)]])[rng.permutation(3040)]
    tree = cKDTree(pts)
    plain = tree.query(pts, k=2)[0][:, 1]
    got = nearest_other(tree)
    assert np.array_equal(got, plain) and (got == 0).sum() == 80
    d, _ = tree.query(pts, k=8)
    positive = np.where(d[:, 1:] > 0, d[:, 1:], np.inf).min(axis=1)
    _, point_input, spacing = merge_duplicates(pts, 1e-9)
    assert spacing == np.median(positive) and len(point_input) == 3000
    assert np.isinf(nearest_other(cKDTree(np.zeros((1, 3))))).all()


def test_large_offset_and_scale_do_not_matter():
    p = circle(50) * 1e-3 + 1e6
    rec = reconstruct(p, 1)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 1)
    assert np.allclose(rec.points, p[rec.point_input])


def test_lower_dimensional_input_is_reconstructed_in_its_affine_hull():
    # an ellipse in a tilted plane of R^3 (codimension 2, but flat)
    e = circle(60, k=2) * [1.0, 0.6]
    rot, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))
    p = np.c_[e, np.zeros(60)] @ rot.T + [5.0, -2.0, 1.0]
    rec = reconstruct(p, 1)
    assert rec.subspace_dim == 2
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 1)
    plane_normal = rot[:, 2]
    # the plane's normal direction is part of every AN_s
    proj = np.einsum("nkc,k->nc", rec.normals, plane_normal)
    assert np.allclose(np.linalg.norm(proj, axis=1), 1.0, atol=1e-8)
    assert rec.normals.shape == (60, 3, 2) and rec.tangents.shape == (60, 3, 1)
    # bounding points and Voronoi vertices are lifted into the plane
    off = (rec.voronoi_vertices - p.mean(axis=0)) @ plane_normal
    assert np.abs(off).max() < 1e-6


def test_core_imports_no_gui_library():
    """Every module of crustview.core, imported and *run*, pulls in only numpy/scipy."""
    code = textwrap.dedent(
        """
        import importlib, pkgutil, sys
        import crustview.core as core
        names = [m.name for m in pkgutil.walk_packages(core.__path__, "crustview.core.")]
        for name in names:
            importlib.import_module(name)
        from crustview.core.samples.manifolds import get_manifold
        rec = core.reconstruct(get_manifold("circle").sample(60, seed=0).points, 1)
        assert rec.topology.closed_manifold
        gui = ("PySide6", "PySide2", "PyQt5", "PyQt6", "qtpy", "shiboken6", "pyvista", "pyvistaqt",
               "vtk", "vtkmodules", "matplotlib", "meshio")
        bad = sorted(m for m in sys.modules if m.split(".")[0] in gui)
        print(len(names), ",".join(bad))
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    count, bad = out.stdout.strip().split(" ", 1) if " " in out.stdout.strip() else (out.stdout.strip(), "")
    assert int(count) >= 12, out.stdout  # every module was imported
    assert bad == "", bad


# ---------------------------------------------------------------- extreme scales
def _ellipse_in_r3(n=80):
    """A tilted ellipse in R^3 (not cospherical, nothing degenerate)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[np.cos(t), 2 * np.sin(t), 0.3 * np.cos(t) + 0.1 * np.sin(2 * t)]


@pytest.mark.parametrize("scale", [1e300, 1e-300, 1e-310])
def test_extreme_scales_give_the_same_result_as_unit_scale(scale):
    """Squared distances of these points overflow (1e600) or underflow (1e-600);
    the exact power-of-two prescaling makes the run identical to the unit one."""
    base = _ellipse_in_r3()
    assert scale * scale in (0.0, float("inf"))
    ref = reconstruct(base, 1)
    # no overflow or invalid-value warning anywhere (harmless underflows exist at scale 1 too)
    with np.errstate(over="raise", invalid="raise", divide="raise"):
        got = reconstruct(base * scale, 1)
    assert got.topology.closed_manifold and got.topology.betti == (1, 1)

    # compared through input rows: subnormal coordinates may number the samples differently
    def by_input(rec):
        faces = np.sort(rec.point_input[rec.manifold], axis=1)
        return faces[np.lexsort(faces.T[::-1])], rec.normals[np.argsort(rec.point_input)]

    (got_faces, got_normals), (ref_faces, ref_normals) = by_input(got), by_input(ref)
    np.testing.assert_array_equal(got_faces, ref_faces)
    np.testing.assert_allclose(got_normals, ref_normals, atol=1e-9)
    assert got.spacing == pytest.approx(ref.spacing * scale, rel=1e-6)


def test_too_large_coordinates_are_one_clear_error():
    with pytest.raises(InputError, match="too large .* divide the data by a constant"):
        prepare_points(_ellipse_in_r3() * 1e306, 1)


def test_samples_are_numbered_along_space_and_joggled_by_input_order():
    rng = np.random.default_rng(11)
    x = rng.normal(size=(5000, 3))
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    prep = prepare_points(x, 2)
    assert sorted(prep.point_input) == list(range(5000))
    # consecutive samples are neighbours in space, unlike consecutive input rows
    step = np.linalg.norm(np.diff(prep.points, axis=0), axis=1).mean()
    assert step < 0.2 * np.linalg.norm(np.diff(x, axis=0), axis=1).mean()
    # the joggle of each input row is the seed's stream in input order
    flat = prepare_points(x, 2, joggle=0.0)
    jog = (prep.work - flat.work)[np.argsort(prep.point_input)]
    stream = np.random.default_rng(0).uniform(-1.0, 1.0, size=jog.shape)
    ratio = jog / stream
    assert np.allclose(ratio, ratio[0, 0], rtol=1e-6) and ratio[0, 0] > 0


@pytest.mark.parametrize("k,d", [(3, 2), (4, 2), (5, 3), (3, 1)])
def test_lift_of_stacked_parts_equals_lift_of_their_stack_bit_for_bit(k, d):
    rng = np.random.default_rng(k * 10 + d)
    # a sample in a d + 1 dimensional affine subspace of R^k when d + 1 < k: the basis is not square there
    r = min(k, d + 1)
    pts = rng.normal(size=(500, r)) @ np.linalg.qr(rng.normal(size=(k, k)))[0][:r] * 3.7 + rng.normal(size=k)
    prep = prepare_points(pts, d)
    parts = [rng.normal(size=(m, prep.r)) for m in (1_001, 0, 7, 333)]
    stacked = prep.lift_stacked(*parts)
    assert stacked.shape == (1_341, k)
    assert stacked.tobytes() == prep.lift(np.vstack(parts)).tobytes()


@pytest.mark.parametrize("k,d", [(3, 2), (4, 2), (3, 1)])
def test_lift_appended_fills_the_room_after_the_rows_and_equals_the_lift_of_the_stack(k, d):
    rng = np.random.default_rng(k + d)
    pts = rng.normal(size=(400, k)) * 2.5 + 1.0
    prep = prepare_points(pts, d)
    assert prep.r == k
    room = np.empty((70_020, k))
    rows, more = room[:70_001], rng.normal(size=(9, k))
    rows[...] = rng.normal(size=rows.shape)
    want = prep.lift(np.vstack([rows, more])).tobytes()
    got = prep.lift_appended(rows, more, block=4_096)  # several blocks, the last one short
    assert got.base is room and got.shape == (70_010, k) and got.tobytes() == want
    # no room after the rows (a plain array, or too little): the stacked copy, the rows untouched
    for plain in (rng.normal(size=(1_000, k)), np.empty((1_005, k))[:1_000]):  # 5 rows of room for 9
        plain[...] = rng.normal(size=plain.shape)
        before = plain.tobytes()
        out = prep.lift_appended(plain, more)
        assert not np.shares_memory(out, plain) and plain.tobytes() == before
        assert out.tobytes() == prep.lift(np.vstack([plain, more])).tobytes()


def test_circumcentres_with_room_after_them_are_the_same_centres():
    from crustview.core.delaunay.triangulation import bounding_points, circumcenters, delaunay

    rng = np.random.default_rng(5)
    pts = rng.normal(size=(300, 3))
    work = np.vstack([pts, bounding_points(3)])
    simp = delaunay(pts, bounding_points(3))
    plain = circumcenters(work, simp)
    roomy = circumcenters(work, simp, spare=300)
    assert roomy.tobytes() == plain.tobytes() and roomy.base.shape == (len(simp) + 300, 3)


def test_the_samples_come_in_spatial_order_whether_or_not_points_merged():
    """prepare_points reuses the merging's k-d tree for the spatial order where nothing merged: the same
    numbering as a tree of its own (and, with copies, the order of the merged points)."""
    from crustview.core.prepare import prescale, spatial_order

    rng = np.random.default_rng(8)
    pts = rng.normal(size=(2000, 3))
    unit = prescale(pts)
    prep = prepare_points(pts, 2)
    assert len(prep.points) == 2000
    assert np.array_equal(prep.point_input, spatial_order(pts / unit))
    with_copies = np.vstack([pts, pts[:25]])
    prep2 = prepare_points(with_copies, 2)
    assert len(prep2.points) == 2000
    assert np.array_equal(prep2.point_input, spatial_order(pts / unit))  # the copies' first rows, same order


def test_the_merging_distances_are_the_samples_nearest_distances_bit_for_bit():
    """``PreparedPoints.nearest``: the merging's own tree query, reused by the later stages (not re-measured)."""
    from scipy.spatial import cKDTree

    from crustview.core.prepare import prescale
    from crustview.core.samples.manifolds import get_manifold

    pts = get_manifold("torus").sample(3000, seed=0, method="random").points * 3.7
    prep = prepare_points(pts, 2)
    ref = cKDTree(prep.points).query(prep.points, k=2)[0][:, 1]
    assert prep.nearest is not None and np.array_equal(prep.nearest, ref)
    unit = prescale(prep.points)
    assert np.array_equal(prep.nearest / unit, cKDTree(prep.points / unit).query(prep.points / unit, k=2)[0][:, 1])
    doubled = np.vstack([pts, pts[:10]])  # ten exact copies merge: the merged set's distances were not measured
    assert prepare_points(doubled, 2).nearest is None
