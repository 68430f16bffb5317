"""Reading point sets and writing reconstructions (crustview.io)."""

from __future__ import annotations

import json

import meshio
import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.errors import InputError
from crustview.core.samples.manifolds import get_manifold
from crustview.io import (
    read_points,
    read_run_parameters,
    report_dict,
    write_points,
    write_report,
    write_result,
)
from crustview.meshfiles import read_mesh as read_any_mesh


# ---------------------------------------------------------------- fixtures: real runs
@pytest.fixture(scope="module")
def circle_rec():
    """A curve in R^2 with duplicated input rows (rows 100..109 repeat rows 0..9)."""
    pts = get_manifold("circle").sample(100, seed=0).points
    return reconstruct(np.vstack([pts, pts[:10]]), 1)


@pytest.fixture(scope="module")
def sphere_rec():
    return reconstruct(get_manifold("sphere").sample(400, seed=0).points, 2)


@pytest.fixture(scope="module")
def trefoil_rec():
    return reconstruct(get_manifold("trefoil").sample(120, seed=0).points, 1)


def _meshio_read(path):
    with np.errstate(over="ignore"):  # meshio's STL sniffing overflows a uint32 (harmless)
        return meshio.read(path)


def _rows(a):
    return {tuple(sorted(r)) for r in np.asarray(a).tolist()}


# ---------------------------------------------------------------- read_points
@pytest.mark.parametrize("suffix", [".npy", ".npz", ".csv", ".txt", ".xyz", ".ply", ".vtk"])
@pytest.mark.parametrize("k", [2, 3, 4])
def test_points_round_trip(tmp_path, suffix, k):
    pts = np.random.default_rng(k).normal(size=(37, k))
    path = tmp_path / f"p{suffix}"
    if suffix == ".vtk" and k > 3:
        with pytest.raises(InputError, match="at most 3"):
            write_points(path, pts)
        return
    write_points(path, pts)
    back = read_points(path)
    assert back.dtype == np.float64 and back.shape == pts.shape
    np.testing.assert_array_equal(back, pts)  # %.17g text and float64 meshes are exact


def test_text_formats_comments_header_and_separators(tmp_path):
    f = tmp_path / "a.csv"
    f.write_text("# exported\nx, y, z\n\n1, 2, 3\n# mid comment\n4,5,6\n  7\t8  9  \n1e-3;2.5;-3\n")
    np.testing.assert_array_equal(read_points(f), [[1, 2, 3], [4, 5, 6], [7, 8, 9], [1e-3, 2.5, -3]])


@pytest.mark.parametrize("suffix", [".obj", ".off", ".stl", ".vtu"])
def test_mesh_formats_give_their_vertices(tmp_path, suffix):
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.5]], dtype=float)
    tris = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])
    path = tmp_path / f"m{suffix}"
    meshio.write(path, meshio.Mesh(pts, [("triangle", tris)]))
    back = read_points(path)
    assert back.shape[1] == 3
    assert _rows(np.round(back, 6)) == _rows(pts)


def _expect_error(path, *fragments):
    with pytest.raises(InputError) as info:
        read_points(path)
    msg = str(info.value)
    assert "\n" not in msg and str(path) in msg
    for frag in fragments:
        assert frag in msg
    return msg


def test_read_errors_name_the_file(tmp_path):
    _expect_error(tmp_path / "missing.csv", "does not exist")
    (tmp_path / "dir.csv").mkdir()
    _expect_error(tmp_path / "dir.csv", "not a regular file")
    (tmp_path / "adir").mkdir()  # a folder without a suffix is a folder too, not an unsupported file type
    _expect_error(tmp_path / "adir", "is a folder, not a regular file")
    (tmp_path / "p.dat").write_text("1 2\n")
    _expect_error(tmp_path / "p.dat", "unsupported", ".csv")
    (tmp_path / "noext").write_text("1 2\n")
    _expect_error(tmp_path / "noext", "no suffix")


@pytest.mark.parametrize(
    ("name", "content", "fragment"),
    [
        ("empty.csv", "", "no points"),
        ("comments.txt", "# only\n# comments\n", "no points"),
        ("garbage.csv", "hello world\nthis is not, a point file\n", "non-number"),
        ("mixed.txt", "1 2 3\n4 five 6\n", "line 2"),
        ("ragged.xyz", "1 2 3\n4 5 6\n7 8\n", "line 3 has 2 values"),
        ("onecol.txt", "1\n2\n3\n", "at least 2 coordinates"),
        ("nan.csv", "1,2\nnan,3\n4,5\n", "NaN or infinite"),
        ("inf.csv", "1,2\n3,inf\n", "NaN or infinite"),
    ],
)
def test_bad_text_files(tmp_path, name, content, fragment):
    path = tmp_path / name
    path.write_text(content)
    _expect_error(path, fragment)


