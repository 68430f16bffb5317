"""The command line, run as ``python -m crustview`` in subprocesses."""

from __future__ import annotations

import json
import subprocess
import sys

import meshio
import numpy as np
import pytest

from crustview.core.analysis.dimension import CONTRADICTION_SHARE
from crustview.core.analysis.topology import analyse
from crustview.core.samples.manifolds import MANIFOLDS


def run(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "crustview", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=cwd,
    )


def assert_one_line_error(proc, *fragments, code=2):
    assert proc.returncode == code, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("crustview: error: ")
    assert "Traceback" not in proc.stderr and proc.stdout == ""
    for frag in fragments:
        assert frag in lines[0]


# ---------------------------------------------------------------- bad input
@pytest.fixture(scope="module")
def bad_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    (d / "dir.csv").mkdir()  # exists but cannot be read as a file
    (d / "corrupt.npy").write_bytes(b"\x93NUMPY this is not an array")
    (d / "latin1.csv").write_bytes(b"1,2,3\n\xe9,2,3\n")
    (d / "empty.csv").write_text("")
    (d / "garbage.txt").write_text("Lorem ipsum dolor\nsit amet\n")
    (d / "garbage.ply").write_text("Lorem ipsum dolor\n")
    (d / "ragged.csv").write_text("1,2,3\n4,5\n")
    (d / "onecol.txt").write_text("1\n2\n3\n4\n5\n")
    np.save(d / "vector.npy", np.arange(12.0))
    (d / "nan.csv").write_text("0,0,1\n1,0,nan\n0,1,0\n1,1,1\n2,2,2\n")
    (d / "few.txt").write_text("0 0 0\n1 0 0\n0 1 0\n")
    np.save(d / "plane.npy", get_points("circle", 40))
    return d


def get_points(name, n):
    return MANIFOLDS[name].sample(n, seed=0).points


# Every kind of bad input once through a real process (exit status, stderr) ...
@pytest.mark.parametrize(
    ("file", "d", "fragments"),
    [
        ("missing.csv", 1, ["missing.csv", "does not exist"]),
        ("dir.csv", 1, ["dir.csv", "not a regular file"]),  # unreadable
        ("empty.csv", 1, ["empty.csv", "no points"]),
        ("garbage.txt", 1, ["garbage.txt", "non-number"]),
        ("garbage.ply", 1, ["garbage.ply", ".ply mesh"]),  # meshio prints and calls sys.exit()
        ("vector.npy", 1, ["vector.npy", "2-D"]),  # wrong shape
        ("nan.csv", 1, ["nan.csv", "NaN"]),
        ("plane.npy", 2, ["between 1 and k-1", "got d = 2"]),  # d out of range: d = k
        ("few.txt", 2, ["few.txt: too few points: 3", "need at least 5"]),  # fewer than k + 2 samples: which file
    ],
)
def test_reconstruct_bad_input_is_one_line(bad_files, tmp_path, file, d, fragments):
    proc = run("reconstruct", bad_files / file, "-d", d, "-o", tmp_path / "out.npz")
    assert_one_line_error(proc, *fragments)
    assert not (tmp_path / "out.npz").exists()


# ... and the other cases in-process through the same main(), which is faster.
def run_main(capsys, *args):
    from crustview.__main__ import main

    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return subprocess.CompletedProcess(args, code, out, err)


