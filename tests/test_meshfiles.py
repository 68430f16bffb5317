"""Mesh files with faces in any dimension: Geomview OFF/nOFF/4OFF, PLY with extra coordinates."""

import struct
from pathlib import Path

import numpy as np
import pytest

from crustview.core import InputError, reconstruct
from crustview.core.samples.manifolds import get_manifold
from crustview.io import read_mesh, read_points, write_points, write_result
from crustview.meshfiles import read_mesh as read_any

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


# ---------------------------------------------------------------- round trips of M_S
@pytest.fixture(scope="module")
def runs():
    """Real reconstructions in several k and d (small n: fast)."""
    out = {}
    for name, n in (("circle", 40), ("trefoil", 120), ("circle-r4", 60), ("clifford-torus", 700)):
        m = get_manifold(name)
        out[name] = reconstruct(m.sample(n, seed=0).points, m.d)
    return out


@pytest.mark.parametrize("suffix", [".noff", ".off", ".ply"])
@pytest.mark.parametrize("name", ["circle", "trefoil", "circle-r4", "clifford-torus", "torus", "s3"])
def test_result_reads_back_to_the_same_points_and_simplices(tmp_path, runs, torus_run, s3_run, name, suffix):
    rec = {"torus": torus_run[0], "s3": s3_run[0]}.get(name) or runs[name]
    assert len(rec.manifold) > 0
    path = tmp_path / f"r{suffix}"
    write_result(path, rec)
    mesh = read_mesh(path)
    np.testing.assert_array_equal(mesh.points, rec.input_points)  # exact: %.17g text, float64 binary
    np.testing.assert_array_equal(mesh.simplices(rec.d), rec.point_input[rec.manifold])
    if suffix == ".noff" or rec.k > 3:
        assert path.read_bytes().startswith(b"nOFF" if suffix != ".ply" else b"ply")


def test_points_in_r5_as_ply_and_their_property_names(tmp_path):
    pts = np.random.default_rng(1).normal(size=(20, 5))
    write_points(tmp_path / "p.ply", pts)
    np.testing.assert_array_equal(read_points(tmp_path / "p.ply"), pts)
    header = (tmp_path / "p.ply").read_bytes().split(b"end_header")[0].decode()
    assert [ln.split()[-1] for ln in header.splitlines() if ln.startswith("property")] == [
        "x0", "x1", "x2", "x3", "x4"]  # fmt: skip
    assert read_mesh(tmp_path / "p.ply") is None  # no faces, no ground truth


# ---------------------------------------------------------------- Geomview OFF variants
def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_4off_is_homogeneous(tmp_path):
    path = _write(tmp_path, "h.off", "4OFF\n3 1 0\n2 4 6 2\n1 0 0 1\n0 3 0 0.5\n3 0 1 2\n")
    mesh = read_any(path)
    np.testing.assert_allclose(mesh.points, [[1, 2, 3], [1, 0, 0], [0, 6, 0]])


def test_noff_in_r4_with_comments_and_face_colours(tmp_path):
    text = (
        "nOFF # four dimensions\n4\n5 2 0\n"
        "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1 # last vertex\n"
        "3 0 1 2 255 0 0\n4 1 2 3 4 0.5 0.5 0.5 1\n"
    )
    mesh = read_any(_write(tmp_path, "a.noff", text))
    assert mesh.points.shape == (5, 4) and mesh.points[4, 3] == 1
    assert [c.tolist() for c in mesh.cells] == [[[0, 1, 2]], [[1, 2, 3, 4]]]


def test_4noff_has_ndim_plus_one_components(tmp_path):
    mesh = read_any(_write(tmp_path, "b.off", "4nOFF\n2\n3 1 0\n2 2 2\n1 0 1\n0 3 3\n3 0 1 2\n"))
    np.testing.assert_allclose(mesh.points, [[1, 1], [1, 0], [0, 1]])