def test_bad_binary_files(tmp_path):
    np.save(tmp_path / "flat.npy", np.arange(6.0))
    _expect_error(tmp_path / "flat.npy", "2-D", "(6,)")
    np.save(tmp_path / "cube.npy", np.zeros((2, 2, 2)))
    _expect_error(tmp_path / "cube.npy", "2-D")
    np.save(tmp_path / "none.npy", np.zeros((0, 3)))
    _expect_error(tmp_path / "none.npy", "no points")
    np.save(tmp_path / "inf.npy", np.array([[0.0, 1.0], [np.inf, 2.0]]))
    _expect_error(tmp_path / "inf.npy", "the first is point 2, counting from 1")
    np.save(tmp_path / "words.npy", np.array([["a", "b"], ["c", "d"]]))
    _expect_error(tmp_path / "words.npy", "not numbers")
    np.save(tmp_path / "objects.npy", np.array([[1, None]], dtype=object), allow_pickle=True)
    assert "pickle" not in _expect_error(tmp_path / "objects.npy", "Python objects, not an array of numbers")
    (tmp_path / "corrupt.npy").write_bytes(b"\x93NUMPY garbage" * 3)
    _expect_error(tmp_path / "corrupt.npy", ".npy")
    (tmp_path / "truncated.npy").write_bytes((tmp_path / "flat.npy").read_bytes()[:-8])
    _expect_error(tmp_path / "truncated.npy", "damaged NumPy .npy file")
    np.savez(tmp_path / "other.npz", xyz=np.zeros((3, 3)))
    _expect_error(tmp_path / "other.npz", "'points'", "xyz")
    (tmp_path / "corrupt.npz").write_bytes(b"PK\x03\x04 not a zip")
    _expect_error(tmp_path / "corrupt.npz", ".npz")
    (tmp_path / "latin.csv").write_bytes(b"1,2\n\xff\xfe,3\n")
    _expect_error(tmp_path / "latin.csv", "UTF-8")
    (tmp_path / "bad.ply").write_text("this is not a ply file\n")
    _expect_error(tmp_path / "bad.ply", ".ply mesh")
    (tmp_path / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n")
    _expect_error(tmp_path / "bad.off")


def test_random_bytes_named_npy_or_npz_are_not_numpy_files(tmp_path):
    """Issue 10: random bytes named .npy gave numpy's message about pickles."""
    junk = np.random.default_rng(0).bytes(4096)
    (tmp_path / "random.npy").write_bytes(junk)
    msg = _expect_error(tmp_path / "random.npy", "not a NumPy array file")
    assert "pickle" not in msg.lower()
    (tmp_path / "random.npz").write_bytes(junk)
    msg = _expect_error(tmp_path / "random.npz", "not a NumPy .npz archive")
    assert "pickle" not in msg.lower()
    (tmp_path / "empty.npy").write_bytes(b"")
    _expect_error(tmp_path / "empty.npy", "not a NumPy array file")
    (tmp_path / "text.npy").write_text("1 2 3\n4 5 6\n")
    _expect_error(tmp_path / "text.npy", "not a NumPy array file")


@pytest.mark.parametrize(
    ("content", "fragments"),
    [
        ("Lorem ipsum dolor!\n1 2 3\n4 5 6\n", ["line 1", "neither numbers nor a header of column names"]),
        ("@@@ ###\n1 2\n", ["line 1", "'@@@ ###'"]),
        ("\n# comment\n%%garbage\n1,2\n", ["line 3", "neither numbers"]),
        ("x y\n1 2 3\n4 5 6\n", ["line 1 names 2 columns (x, y)", "line 2 has 3 values"]),
        ("x y z\nu v w\n1 2 3\n", ["line 2 has the non-number 'u'"]),
        ("1 2 3\nx y z\n", ["line 2 has the non-number 'x'"]),
    ],
)
def test_a_garbage_first_line_is_an_error_naming_it(tmp_path, content, fragments):
    """Issue 10: a garbage first line was skipped silently.  Only a line of column names,
    as many as the data has columns, is taken as a header; anything else names its line."""
    path = tmp_path / "p.xyz"
    path.write_text(content)
    _expect_error(path, *fragments)


def test_a_header_of_column_names_is_skipped_and_said(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text('"x","y","z"\n1,2,3\n4,5,6\n')
    notes = []
    np.testing.assert_array_equal(read_points(path, notes), [[1, 2, 3], [4, 5, 6]])
    assert notes == ["p.csv: line 1 was read as column names (x, y, z), not as a point."]
    plain = tmp_path / "q.txt"
    plain.write_text("1 2\n3 4\n")
    notes = []
    read_points(plain, notes)
    assert notes == []


def test_write_points_errors(tmp_path):
    with pytest.raises(InputError, match="does-not-exist"):
        write_points(tmp_path / "does-not-exist" / "p.csv", np.zeros((3, 2)))
    with pytest.raises(InputError, match=r"shape \(n, k\)"):
        write_points(tmp_path / "p.csv", np.zeros(3))
    with pytest.raises(InputError, match="unsupported"):
        write_points(tmp_path / "p.obj", np.zeros((3, 3)))


# ---------------------------------------------------------------- write_result: npz
def _check_npz(path, rec):
    with np.load(path, allow_pickle=False) as z:
        data = {key: z[key] for key in z.files}
    assert set(data) == {"points", "simplices", "candidates", "normals", "tangents",
                         "d", "k", "test", "theta", "prune_boundary", "mode", "normals_method",
                         "labelling"}  # fmt: skip
    assert str(data["normals_method"]) == rec.normals_method  # the planes it was made with
    assert bool(data["labelling"]) == rec.labelling  # labelled, or grown on request
    n_in, k, d = len(rec.input_points), rec.k, rec.d
    np.testing.assert_array_equal(data["points"], rec.input_points)
    assert int(data["d"]) == d and int(data["k"]) == k
    assert str(data["test"]) == rec.test and float(data["theta"]) == rec.theta
    assert bool(data["prune_boundary"]) == rec.prune_boundary
    assert str(data["mode"]) == rec.mode
    simp, cand = data["simplices"], data["candidates"]
    assert simp.shape == (len(rec.manifold), d + 1) and cand.shape[1] == d + 1
    assert simp.min() >= 0 and simp.max() < n_in
    # every simplex maps back to the same unique points, and M_S is part of T_S
    assert _rows(rec.input_index[simp]) == _rows(rec.manifold)
    assert _rows(simp) <= _rows(cand)
    normals, tangents = data["normals"], data["tangents"]
    assert normals.shape == (n_in, k, k - d) and tangents.shape == (n_in, k, d)
    eye = np.einsum("nki,nkj->nij", normals, normals)
    assert np.abs(eye - np.eye(k - d)).max() < 1e-9
    assert np.abs(np.einsum("nki,nkj->nij", normals, tangents)).max() < 1e-9
    return data


def test_npz_result_of_a_surface(tmp_path, sphere_rec):
    write_result(tmp_path / "r.npz", sphere_rec)
    data = _check_npz(tmp_path / "r.npz", sphere_rec)
    assert len(data["simplices"]) == sphere_rec.topology.n_simplices


def test_npz_result_is_stored_by_default_and_deflated_on_request(tmp_path, sphere_rec):
    import zipfile

    write_result(tmp_path / "plain.npz", sphere_rec)
    write_result(tmp_path / "small.npz", sphere_rec, compress=True)
    for name, method in (("plain", zipfile.ZIP_STORED), ("small", zipfile.ZIP_DEFLATED)):
        with zipfile.ZipFile(tmp_path / f"{name}.npz") as z:
            assert {info.compress_type for info in z.infolist()} == {method}
    plain, small = _check_npz(tmp_path / "plain.npz", sphere_rec), _check_npz(tmp_path / "small.npz", sphere_rec)
    assert all(np.array_equal(plain[key], small[key]) for key in plain)
    assert (tmp_path / "small.npz").stat().st_size < (tmp_path / "plain.npz").stat().st_size


def test_npz_result_maps_duplicates_to_input_rows(tmp_path, circle_rec):
    assert len(circle_rec.input_points) == 110 and circle_rec.n == 100
    write_result(tmp_path / "c.npz", circle_rec)
    data = _check_npz(tmp_path / "c.npz", circle_rec)
    np.testing.assert_array_equal(data["normals"][100:], data["normals"][:10])
    assert data["simplices"].max() < 100  # first input row of each sample


def test_npz_result_in_r4(tmp_path):
    rec = reconstruct(get_manifold("s3").sample(300, seed=0).points, 3)
    write_result(tmp_path / "s3.npz", rec)
    _check_npz(tmp_path / "s3.npz", rec)
    with pytest.raises(InputError, match="3-dimensional"):
        write_result(tmp_path / "s3.obj", rec)


# ---------------------------------------------------------------- write_result: meshes
@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off", ".vtk", ".stl"])
def test_surface_meshes_read_back(tmp_path, sphere_rec, suffix):
    path = tmp_path / f"s{suffix}"
    write_result(path, sphere_rec)
    mesh = _meshio_read(path)
    tris = mesh.get_cells_type("triangle")
    assert len(tris) == len(sphere_rec.manifold) > 0
    if suffix == ".stl":  # STL stores coordinates per triangle, not indices: the same triangles, corner by corner

        def triangles(corners):  # (m, 3, 3): each triangle's corners in order, then the triangles in order
            c = np.array([t[np.lexsort(t.T[::-1])] for t in corners])
            flat = c.reshape(len(c), -1)
            return flat[np.lexsort(flat.T[::-1])]

        expected = sphere_rec.input_points[sphere_rec.point_input[sphere_rec.manifold]]
        np.testing.assert_allclose(triangles(mesh.points[tris]), triangles(expected), atol=1e-6)
    else:
        assert len(mesh.points) == len(sphere_rec.input_points)
        np.testing.assert_allclose(mesh.points, sphere_rec.input_points, atol=1e-6)
        assert _rows(tris) == _rows(sphere_rec.point_input[sphere_rec.manifold])


@pytest.mark.parametrize("suffix", [".ply", ".vtk", ".obj"])
def test_curve_meshes_read_back(tmp_path, circle_rec, trefoil_rec, suffix):
    for rec in (circle_rec, trefoil_rec):
        path = tmp_path / f"c{suffix}"
        write_result(path, rec)
        expected = _rows(rec.point_input[rec.manifold])
        if suffix == ".obj":  # crustview's own OBJ reader reads the 'l' records back
            mesh = read_any_mesh(path)
            verts, segs = mesh.points, mesh.simplices(1)
        else:
            mesh = _meshio_read(path)
            verts, segs = mesh.points, mesh.get_cells_type("line")
        assert len(segs) == len(rec.manifold) > 0 and _rows(segs) == expected
        assert verts.shape == (len(rec.input_points), 3)
        np.testing.assert_allclose(verts[:, : rec.k], rec.input_points, atol=1e-6)


def test_unsupported_result_combinations(tmp_path, circle_rec):
    with pytest.raises(InputError, match="triangles only"):
        write_result(tmp_path / "c.stl", circle_rec)
    with pytest.raises(InputError, match="unsupported"):
        write_result(tmp_path / "c.csv", circle_rec)
    rec4 = reconstruct(get_manifold("circle-r4").sample(60, seed=0).points, 1)
    with pytest.raises(InputError, match="at most 3 dimensions"):
        write_result(tmp_path / "c4.vtk", rec4)
    with pytest.raises(InputError, match="Cannot write"):
        write_result(tmp_path / "no-dir" / "c.npz", circle_rec)


# ---------------------------------------------------------------- write_report
def test_report(tmp_path, sphere_rec):
    path = tmp_path / "r.json"
    write_report(path, sphere_rec)
    data = json.loads(path.read_text())
    assert data == report_dict(sphere_rec)
    # the sphere's sample reconstructs as a sphere, and the file says so
    assert data["topology"]["betti"] == [1, 0, 1] and data["topology"]["closed_manifold"] is True
    assert (data["d"], data["k"], data["n"]) == (2, 3, sphere_rec.n)
    assert data["test"] == sphere_rec.test
    assert data["theta_degrees"] == pytest.approx(np.degrees(sphere_rec.theta))
    assert data["topology"]["betti"] == list(sphere_rec.topology.betti)
    assert data["topology"]["closed_manifold"] == sphere_rec.topology.closed_manifold
    assert data["rules"] == sphere_rec.extraction.counts_by_rule()
    assert set(data["timings"]) == set(sphere_rec.timings)
    with pytest.raises(InputError):
        write_report(tmp_path / "missing" / "r.json", sphere_rec)


def test_run_parameters_round_trip_and_plain_files_have_none(tmp_path):
    pts = get_manifold("circle").sample(60, seed=0).points
    # prune_boundary is an option of the paper's Algorithm 3
    rec = reconstruct(pts, 1, test="cocone-all", theta=0.3, prune_boundary=False, mode="paper")
    write_result(tmp_path / "r.npz", rec)
    got = read_run_parameters(tmp_path / "r.npz")
    assert (got["d"], got["test"], got["theta"], got["prune_boundary"], got["mode"]) == (
        1,
        "cocone-all",
        0.3,
        False,
        "paper",
    )
    again = reconstruct(
        read_points(tmp_path / "r.npz"),
        got["d"],
        test=got["test"],
        theta=got["theta"],
        prune_boundary=got["prune_boundary"],
        mode=got["mode"],
    )
    assert _rows(again.point_input[again.manifold]) == _rows(got["simplices"])  # the same M_S
    np.savez(tmp_path / "plain.npz", points=pts)
    np.save(tmp_path / "plain.npy", pts)
    assert read_run_parameters(tmp_path / "plain.npz") is None
    assert read_run_parameters(tmp_path / "plain.npy") is None


def test_a_saved_built_in_keeps_its_name_and_how_it_was_drawn(tmp_path):
    """Issue 10: a reopened saved built-in lost its expected topology."""
    sample = get_manifold("circle").sample(60, seed=3)
    rec = reconstruct(sample.points, 1)
    info = {"name": "circle", "n": 60, "seed": 3, "noise": 0.0, "density": "uniform", "method": "even"}
    write_result(tmp_path / "b.npz", rec, builtin=info)
    assert read_run_parameters(tmp_path / "b.npz")["builtin"] == info
    write_result(tmp_path / "plain.npz", rec)
    assert read_run_parameters(tmp_path / "plain.npz")["builtin"] is None
    write_result(tmp_path / "noseed.npz", rec, builtin={**info, "seed": None})
    assert "seed" not in read_run_parameters(tmp_path / "noseed.npz")["builtin"]


def test_saved_mode_round_trip(tmp_path):
    """Issue 7: a result remembers which extraction made it.  On the decimated knight the two
    modes give different M_S (the paper's is a small blob), so the mode must come back."""
    from pathlib import Path

    from crustview.io import read_mesh

    points = read_mesh(Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off").points
    robust = reconstruct(points, 2)
    paper = reconstruct(points, 2, mode="paper")
    assert _rows(robust.point_input[robust.manifold]) != _rows(paper.point_input[paper.manifold])
    for rec in (robust, paper):
        path = tmp_path / f"{rec.mode}.npz"
        write_result(path, rec)
        got = read_run_parameters(path)
        assert got["mode"] == rec.mode
        again = reconstruct(
            read_points(path),
            got["d"],
            test=got["test"],
            theta=got["theta"],
            prune_boundary=got["prune_boundary"],
            mode=got["mode"],
        )
        assert _rows(again.point_input[again.manifold]) == _rows(got["simplices"])

    # a result saved before the robust extraction existed has no mode: the paper's loop made it
    with np.load(tmp_path / "paper.npz") as z:
        old = {key: z[key] for key in z.files if key != "mode"}
    np.savez(tmp_path / "old.npz", **old)
    assert read_run_parameters(tmp_path / "old.npz")["mode"] == "paper"
    np.savez(tmp_path / "odd.npz", **old, mode=np.str_("magic"))
    with pytest.raises(InputError, match="magic"):
        read_run_parameters(tmp_path / "odd.npz")


def test_report_of_a_paper_run_lists_its_cascades(tmp_path):
    """A holed torus in paper mode: the prune cascades start at holes of T_S."""
    pts = get_manifold("torus").sample(1500, seed=0).points
    rec = reconstruct(pts[pts[:, 0] <= 0.6], 2, mode="paper")
    data = report_dict(rec)
    assert data["mode"] == "paper" and data["stopped"] == "empty"
    assert json.loads(json.dumps(data)) == data  # plain JSON
    holes = {tuple(sorted(int(rec.point_input[v]) for v in h)) for h in rec.extraction.holes}
    assert data["holes_of_T_S"] == len(holes) > 0
    listed = data["cascades"]
    assert len(listed) == min(20, data["n_cascades"]) > 0
    assert listed[0]["removed"] >= listed[-1]["removed"]
    for c in listed:  # a hole origin is a prune of a face in a single candidate (tau in input rows)
        if c["hole"]:
            assert c["rule"] == "prune-sharp" and tuple(sorted(c["tau"])) in holes
    assert any(c["hole"] for c in listed)