@pytest.mark.parametrize(
    ("file", "d", "fragments"),
    [
        ("corrupt.npy", 1, ["corrupt.npy", "NumPy .npy"]),
        ("latin1.csv", 1, ["latin1.csv", "UTF-8"]),
        ("ragged.csv", 1, ["ragged.csv", "line 2"]),
        ("onecol.txt", 1, ["onecol.txt", "coordinates"]),
        ("plane.npy", 7, ["between 1 and k-1", "got d = 7"]),  # d > k
        ("plane.npy", 0, ["-d"]),  # rejected by the parser
        ("plane.npy", "x", ["-d"]),
    ],
)
def test_more_bad_input_is_one_line(capsys, bad_files, tmp_path, file, d, fragments):
    proc = run_main(capsys, "reconstruct", bad_files / file, "-d", d, "-o", tmp_path / "out.npz")
    assert_one_line_error(proc, *fragments)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["frobnicate"], ["frobnicate"]),
        (["reconstruct", "x.csv", "-o", "y.npz"], ["-d"]),
        (["reconstruct", "PLANE", "-d", "1"], ["-o"]),
        (["reconstruct", "PLANE", "-d", "1", "-o", "OUT/r.npz", "--theta", "95"], ["theta", "95"]),
        (["reconstruct", "PLANE", "-d", "1", "-o", "OUT/r.npz", "--test", "magic"], ["magic"]),
        (["reconstruct", "PLANE", "-d", "1", "-o", "OUT/r.xyz"], ["r.xyz", "unsupported"]),
        (["reconstruct", "PLANE", "-d", "1", "-o", "OUT/r.stl"], ["triangles only"]),
        (["reconstruct", "PLANE", "-d", "1", "-o", "OUT/nodir/r.npz"], ["nodir"]),
        (["sample", "doughnut", "-o", "OUT/s.csv"], ["doughnut", "torus"]),
        (["sample", "torus", "-n", "-5", "-o", "OUT/s.csv"], ["-n"]),
        (["sample", "torus", "--noise", "-1", "-o", "OUT/s.csv"], ["--noise"]),
        (["sample", "torus", "-n", "50", "-o", "OUT/s.obj"], ["s.obj"]),
        (["view", "OUT/missing.npy"], ["missing.npy", "does not exist"]),
    ],
)
def test_usage_errors_are_one_line(capsys, bad_files, tmp_path, args, fragments):
    args = [a.replace("PLANE", str(bad_files / "plane.npy")).replace("OUT", str(tmp_path)) for a in args]
    assert_one_line_error(run_main(capsys, *args), *fragments)


def test_usage_error_from_a_real_process():
    assert_one_line_error(run("reconstruct", "--theta", "abc"), "--theta")


# ---------------------------------------------------------------- success
def test_too_small_a_sample_suggests_no_command_that_fails(tmp_path, capsys):
    """``sample -n 3`` on a torus (R^3: reconstruct needs 5) wrote the file and suggested a reconstruct
    command that then failed; it says instead that the points are too few."""
    proc = run_main(capsys, "sample", "torus", "-n", 3, "-o", tmp_path / "t3.npy")
    assert proc.returncode == 0 and (tmp_path / "t3.npy").is_file()
    assert "too few to reconstruct (points in R^3 need at least 5)" in proc.stdout
    assert "reconstruct with" not in proc.stdout
    failed = run_main(capsys, "reconstruct", tmp_path / "t3.npy", "-d", 2, "-o", tmp_path / "t3.npz")
    assert failed.returncode == 2 and "need at least 5" in failed.stderr  # what the note foretold


def test_sample_then_reconstruct_a_circle(tmp_path):
    pts = tmp_path / "circle.csv"
    proc = run("sample", "circle", "-n", 100, "--seed", 3, "-o", pts)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "" and "circle" in proc.stdout
    assert f"reconstruct with: crustview reconstruct {pts} -d 1 -o OUTPUT" in proc.stdout
    np.testing.assert_allclose(
        np.loadtxt(pts, delimiter=","), MANIFOLDS["circle"].sample(100, seed=3).points, rtol=1e-15
    )
    out, report = tmp_path / "circle.npz", tmp_path / "circle.json"
    proc = run("reconstruct", pts, "-d", 1, "-o", out, "--report", report)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    summary, extraction, verdict = proc.stdout.strip().split("\n")  # the result, how it was extracted, how sure
    assert "100 points" in summary and "(1, 1)" in summary and "a closed manifold (circle);" in summary
    assert verdict == "Verdict: SURE -- M_S is a closed manifold through every sample."
    # an evenly sampled circle: the paper's Algorithm 3 succeeds, so the robust default returns it
    assert extraction.startswith("extraction: robust (the paper's Algorithm 3 gave a closed manifold")
    with np.load(out) as z:
        assert z["points"].shape == (100, 2) and z["simplices"].shape == (100, 2)
        assert int(z["d"]) == 1 and int(z["k"]) == 2 and str(z["test"]) == "cocone"
        assert float(z["theta"]) == pytest.approx(np.pi / 8)
    data = json.loads(report.read_text())
    assert data["topology"]["betti"] == [1, 1] and data["topology"]["closed_manifold"]
    assert data["verdict"] == {"level": "sure", "text": "M_S is a closed manifold through every sample"}
    assert data["n"] == 100 and data["theta_degrees"] == pytest.approx(22.5)


