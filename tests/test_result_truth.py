"""A result written from a mesh's vertices keeps the mesh's faces: reopened or reconstructed again, it is judged
against them again (a new user reopened the foot bones' red WRONG result and saw it amber)."""

from __future__ import annotations

import numpy as np
import pytest

from crustview import io
from crustview.core import reconstruct
from crustview.core.samples.manifolds import get_manifold
from crustview.meshfiles.off import write_off


@pytest.fixture(scope="module")
def holed_torus_mesh(tmp_path_factory):
    """A torus sample whose 'mesh' is its own reconstruction less the faces at its 25 samples nearest one: the
    truth has a hole many spacings around, so the closed torus the vertices give is WRONG against it (a
    hole of one missing face is below the sample's resolution and judges nothing: test_mesh_judges.py)."""
    points = get_manifold("torus").sample(800, seed=0).points
    rec = reconstruct(points, 2, resample=False)
    faces = np.asarray(rec.point_input)[np.asarray(rec.manifold)]
    near = np.argsort(np.linalg.norm(points - points[0], axis=1))[:25]
    faces = faces[~np.isin(faces, near).any(axis=1)]
    path = tmp_path_factory.mktemp("truth") / "holed.off"
    write_off(path, points, faces)
    return path, points, faces


def test_the_faces_go_into_the_npz_and_come_back(tmp_path, holed_torus_mesh):
    _, points, faces = holed_torus_mesh
    rec = reconstruct(points, 2, resample=False)
    io.write_result(tmp_path / "r.npz", rec, mesh=("holed.off", faces))
    saved = io.read_run_parameters(tmp_path / "r.npz")
    name, back = saved["mesh"]
    assert name == "holed.off" and np.array_equal(back, faces)
    # faces that cannot be this result's truth (another d, rows beyond the points) are not stored
    io.write_result(tmp_path / "bad.npz", rec, mesh=("x", faces[:, :2]))
    io.write_result(tmp_path / "far.npz", rec, mesh=("x", faces + len(points)))
    assert io.read_run_parameters(tmp_path / "bad.npz")["mesh"] is None
    assert io.read_run_parameters(tmp_path / "far.npz")["mesh"] is None
    io.write_result(tmp_path / "none.npz", rec)
    assert io.read_run_parameters(tmp_path / "none.npz")["mesh"] is None
    io.write_result(tmp_path / "empty.npz", rec, mesh=("x", faces[:0]))
    assert io.read_run_parameters(tmp_path / "empty.npz")["mesh"] is None


def test_an_altered_truth_is_ignored_and_the_result_still_opens(tmp_path, holed_torus_mesh):
    """Members that are not what write_result stores (an object array, an empty or float face table) leave the
    result readable, without its truth."""
    _, points, faces = holed_torus_mesh
    rec = reconstruct(points, 2, resample=False)
    io.write_result(tmp_path / "r.npz", rec)
    with np.load(tmp_path / "r.npz") as archive:
        members = dict(archive)
    for name, table in (
        (np.array(["x"], dtype=object), faces),
        (np.str_("x"), np.zeros((0, 3), np.int64)),
        (np.str_("x"), faces.astype(float)),
    ):
        np.savez(tmp_path / "bad.npz", **members, truth_name=name, truth_faces=table)
        saved = io.read_run_parameters(tmp_path / "bad.npz")
        assert saved is not None and saved["mesh"] is None and saved["d"] == 2


def test_a_wrong_result_reconstructed_again_from_its_npz_is_still_wrong(capsys, tmp_path, holed_torus_mesh):
    from crustview.__main__ import main

    path, _, _ = holed_torus_mesh
    assert main(["reconstruct", str(path), "-d", "2", "-o", str(tmp_path / "a.npz")]) == 1  # written, but wrong
    first = capsys.readouterr().out
    assert "Verdict: WRONG" in first and (tmp_path / "a.npz").is_file()
    assert main(["reconstruct", str(tmp_path / "a.npz"), "-d", "2", "-o", str(tmp_path / "b.npz")]) == 1
    out, err = capsys.readouterr()
    assert "judged against the faces of holed.off stored with it" in out + err
    assert "Against the faces of holed.off" in out and "Verdict: WRONG" in out


def test_a_batch_with_a_wrong_result_counts_it_and_exits_1(capsys, tmp_path, holed_torus_mesh):
    """The batch's exit status follows the verdicts as one file's does: a WRONG result beside a sure one
    (a reviewer removed "wrong" from the batch's bad verdicts and every test still passed)."""
    from crustview.__main__ import main
    from crustview.io import write_points

    path, points, _ = holed_torus_mesh
    sure = tmp_path / "torus.npy"
    write_points(sure, points)  # the same points without the mesh: nothing to contradict them
    code = main(["reconstruct", str(sure), str(path), "-d", "2", "--out-dir", str(tmp_path / "out")])
    lines = capsys.readouterr().out.splitlines()
    assert any(line.startswith("holed.off: wrong: ") for line in lines), lines
    assert "verdicts: 1 sure, 1 wrong;" in lines[-1] and code == 1
    assert main(["reconstruct", str(sure), "-d", "2", "--out-dir", str(tmp_path / "one")]) == 0
    assert "1 of 1 file reconstructed (0 could not be); verdicts: 1 sure;" in capsys.readouterr().out


@pytest.mark.gl
def test_a_reopened_wrong_result_is_red(qtbot, window, tmp_path, holed_torus_mesh):
    from crustview.qt.info_dock import BANNER_STYLE

    path, _, _ = holed_torus_mesh
    assert window.open_file(path, d=2)
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    assert window.info_panel.banner.styleSheet() == BANNER_STYLE["bad"]
    assert window.save_result(str(tmp_path / "saved.npz"), ask=False)
    assert window.open_file(tmp_path / "saved.npz")
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    banner = window.info_panel.banner
    assert banner.styleSheet() == BANNER_STYLE["bad"] and "WRONG" in banner.text()