def test_normals_colours_and_texture_prefixes_are_skipped(tmp_path):
    """'N' (upper case) is normals, 'n' (lower case) is n-dimensional."""
    text = (
        "STCNOFF\n3 1 0\n" + "".join(f"{i} {i + 1} {i + 2}  0 0 1  1 0 0 1  0.5 0.5\n" for i in range(3)) + "3 2 1 0\n"
    )
    mesh = read_any(_write(tmp_path, "c.off", text))
    np.testing.assert_array_equal(mesh.points, [[0, 1, 2], [1, 2, 3], [2, 3, 4]])
    assert mesh.cells[0].tolist() == [[2, 1, 0]]


def test_headerless_off(tmp_path):
    mesh = read_any(_write(tmp_path, "d.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
    assert mesh.points.shape == (3, 3) and mesh.n_cells == 1


def test_binary_off_written_by_hand(tmp_path):
    """'OFF BINARY': big-endian int32 counts and indices, float32 coordinates, a colour count per face."""
    body = struct.pack(">3i", 4, 2, 0)
    body += struct.pack(">12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
    body += struct.pack(
        ">4i",
        3,
        0,
        1,
        2,
    ) + struct.pack(">i", 0)
    body += struct.pack(">4i", 3, 0, 2, 3) + struct.pack(">i3f", 3, 1, 0, 0)
    path = tmp_path / "bin.off"
    path.write_bytes(b"OFF BINARY\n" + body)
    mesh = read_any(path)
    np.testing.assert_array_equal(mesh.points[3], [0, 0, 1])
    assert mesh.cells[0].tolist() == [[0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "refers to vertex 7 but the file has 3 vertices"),
        ("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "it has 1 faces but its header says 2"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "says it has 4 vertices but lists 3"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "ends early"),
        ("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "not a number"),
        ("4OFF\n3 1 0\n0 0 0 1\n1 0 0 0\n0 1 0 1\n3 0 1 2\n", "points at infinity"),
        ("4OFF\n3 1 0 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n", "Stella4D"),
        ("MESH\n1 2 3\n", "does not start with an OFF keyword"),
    ],
)
def test_bad_off_files_are_one_sentence(tmp_path, text, fragment):
    path = _write(tmp_path, "bad.off", text)
    with pytest.raises(InputError) as info:
        read_mesh(path)
    msg = str(info.value)
    assert fragment in msg and str(path) in msg and "\n" not in msg


def test_faces_in_one_pass_are_the_line_by_line_ones(tmp_path, monkeypatch):
    # off._uniform_faces (every face line "size i0 ... i(size-1)", read in one pass) against the line-by-line
    # reading it falls back to: a triangle mesh, the same with a comment, a quad mesh, mixed sizes (blocks in
    # order of first appearance), face colours, an index out of range and a non-integer index (the same
    # one-line errors)
    from crustview.meshfiles import off

    head = "OFF\n5 {nf} 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 1\n"
    cases = {
        "tris": head.format(nf=3) + "3 0 1 4\n3 1 2 4\n3 2 3 4\n",
        "comment": head.format(nf=2) + "3 0 1 4 # first\n\n3 1 2 4\n",
        "quads": head.format(nf=2) + "4 0 1 2 3\n4 0 1 4 3\n",
        "mixed": head.format(nf=3) + "4 0 1 2 3\n3 0 1 4\n4 0 1 4 3\n",
        "colours": head.format(nf=2) + "3 0 1 4 1 0 0\n3 1 2 4 0 1 0\n",
        "range": head.format(nf=2) + "3 0 1 4\n3 1 2 9\n",
        "word": head.format(nf=2) + "3 0 1 4\n3 1 two 4\n",
    }
    for name, text in cases.items():
        path = _write(tmp_path, f"{name}.off", text)
        got = []
        for fast in (True, False):
            if not fast:
                monkeypatch.setattr(off, "_uniform_faces", lambda *args: None)
            try:
                mesh = off.read_off(path)
                got.append(("mesh", mesh.points.tolist(), [(c.dtype, c.tolist()) for c in mesh.cells]))
            except InputError as err:
                got.append(("error", str(err)))
            monkeypatch.undo()
        assert got[0] == got[1], name
    assert got[0][0] == "error" and "must be whole numbers" in got[0][1]  # the last case: a non-integer index
    assert off._uniform_faces([["3", "0", "1", "4"], ["3", "1", "2", "4"]], 0, 2).tolist() == [[0, 1, 4], [1, 2, 4]]


# ---------------------------------------------------------------- faces as d-simplices
def test_quads_and_pentagons_become_triangle_fans(tmp_path):
    path = _write(tmp_path, "q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 6\n")
    simp = read_mesh(path).simplices(2)
    assert {tuple(r) for r in simp.tolist()} == {(0, 1, 2), (0, 2, 3), (0, 1, 5)}
    pent = read_any(_write(tmp_path, "p.off", "OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0.5 2 0\n0 1 0\n5 0 1 2 3 4\n"))
    assert pent.simplices(2).tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4]]


def test_faces_that_do_not_fit_d_are_one_sentence(tmp_path):
    tri = read_any(_write(tmp_path, "t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n2 0 3\n"))
    with pytest.raises(InputError, match="1 of them have 2 vertices .* needs 3 or more vertices"):
        tri.simplices(2)
    with pytest.raises(InputError, match="for d = 1: 1 of them have 3 vertices"):
        tri.simplices(1)
    rep = read_any(_write(tmp_path, "r.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n"))
    with pytest.raises(InputError, match="repeat a vertex"):
        rep.simplices(2)


# ---------------------------------------------------------------- PLY variants
def test_ply_ascii_with_w_and_ignored_properties(tmp_path):
    text = (
        "ply\nformat ascii 1.0\ncomment hand-made\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty float w\nproperty float nx\nelement face 1\n"
        "property list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
        "end_header\n0 0 0 0 9\n1 0 0 1 9\n0 1 0 2 9\n0 0 1 3 9\n3 0 1 2\n2 3\n"
    )
    mesh = read_any(_write(tmp_path, "w.ply", text))
    np.testing.assert_array_equal(mesh.points[:, 3], [0, 1, 2, 3])
    assert mesh.points.shape == (4, 4)
    assert sorted(c.tolist()[0] for c in mesh.cells) == [[0, 1, 2], [2, 3]]


def test_ply_big_endian_binary_x0_to_x4(tmp_path):
    pts = np.arange(30, dtype=">f8").reshape(6, 5)
    faces = np.zeros(2, dtype=[("n", "u1"), ("v", ">i4", (3,))])
    faces["n"], faces["v"] = 3, [[0, 1, 2], [3, 4, 5]]
    head = (
        "ply\nformat binary_big_endian 1.0\nelement vertex 6\n"
        + "".join(f"property double x{i}\n" for i in range(5))
        + "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    )
    path = tmp_path / "be.ply"
    path.write_bytes(head.encode() + pts.tobytes() + faces.tobytes())
    mesh = read_mesh(path)
    np.testing.assert_array_equal(mesh.points, pts)
    assert mesh.simplices(2).tolist() == [[0, 1, 2], [3, 4, 5]]


def test_truncated_binary_ply_is_one_sentence(tmp_path):
    path = tmp_path / "cut.ply"
    path.write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 9\nproperty double x\n"
        b"property double y\nend_header\n" + b"\0" * 20
    )
    with pytest.raises(InputError, match="ends early or is malformed"):
        read_points(path)


def test_resources_are_closed_meshes():
    for name, faces in (("bumpy.off", 2496), ("decimated-knight.off", 1000), ("3holes.off", 7200)):
        mesh = read_mesh(RESOURCES / name)
        assert mesh.points.shape[1] == 3 and len(mesh.simplices(2)) == faces