@pytest.fixture(scope="module")
def torus_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("torus") / "torus.npy"
    proc = run("sample", "torus", "-n", 1500, "-o", path)
    assert proc.returncode == 0, proc.stderr
    return path


def test_reconstruct_torus_npz(torus_file, tmp_path):
    out = tmp_path / "torus.npz"
    proc = run("reconstruct", torus_file, "-d", 2, "-o", out, "--test", "cocone", "--theta", 22.5)
    assert proc.returncode == 0, proc.stderr
    assert "a closed manifold (torus);" in proc.stdout and "(1, 2, 1)" in proc.stdout
    points = np.load(torus_file)
    with np.load(out) as z:
        np.testing.assert_array_equal(z["points"], points)
        simp, normals, tangents = z["simplices"], z["normals"], z["tangents"]
    assert simp.shape == (3000, 3)  # closed torus: chi = V - E + F = 0 with E = 3F/2
    assert simp.min() >= 0 and simp.max() < len(points)
    assert np.unique(simp).size == len(points)  # every sample is a vertex
    assert normals.shape == (1500, 3, 1) and tangents.shape == (1500, 3, 2)
    np.testing.assert_allclose(np.linalg.norm(normals[:, :, 0], axis=1), 1, atol=1e-9)
    # the estimated normals are close to the true ones
    true_tangents = MANIFOLDS["torus"].sample(1500, seed=0).tangents
    assert np.median(np.linalg.norm(np.einsum("nk,nkd->nd", normals[:, :, 0], true_tangents), axis=1)) < 0.1


def test_a_given_d_the_sample_contradicts_is_named_after_the_run(capsys, torus_file, tmp_path):
    """A surface reconstructed as a curve (-d 1) used to be accepted without a word: the result now says that
    local PCA sees another d (on the command line and in the report), and the run still uses the d given."""
    out, report = tmp_path / "t.npz", tmp_path / "t.json"
    proc = run_main(capsys, "reconstruct", torus_file, "-d", 1, "-o", out, "--report", report)
    notes = [line for line in proc.stderr.splitlines() if "was given" in line]
    assert len(notes) == 1 and "-d 1 was given, but the sample looks like d = 2 (a surface)" in notes[0]
    est = json.loads(report.read_text())["dimension_estimate"]
    assert est["d"] == 2 and est["given_d"] == 1 and est["confidence"] > CONTRADICTION_SHARE
    with np.load(out) as z:
        assert z["simplices"].shape[1] == 2  # the run used d = 1, as asked
    # a write that fails after the run: its one error line and no note (a review: the note came first)
    proc = run_main(capsys, "reconstruct", torus_file, "-d", 1, "-o", tmp_path / "t.stl")
    assert proc.returncode != 0 and len(proc.stderr.splitlines()) == 1 and "error" in proc.stderr
    # the d the sample shows: no note, no estimate in the report
    proc = run_main(capsys, "reconstruct", torus_file, "-d", 2, "-o", out, "--report", report)
    assert proc.returncode == 0 and proc.stderr == ""
    assert "dimension_estimate" not in json.loads(report.read_text())


def test_a_split_vote_or_too_few_points_questions_no_d(tmp_path):
    """A contradiction needs a majority of local PCA's votes for one other d; fewer than k + 2 points give
    no estimate at all, so a run that then fails keeps its one error line (checked in the bad-input tests)."""
    from crustview.core.analysis.dimension import contradiction

    rng = np.random.default_rng(4)
    square = np.c_[rng.random((400, 2)), np.zeros(400)]  # a flat square in R^3: d = 2 for nearly every vote
    assert contradiction(square, 2) is None
    assert contradiction(square, 1).d == 2
    # a segment, a square and a cube far apart in R^4, a third of the points each: every d gets about a third
    # of the votes, and none of them contradicts a given d
    parts = [np.c_[rng.random((400, j)), np.zeros((400, 4 - j))] + 10.0 * j for j in (1, 2, 3)]
    split = np.concatenate(parts)[rng.permutation(1200)]
    assert all(contradiction(split, d) is None for d in (1, 2, 3))
    segment = np.c_[rng.random((800, 1)), np.zeros((800, 3))] + 10.0
    assert contradiction(np.concatenate([segment, parts[1]]), 2).d == 1  # two thirds on a segment: 67 % for d = 1
    assert contradiction(square[:4], 1) is None  # k + 1 distinct points: no estimate
    assert contradiction(square[:, :2], 2) is None  # the plane: nothing to estimate


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off", ".vtk", ".stl"])
def test_reconstruct_torus_meshes(capsys, torus_file, tmp_path, suffix):
    out = tmp_path / f"torus{suffix}"
    args = ("reconstruct", torus_file, "-d", 2, "-o", out)
    proc = run(*args) if suffix == ".ply" else run_main(capsys, *args)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    with np.errstate(over="ignore"):  # meshio's STL sniffing overflows a uint32
        mesh = meshio.read(out)
    assert len(mesh.get_cells_type("triangle")) == 3000
    if suffix != ".stl":
        assert len(mesh.points) == 1500


