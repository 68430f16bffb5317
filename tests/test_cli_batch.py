"""The command line as a peer of other tools: progress on a terminal, quiet pipes, -q, batch runs, -d auto."""

import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crustview.core.analysis.dimension import estimate_dimension
from crustview.core.samples.manifolds import MANIFOLDS, get_manifold
from crustview.io import read_points, write_points

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
if not DATA.is_dir():
    DATA = Path("/work/shared/data")
SCANS = sorted(p for p in DATA.rglob("*") if p.suffix in (".off", ".obj", ".ply", ".xyz"))


def _cmd(*args):
    return [sys.executable, "-m", "crustview", *map(str, args)]


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    folder = tmp_path_factory.mktemp("samples")
    write_points(folder / "torus.npy", get_manifold("torus").sample(1500, seed=0).points)
    write_points(folder / "sphere.xyz", get_manifold("sphere").sample(800, seed=0).points)
    write_points(folder / "trefoil.csv", get_manifold("trefoil").sample(300, seed=0).points)
    (folder / "broken.xyz").write_text("1 2 3\n4 5\n")
    return folder


def test_on_a_terminal_a_progress_bar_moves_and_is_erased(samples, tmp_path):
    big = tmp_path / "big.npy"
    # i.i.d. points: the even sampler's farthest-point pass takes 9 s at 20,000 points, the run 1.5 s
    write_points(big, get_manifold("torus").sample(20000, seed=0, method="random").points)
    run = subprocess.run(
        ["script", "-qec", " ".join(_cmd("reconstruct", big, "-d", 2, "-o", tmp_path / "r.npz")), "/dev/null"],
        capture_output=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout[-2000:]
    screen = re.sub(r"\x1b\[[0-9;?]*[a-zA-Z]", "", run.stdout.decode("utf-8", "replace"))  # colours off
    stages = set(re.findall(r"big\.npy: ([a-z ]+?) ━", screen))
    assert {"delaunay", "candidates", "extraction"} <= stages, stages
    percents = {int(p) for p in re.findall(r"(\d+)% \d:\d\d:\d\d", screen)}
    assert len(percents) >= 3  # the bar moves
    assert "Reconstructed a surface" in screen.split("━")[-1]  # the summary comes after the bar's last frame


def test_piped_only_the_summary_and_with_q_nothing(samples, tmp_path):
    run = subprocess.run(
        _cmd("reconstruct", samples / "torus.npy", "-d", 2, "-o", tmp_path / "r.npz"), capture_output=True, text=True
    )
    assert run.returncode == 0 and run.stderr == ""
    lines = run.stdout.splitlines()
    assert len(lines) == 3 and lines[0].startswith("Reconstructed a surface") and lines[1].startswith("extraction:")
    assert lines[2] == "Verdict: SURE -- M_S is a closed manifold through every sample."
    quiet = subprocess.run(
        _cmd("reconstruct", samples / "torus.npy", "-d", "auto", "-o", tmp_path / "q.npz", "-q"),
        capture_output=True,
        text=True,
    )
    assert quiet.returncode == 0 and quiet.stdout == "" and quiet.stderr == ""
    assert (tmp_path / "q.npz").is_file()


def test_batch_runs_files_in_two_processes_and_writes_the_summaries(samples, tmp_path):
    out = tmp_path / "out"
    files = [samples / n for n in ("torus.npy", "sphere.xyz", "trefoil.csv", "broken.xyz")]
    run = subprocess.run(
        _cmd("reconstruct", *files, "-d", "auto", "--out-dir", out, "-j", 2),
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 1, run.stderr  # one file failed
    assert (
        "broken.xyz: not reconstructed: Cannot use" in run.stdout
        or "broken.xyz: not reconstructed: Cannot read" in run.stdout
    )
    assert "3 of 4 files reconstructed (1 could not be); verdicts: " in run.stdout
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(
        ["summary.csv", "summary.json"]
        + [f"{s}{e}" for s in ("torus", "sphere", "trefoil") for e in (".npz", ".report.json")]
    )
    summary = json.loads((out / "summary.json").read_text())
    rows = {Path(r["file"]).name: r for r in summary["rows"]}
    assert [Path(r["file"]).name for r in summary["rows"]] == [f.name for f in files]  # input order
    assert rows["torus.npy"]["betti"] == [1, 2, 1] and rows["torus.npy"]["closed"] and rows["torus.npy"]["d"] == 2
    assert rows["trefoil.csv"]["d"] == 1 and rows["trefoil.csv"]["betti"] == [1, 1]
    assert (
        rows["broken.xyz"]["status"] == "error"
        and rows["broken.xyz"]["verdict"] is None
        and rows["broken.xyz"]["error"]
    )
    assert summary["errors"] == 1  # not the verdict's word: "failed" counts the written results below
    # the closing line counts the written results' verdicts, as the rows give them
    counts = {v: sum(r["status"] == "ok" and r["verdict"] == v for r in rows.values()) for v in summary["verdicts"]}
    assert summary["verdicts"] == counts and sum(counts.values()) == 3
    said = ", ".join(f"{n} {v}" for v, n in counts.items() if n)
    assert f"verdicts: {said};" in run.stdout
    for r in rows.values():
        assert {"points", "uncertain_handles", "uncertain_holes", "uncertain_components", "seconds"} <= set(r)
    table = list(csv.DictReader((out / "summary.csv").read_text().splitlines()))
    assert [Path(r["file"]).name for r in table] == [f.name for f in files]
    assert table[0]["betti"] == "1 2 1" and table[0]["status"] == "ok" and table[3]["status"] == "error"
    report = json.loads((out / "torus.report.json").read_text())
    assert report["dimension_estimate"]["d"] == 2


def test_batch_refuses_o_and_several_inputs_without_out_dir(samples, tmp_path):
    a, b = samples / "torus.npy", samples / "sphere.xyz"
    run = subprocess.run(_cmd("reconstruct", a, b, "-d", 2, "-o", tmp_path / "x.npz"), capture_output=True, text=True)
    assert run.returncode == 2 and "--out-dir" in run.stderr and len(run.stderr.splitlines()) == 1


@pytest.mark.parametrize("name", list(MANIFOLDS))
def test_d_auto_is_right_on_every_builtin(name):
    m = MANIFOLDS[name]
    for seed in (0, 1):
        est = estimate_dimension(m.sample(m.default_n, seed=seed).points)
        assert est.d == m.d, est.sentence()
        # in R^2 there is no estimate to be confident of, and the sentence says so (session 30)
        assert f"d = {m.d}" in est.sentence() and ("confidence" if m.k > 2 else "not an estimate") in est.sentence()


@pytest.mark.skipif(not SCANS, reason="needs ../shared/data")
def test_d_auto_is_right_on_every_scan_in_the_shared_data():
    wrong = {}
    for path in SCANS:
        est = estimate_dimension(read_points(path))
        if est.d != 2:
            wrong[path.name] = est.sentence()
    assert len(SCANS) >= 25 and not wrong, wrong


@pytest.mark.parametrize("scale", [1e-300, 1e300])
def test_d_auto_at_extreme_scales_is_the_same_as_at_one(scale, tmp_path):
    """A torus near 1e-300 voted d = 1 everywhere (its covariances underflowed to 0), and near 1e300 the
    command line stopped with an unexpected IndexError; reconstruct works at both scales (test_cli.py)."""
    from crustview.__main__ import main

    pts = get_manifold("torus").sample(400, seed=0).points
    at_one = estimate_dimension(pts)
    far = estimate_dimension(pts * scale)
    assert far.d == at_one.d == 2 and far.votes == at_one.votes
    np.save(tmp_path / "far.npy", pts * scale)
    assert main(["reconstruct", str(tmp_path / "far.npy"), "-d", "auto", "-q", "-o", str(tmp_path / "o.npz")]) == 0


def test_d_auto_says_curve_in_the_plane_and_handles_duplicates():
    est = estimate_dimension(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))
    assert est.d == 1 and est.confidence == 1.0 and "R^2" in est.sentence()
    assert "100%" not in est.sentence() and "not checked" in est.sentence()
    pts = get_manifold("sphere").sample(500, seed=0).points
    assert estimate_dimension(np.vstack([pts, pts])).d == 2


def test_d_auto_on_the_command_line_says_what_it_chose(samples, tmp_path):
    run = subprocess.run(
        _cmd("reconstruct", samples / "trefoil.csv", "-d", "auto", "-o", tmp_path / "t.npz"),
        capture_output=True,
        text=True,
        env={**os.environ},
    )
    assert run.returncode == 0, run.stderr
    assert "-d auto chose d = 1 (a curve)" in run.stderr and "local PCA" in run.stderr
    assert "Reconstructed a curve" in run.stdout


def test_compare_json_never_replaces_an_input_and_view_takes_d_auto(samples, tmp_path):
    res = tmp_path / "r.npz"
    subprocess.run(_cmd("reconstruct", samples / "torus.npy", "-d", 2, "-o", res), check=True, capture_output=True)
    before = res.read_bytes()
    run = subprocess.run(_cmd("compare", res, res, "--json", res), capture_output=True, text=True)
    assert run.returncode == 2 and "Refusing to write over the input file" in run.stderr and run.stdout == ""
    assert res.read_bytes() == before
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")}
    run = subprocess.run(_cmd("view", samples / "trefoil.csv", "-d", "auto"), capture_output=True, text=True, env=env)
    assert "-d auto chose d = 1 (a curve)" in run.stderr  # then no display here: one error line, exit 2
    assert run.returncode == 2 and run.stderr.strip().splitlines()[-1].startswith("crustview: error: no display")


def test_a_failed_row_names_its_file_once():
    """The error of a file's points names the file (for a single run); the batch line names it already."""
    from crustview.cli_batch import row_line

    row = {
        "file": "/data/few.txt",
        "status": "error",
        "error": "few.txt: too few points: 3; points in R^3 need at least 5 (k + 2) for a reconstruction",
    }
    want = "few.txt: not reconstructed: too few points: 3; points in R^3 need at least 5 (k + 2) for a reconstruction"
    assert row_line(row) == want
    row["error"] = "Cannot read '/data/few.txt': the file does not exist."
    assert row_line(row) == "few.txt: not reconstructed: Cannot read '/data/few.txt': the file does not exist."


def test_a_failed_file_in_a_batch_says_the_note_that_explains_it(samples, tmp_path, capsys):
    """A flat OBJ (z = 0) among others: its FAILED line is followed by the note that its points were read in
    R^2 (a new user's batch said only "d must be between 1 and k-1 = 1")."""
    from crustview.__main__ import main

    flat = tmp_path / "flat.obj"
    grid = [(x, y) for x in range(4) for y in range(4)]
    flat.write_text("\n".join(f"v {x} {y} 0" for x, y in grid) + "\n")
    code = main(["reconstruct", str(flat), str(samples / "sphere.xyz"), "-d", "2", "--out-dir", str(tmp_path / "o")])
    out = capsys.readouterr()
    text = out.out + out.err
    assert code == 1
    lines = text.splitlines()
    i = next(i for i, line in enumerate(lines) if line.startswith("flat.obj: not reconstructed: "))
    assert "third coordinate is 0" in lines[i + 1] and lines[i + 1].startswith("  note: ")
    assert any(line.startswith("sphere.xyz: ") and "not reconstructed" not in line for line in lines)


def test_a_failed_verdict_exits_1_alone_and_in_a_batch(samples, tmp_path, capsys):
    """A written result that is no closed manifold (the paper's pruning eats the open cow head away: an empty
    M_S) says FAILED and exits 1, also with -q; in a batch beside a sure file the closing line counts one of
    each and the batch exits 1.  The sure file alone exits 0."""
    from crustview.__main__ import main

    cow = Path(__file__).resolve().parents[1] / "resources" / "cow-head.off"
    code = main(["reconstruct", str(cow), "-d", "2", "--paper", "-o", str(tmp_path / "c.npz")])
    out = capsys.readouterr().out
    assert "Verdict: FAILED" in out and code == 1, out
    assert main(["reconstruct", str(cow), "-d", "2", "--paper", "-q", "-o", str(tmp_path / "q.npz")]) == 1
    assert capsys.readouterr().out == "" and (tmp_path / "q.npz").is_file()  # written all the same
    assert main(["reconstruct", str(samples / "sphere.xyz"), "-d", "2", "--paper", "-o", str(tmp_path / "s.npz")]) == 0
    assert "Verdict: SURE" in capsys.readouterr().out
    both = [
        "reconstruct",
        str(samples / "sphere.xyz"),
        str(cow),
        "-d",
        "2",
        "--paper",
        "--out-dir",
        str(tmp_path / "b"),
    ]
    code = main(both)
    lines = capsys.readouterr().out.splitlines()
    assert code == 1
    assert any(line.startswith("cow-head.off: failed: ") for line in lines), lines
    assert "2 of 2 files reconstructed (0 could not be); verdicts: 1 sure, 1 failed;" in lines[-1]


def test_a_given_d_the_sample_contradicts_is_in_the_batch_rows_and_summaries(samples, tmp_path, capsys):
    """A batch at -d 1 over a surface and a curve: the surface's row and its summaries name the d local PCA sees
    (a review: only its report did); the curve's do not."""
    from crustview.__main__ import main

    out = tmp_path / "o"
    main(["reconstruct", str(samples / "sphere.xyz"), str(samples / "trefoil.csv"), "-d", "1", "--out-dir", str(out)])
    lines = capsys.readouterr().out.splitlines()
    (sphere,) = [line for line in lines if line.startswith("sphere.xyz: ")]
    (trefoil,) = [line for line in lines if line.startswith("trefoil.csv: ")]
    assert "d = 1 (given; the sample looks like d = 2)," in sphere and "looks like" not in trefoil
    rows = {Path(r["file"]).name: r for r in json.loads((out / "summary.json").read_text())["rows"]}
    assert rows["sphere.xyz"]["d_estimate_contradicts"] == 2 and rows["trefoil.csv"]["d_estimate_contradicts"] is None
    with open(out / "summary.csv", newline="") as f:
        table = {Path(r["file"]).name: r for r in csv.DictReader(f)}
    assert table["sphere.xyz"]["d_estimate_contradicts"] == "2" and table["trefoil.csv"]["d_estimate_contradicts"] == ""


def test_ctrl_c_in_a_batch_keeps_a_summary_of_the_files_done(samples, tmp_path, capsys, monkeypatch):
    """A new user pressed Ctrl-C after some files of a batch were done: their results stayed but no summary
    listed them.  Now the summary lists them, and the files not reached as cancelled.  The interrupt is
    raised where the second file would begin (the first runs for real)."""
    from crustview import cli_batch
    from crustview.__main__ import main

    real = cli_batch._job
    calls = []

    def job(path, *args):
        calls.append(path)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(path, *args)

    monkeypatch.setattr(cli_batch, "_job", job)
    out = tmp_path / "out"
    files = [samples / "sphere.xyz", samples / "torus.npy", samples / "trefoil.csv"]
    code = main(["reconstruct", *map(str, files), "-d", "auto", "--out-dir", str(out), "-j", "1"])
    assert code == 130 and "no partial file was written" in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert [r["status"] for r in summary["rows"]] == ["ok", "cancelled", "cancelled"] and summary["cancelled"] == 2
    assert summary["rows"][0]["verdict"] == "sure" and Path(summary["rows"][0]["output"]).is_file()
    table = list(csv.DictReader((out / "summary.csv").read_text().splitlines()))
    assert [r["status"] for r in table] == ["ok", "cancelled", "cancelled"]
    assert sorted(p.name for p in out.iterdir()) == ["sphere.npz", "sphere.report.json", "summary.csv", "summary.json"]