def test_reconstruct_curve_as_ply_lines(tmp_path):
    pts = tmp_path / "trefoil.txt"
    assert run("sample", "trefoil", "-n", 120, "-o", pts).returncode == 0
    proc = run("reconstruct", pts, "-d", 1, "-o", tmp_path / "t.ply")
    assert proc.returncode == 0, proc.stderr
    assert len(meshio.read(tmp_path / "t.ply").get_cells_type("line")) == 120


def test_list_prints_every_manifold():
    proc = run("list")
    assert proc.returncode == 0 and proc.stderr == ""
    lines = proc.stdout.splitlines()
    assert len(lines) == 1 + len(MANIFOLDS)
    for m, line in zip(MANIFOLDS.values(), lines[1:]):
        assert line.split()[:3] == [m.name, str(m.k), str(m.d)]
        assert "(" + ",".join(map(str, m.betti)) + ")" in line


def test_help_exits_zero():
    proc = run("reconstruct", "--help")
    assert proc.returncode == 0 and "--theta" in proc.stdout and proc.stderr == ""


def test_cli_without_gui_never_imports_qt_or_vtk(tmp_path):
    code = (
        "import sys; from crustview.__main__ import main\n"
        f"assert main(['sample', 'circle', '-n', '50', '-o', r'{tmp_path / 'c.ply'}']) == 0\n"
        f"assert main(['reconstruct', r'{tmp_path / 'c.ply'}', '-d', '1', '-o', r'{tmp_path / 'c.vtk'}']) == 0\n"
        "assert main(['list']) == 0\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('PySide6', 'pyvista', 'vtkmodules', 'vtk'))\n"
        "assert not bad, bad\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr


@pytest.fixture(scope="module")
def holed_torus(tmp_path_factory):
    pts = MANIFOLDS["torus"].sample(1500, seed=0).points
    holed = pts[pts[:, 0] <= 0.6]  # cut the torus open: the plane x = 0.6 crosses the tube
    src = tmp_path_factory.mktemp("holed") / "holed.npy"
    np.save(src, holed)
    return src, holed


def test_keep_boundary_on_a_torus_with_a_hole(capsys, tmp_path, holed_torus):
    src, holed = holed_torus
    strict, kept = tmp_path / "strict.npz", tmp_path / "kept.npz"
    report = tmp_path / "strict.json"
    # no closed manifold in either (the pruning eats the tube; kept faces leave a boundary): FAILED, status 1,
    # and the result written all the same
    proc = run_main(capsys, "reconstruct", src, "-d", 2, "-o", strict, "--report", report, "--paper")
    assert proc.returncode == 1 and proc.stderr == "" and "Verdict: FAILED" in proc.stdout
    # --keep-boundary is a paper-mode option: alone, it implies --paper and says so
    proc = run_main(capsys, "reconstruct", src, "-d", 2, "-o", kept, "--keep-boundary")
    assert proc.returncode == 1 and "Verdict: FAILED" in proc.stdout
    assert "--keep-boundary" in proc.stderr and "--paper" in proc.stderr and len(proc.stderr.splitlines()) == 1
    assert "extraction: paper's Algorithm 3 with boundary faces kept" in proc.stdout
    proc = run_main(capsys, "reconstruct", src, "-d", 2, "-o", tmp_path / "both.npz", "--keep-boundary", "--paper")
    assert proc.returncode == 1 and proc.stderr == ""
    with np.load(kept) as a, np.load(tmp_path / "both.npz") as b:
        assert str(a["mode"]) == str(b["mode"]) == "paper" and not a["prune_boundary"]
        assert np.array_equal(a["simplices"], b["simplices"])
    rep = json.loads(report.read_text())
    assert rep["mode"] == "paper"
    assert not rep["topology"]["closed_manifold"]  # a holed torus is not closed: the paper prunes it away
    with np.load(strict) as a, np.load(kept) as b:
        assert len(a["simplices"]) == 0  # the prune cascade eats the open tube
        tri = b["simplices"]
    # kept: an open surface through every sample, in one piece, with a boundary
    assert np.array_equal(np.unique(tri), np.arange(len(holed)))
    rep = analyse(tri, len(holed), 2)
    assert rep.components == 1 and rep.nonmanifold_faces == 0 and rep.betti[2] == 0
    assert rep.boundary_faces > 0 and not rep.closed_manifold


def test_view_rejects_an_impossible_d_before_a_window_opens(capsys, bad_files):
    proc = run_main(capsys, "view", bad_files / "plane.npy", "-d", 2)
    assert_one_line_error(proc, "between 1 and k-1 = 1", "got d = 2")


def test_view_without_a_display_is_one_line(capsys, bad_files, monkeypatch):
    for var in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"):
        monkeypatch.delenv(var, raising=False)
    proc = run_main(capsys, "view", bad_files / "plane.npy", "-d", 1)
    assert_one_line_error(proc, "no display", "xvfb-run")
    assert_one_line_error(run_main(capsys), "no display")
    monkeypatch.setenv("DISPLAY", ":9731")  # no X server there
    assert_one_line_error(
        run_main(capsys, "view", bad_files / "plane.npy", "-d", 1), "cannot connect to the X display ':9731'"
    )


def test_high_dimensions_get_a_warning_first(capsys, tmp_path):
    rng = np.random.default_rng(0)
    src = tmp_path / "r6.npy"
    np.save(src, rng.random((12, 6)))
    proc = run_main(capsys, "reconstruct", src, "-d", 5, "-o", tmp_path / "r6.npz")
    assert (tmp_path / "r6.npz").is_file()  # 12 random points give no closed 5-manifold: FAILED, status 1
    assert proc.returncode == 1 and "Verdict: FAILED" in proc.stdout
    assert proc.stderr.startswith("crustview: warning: Points in R^6") and "long run" in proc.stderr
    small = tmp_path / "c.npy"
    np.save(small, get_points("circle", 40))
    assert run_main(capsys, "reconstruct", small, "-d", 1, "-o", tmp_path / "c.npz").stderr == ""


@pytest.mark.parametrize("scale", [1e300, 1e-300])
def test_reconstruct_at_extreme_scales(tmp_path, scale):
    """Issue 9, item 6: values near 1e300 (or 1e-300) reconstruct, without a warning line."""
    src = tmp_path / "far.npy"
    np.save(src, get_points("torus", 400) * scale)
    proc = run("reconstruct", src, "-d", 2, "-o", tmp_path / "out.npz")
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    assert "a closed manifold" in proc.stdout and "(1, 2, 1)" in proc.stdout


def test_reconstruct_beyond_the_largest_scale_is_one_line(tmp_path):
    src = tmp_path / "huge.csv"
    np.savetxt(src, get_points("circle", 40) * 1e306, delimiter=",")
    assert_one_line_error(run("reconstruct", src, "-d", 1, "-o", tmp_path / "o.npz"), "too large")


# ---------------------------------------------------------------- meshes as ground truth
RESOURCES = __import__("pathlib").Path(__file__).resolve().parents[1] / "resources"


def test_reconstruct_a_mesh_reports_the_comparison(tmp_path):
    report = tmp_path / "r.json"
    proc = run("reconstruct", RESOURCES / "bumpy.off", "-d", 2, "-o", tmp_path / "out.noff", "--report", report)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    assert "Against the faces of bumpy.off:" in proc.stdout and "of 2496 mesh faces recovered" in proc.stdout
    truth = json.loads(report.read_text())["ground_truth"]
    assert truth["mesh_faces"] == 2496 and truth["mesh"]["genus"] == 0 and truth["mesh"]["closed_manifold"]
    assert truth["recovered"] + truth["extra"] == truth["result_faces"]
    assert 0 <= truth["hausdorff"] < float("inf") and truth["hausdorff_error_bound"] > 0
    assert (tmp_path / "out.noff").read_text().startswith("nOFF\n")


def test_mesh_faces_that_do_not_fit_d_are_one_line(tmp_path):
    src = tmp_path / "bad.off"
    src.write_text("OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n3 0 1 2\n3 0 1 9\n")
    assert_one_line_error(run("reconstruct", src, "-d", 2, "-o", tmp_path / "o.npz"), "refers to vertex 9")
    src.write_text("OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n3 0 1 2\n2 3 4\n")
    assert_one_line_error(run("reconstruct", src, "-d", 2, "-o", tmp_path / "o.npz"), "2 vertices")


def test_reconstruct_in_r4_to_noff_and_ply(tmp_path):
    src = tmp_path / "c4.npy"
    np.save(src, get_points("circle-r4", 60))
    for suffix in (".noff", ".ply"):
        out = tmp_path / f"c4{suffix}"
        proc = run("reconstruct", src, "-d", 1, "-o", out)
        assert proc.returncode == 0, proc.stderr
        back = run("reconstruct", out, "-d", 1, "-o", tmp_path / "again.npz")  # its own M_S as the truth
        assert back.returncode == 0, back.stderr
        assert "60 of 60 mesh faces recovered (100.0%), 0 extra" in back.stdout
        assert "Hausdorff distance 0 (the same faces)" in back.stdout


def test_view_rejects_bad_mesh_faces_before_a_window_opens(capsys, tmp_path):
    src = tmp_path / "bad.off"
    src.write_text("OFF\n5 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n3 0 1 5\n")
    proc = run_main(capsys, "view", src, "-d", 2)
    assert_one_line_error(proc, "refers to vertex 5")


# ---------------------------------------------------------------- extraction mode (issue 7)
def _step_counts(line):
    """``{"rule": steps}`` and the total from an ``extraction: ...; N steps: rule a, rule b.`` line."""
    head, _, rules = line.rstrip(".").rpartition(" steps: ")
    total = int(head.rsplit("; ", 1)[1])
    return total, {r.rsplit(" ", 1)[0]: int(r.rsplit(" ", 1)[1]) for r in rules.split(", ")}


def _holes_of(triangles):
    """Edges of a triangle list that lie in exactly one triangle, as a set of sorted pairs."""
    t = np.sort(np.asarray(triangles), axis=1)
    edges = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [0, 2]]])
    rows, counts = np.unique(edges, axis=0, return_counts=True)
    return {tuple(int(v) for v in r) for r in rows[counts == 1]}


@pytest.fixture(scope="module")
def knight_runs(tmp_path_factory):
    """The decimated knight (502 points) reconstructed by the CLI in both modes, with reports."""
    out = tmp_path_factory.mktemp("knight")
    runs = {}
    for mode, extra in (("robust", ()), ("paper", ("--paper",))):
        npz, report = out / f"{mode}.npz", out / f"{mode}.json"
        proc = run("reconstruct", RESOURCES / "decimated-knight.off", "-d", 2, "-o", npz, "--report", report, *extra)
        assert proc.returncode == 0 and proc.stderr == "", proc.stderr
        runs[mode] = (proc.stdout.splitlines(), npz, report)
    return runs


def test_paper_flag_runs_the_papers_algorithm_3(knight_runs):
    """The issue: on the decimated knight the paper's Algorithm 3 leaves a tiny closed blob; the
    default does not stop there.  The printed lines say which extraction ran and its steps per rule."""
    from crustview.core import reconstruct
    from crustview.io import read_mesh

    points = read_mesh(RESOURCES / "decimated-knight.off").points
    lines, npz, report = knight_runs["paper"]
    assert lines[1].startswith("extraction: paper's Algorithm 3; ")
    total, counts = _step_counts(lines[1])
    assert set(counts) == {"prune-sharp", "resolve-nonmanifold"} and sum(counts.values()) == total
    rep = json.loads(report.read_text())
    assert {r: c["steps"] for r, c in rep["rules"].items()} == counts
    paper = reconstruct(points, 2, mode="paper")  # the same run in-process
    assert total == paper.extraction.n_steps
    with np.load(npz) as z:
        assert str(z["mode"]) == "paper"
        assert _rows_set(z["simplices"]) == _rows_set(paper.point_input[paper.manifold])
        used = np.unique(z["simplices"]).size
    assert used < 0.1 * len(points)  # the blob: most samples are dropped

    lines, npz, report = knight_runs["robust"]
    assert lines[1].startswith("extraction: robust (the paper's Algorithm 3 was abandoned after ")
    total, counts = _step_counts(lines[1])
    assert sum(counts.values()) == total and 0 not in counts.values()
    # the extension built M_S instead of pruning it (labelling the cells, or growing it)
    assert counts.get("label-cells", 0) == 1 or counts.get("grow", 0) > 0
    with np.load(npz) as z:
        assert str(z["mode"]) == "robust"
        assert np.unique(z["simplices"]).size > 0.9 * len(points)


def _rows_set(simplices):
    return {tuple(r) for r in np.sort(np.asarray(simplices), axis=1).tolist()}


def test_report_says_which_extraction_ran_and_why(knight_runs):
    from crustview.core import reconstruct
    from crustview.core.analysis.quality import summary
    from crustview.io import read_mesh

    _, npz, report = knight_runs["paper"]
    assert report.stat().st_size < 20_000  # small: the top cascades only
    rep = json.loads(report.read_text())
    assert rep["mode"] == "paper" and rep["notes"] == [] and rep["prune_boundary"] is True
    with np.load(npz) as z:
        holes = _holes_of(z["candidates"])  # T_S, counted here from the saved candidates
    assert rep["holes_of_T_S"] == len(holes) > 0
    cascades = rep["cascades"]
    assert 0 < len(cascades) <= 20 and rep["n_cascades"] >= len(cascades)
    removed = [c["removed"] for c in cascades]
    assert removed == sorted(removed, reverse=True)
    assert sum(removed) <= rep["n_candidates"]
    assert sum(c["steps"] for c in cascades) <= sum(r["steps"] for r in rep["rules"].values())
    for c in cascades:
        assert c["rule"] in ("prune-sharp", "resolve-nonmanifold") and len(c["tau"]) == 2
        if c["hole"]:  # a hole of T_S: its edge lies in a single candidate triangle
            assert c["rule"] == "prune-sharp" and tuple(sorted(c["tau"])) in holes
    assert any(c["hole"] for c in cascades)
    q = rep["sampling_quality"]
    points = read_mesh(RESOURCES / "decimated-knight.off").points
    expected = summary(reconstruct(points, 2, mode="paper"))
    assert {k: v for k, v in q.items() if k != "seconds"} == {k: v for k, v in expected.items() if k != "seconds"}
    assert all(0 <= b <= rep["n"] for b in q["beyond"].values())

    rep = json.loads(knight_runs["robust"][2].read_text())
    assert rep["mode"] == "robust" and "cascades" not in rep
    assert rep["notes"][0].startswith("the paper's Algorithm 3 was abandoned after ")
    assert rep["holes_of_T_S"] == len(holes)  # the same T_S, whichever extraction ran
    assert set(rep["sampling_quality"]["beyond"]) == set(q["beyond"])


def test_view_takes_paper_and_keep_boundary_stays_with_reconstruct():
    from crustview.__main__ import build_parser

    parser = build_parser()
    assert parser.parse_args(["view", "x.npy", "--paper"]).paper
    assert not parser.parse_args(["view", "x.npy"]).paper
    assert parser.parse_args(["reconstruct", "x.npy", "-d", "2", "-o", "y.npz", "--paper"]).paper
    proc = run("reconstruct", "--help")
    assert "--paper" in proc.stdout and "implies --paper" in " ".join(proc.stdout.split())


def test_reconstruct_with_smoothed_normals(capsys, torus_file, tmp_path):
    """--normals smoothed: the report says so, the stored normals are the averaged planes (not those
    of Algorithm 1), and the torus still comes out right; a bad value is one line, no traceback."""
    out_p, out_s = tmp_path / "p.npz", tmp_path / "s.npz"
    rep = tmp_path / "s.json"
    assert run_main(capsys, "reconstruct", torus_file, "-d", 2, "-o", out_p).returncode == 0
    proc = run_main(capsys, "reconstruct", torus_file, "-d", 2, "-o", out_s, "--normals", "smoothed", "--report", rep)
    assert proc.returncode == 0, proc.stderr
    assert "(1, 2, 1)" in proc.stdout
    assert json.loads(rep.read_text())["normals"] == "smoothed"
    with np.load(out_p) as zp, np.load(out_s) as zs:
        diff = np.abs(np.einsum("nk,nk->n", zp["normals"][:, :, 0], zs["normals"][:, :, 0]))
    assert diff.min() < 0.9999  # some planes moved
    bad = run_main(capsys, "reconstruct", torus_file, "-d", 2, "-o", out_s, "--normals", "blurred")
    assert bad.returncode != 0 and "Traceback" not in bad.stderr and "--normals" in bad.stderr


def test_jobs_below_one_is_refused_in_one_line(tmp_path):
    """``-j 0`` (or a negative count) is no number of processes: one line, exit 2, before reading anything."""
    for bad in ("0", "-3", "two"):
        run = subprocess.run(
            [sys.executable, "-m", "crustview", "reconstruct", tmp_path / "a.xyz", "-d", "2", "-o", tmp_path / "a.npz"]
            + ["-j", bad],
            capture_output=True,
            text=True,
        )
        assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1, run.stderr
        assert "-j/--jobs" in run.stderr


def test_a_large_even_sample_says_first_how_long_it_takes(tmp_path, monkeypatch, capsys):
    """A new user's `crustview sample torus -n 300000` was silent for minutes.  Above SAMPLE_SLOW_N even
    points the command says how long it will take and what is instant (checked with the bound lowered);
    i.i.d. points and small samples say nothing."""
    import crustview.__main__ as cli

    monkeypatch.setattr(cli, "SAMPLE_SLOW_N", 100)
    assert cli.main(["sample", "circle", "-n", "200", "-o", str(tmp_path / "a.npy")]) == 0
    err = capsys.readouterr().err
    assert "sampling 200 points evenly takes about" in err and "--method random" in err
    assert cli.main(["sample", "circle", "-n", "200", "--method", "random", "-o", str(tmp_path / "b.npy")]) == 0
    assert cli.main(["sample", "circle", "-n", "50", "-o", str(tmp_path / "c.npy")]) == 0
    assert capsys.readouterr().err == ""


def test_a_flat_mesh_says_its_points_were_read_in_the_plane(capsys, tmp_path):
    """A mesh whose z is 0 everywhere is read as points in R^2: the refusal of d = 2 says why k is 2."""
    flat = tmp_path / "flat.obj"
    grid = [(x, y) for x in range(4) for y in range(4)]
    lines = [f"v {x} {y} 0" for x, y in grid]
    lines += [f"f {4 * x + y + 1} {4 * x + y + 5} {4 * x + y + 2}" for x in range(3) for y in range(3)]
    flat.write_text("\n".join(lines) + "\n")
    proc = run_main(capsys, "reconstruct", flat, "-d", 2, "-o", tmp_path / "out.npz")
    assert proc.returncode == 2
    assert "third coordinate is 0 at every vertex" in proc.stderr and "R^2" in proc.stderr
    assert "between 1 and k-1 = 1" in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "out.npz").exists()
    # its triangles are regions of the plane, no curve's truth: its vertices are reconstructed as a curve
    proc = run_main(capsys, "reconstruct", flat, "-d", 1, "-o", tmp_path / "out.npz")
    assert "faces, regions of that plane, are not a curve's and are not used" in proc.stderr + proc.stdout
    assert "Cannot use the faces" not in proc.stderr and "Verdict:" in proc.stdout
    # a file that is 2-D itself (an nOFF of dimension 2) had no third coordinate to drop: no such note
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    ring = tmp_path / "ring.noff"
    body = "".join(f"{np.cos(a):.6f} {np.sin(a):.6f}\n" for a in t) + "".join(
        f"2 {i} {(i + 1) % 40}\n" for i in range(40)
    )
    ring.write_text(f"nOFF\n2\n40 40 0\n{body}")
    proc = run_main(capsys, "reconstruct", ring, "-d", 1, "-o", tmp_path / "ring.npz")
    assert proc.returncode == 0 and "third coordinate" not in proc.stdout + proc.stderr


def test_an_empty_paper_result_names_no_features_and_no_infinite_distance(capsys, tmp_path):
    """The paper's pruning eats an open scan away: an empty M_S is FAILED, without 42 "uncertain components"
    (every sample is left out of an empty result) or a Hausdorff distance of inf."""
    report = tmp_path / "r.json"
    proc = run_main(
        capsys,
        "reconstruct",
        RESOURCES / "cow-head.off",
        "-d",
        2,
        "--paper",
        "-o",
        tmp_path / "o.npz",
        "--report",
        report,
    )
    assert "0 2-simplices" in proc.stdout and "Verdict: FAILED" in proc.stdout
    assert "uncertain:" not in proc.stdout and "inf" not in proc.stdout.replace("information", "")
    assert "no Hausdorff distance (M_S is empty)" in proc.stdout
    assert json.loads(report.read_text())["uncertain_features"] == []
