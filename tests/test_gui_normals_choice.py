"""The Run panel's choice of normal planes: Algorithm 1 or the smoothed planes (issue 18, item 1)."""

import numpy as np
from gui_helpers import load, wait_idle


def _choose(window, value):
    box = window.run_panel.normals
    box.setCurrentIndex(box.findData(value))


def test_smoothed_normals_run_and_show_in_the_normals_layer(qtbot, window):
    """Choosing smoothed planes marks the result out of date; Reconstruct then runs Algorithm 2 on
    them, the normals layer draws them (they differ from Algorithm 1's), and the panel shows the
    result's choice; switching back gives Algorithm 1's planes again."""
    rec = load(qtbot, window, "torus", 800)
    assert rec.normals_method == "paper" and window.run_panel.normals_method == "paper"
    first = rec.normals.copy()
    assert not window.run_panel.stale.isVisible()
    _choose(window, "smoothed")
    assert window.run_panel.stale.isVisible() and "smoothed" in window.run_panel.stale.text()
    window.run_panel.run.click()
    wait_idle(qtbot, window)
    rec = window.model.rec
    assert rec.normals_method == "smoothed"
    assert not window.run_panel.stale.isVisible()
    cos = np.abs(np.einsum("nk,nk->n", first[:, :, 0], rec.normals[:, :, 0]))
    assert cos.min() < 0.9999  # the planes moved
    assert rec.topology.betti == (1, 2, 1)
    # the normal-error colouring is of the run's planes: computed again, it changes with them
    smoothed_err = window.model.point_values("normal error")[0].copy()
    _choose(window, "paper")
    window.run_panel.run.click()
    wait_idle(qtbot, window)
    assert window.model.rec.normals_method == "paper"
    np.testing.assert_allclose(window.model.rec.normals, first)
    paper_err = window.model.point_values("normal error")[0]
    assert smoothed_err.shape == paper_err.shape and not np.allclose(smoothed_err, paper_err)


def test_smoothed_normals_carried_to_new_data_are_named(qtbot, window):
    load(qtbot, window, "circle", 60)
    _choose(window, "smoothed")
    window.run_panel.run.click()
    wait_idle(qtbot, window)
    rec = load(qtbot, window, "circle", 80)
    assert rec.normals_method == "smoothed"
    assert "smoothed normals" in window.statusBar().currentMessage()
    _choose(window, "paper")


def test_a_session_keeps_the_normals(qtbot, window, tmp_path):
    """Saved with smoothed planes, a session reopens with them (and the panel shows them)."""
    load(qtbot, window, "circle", 60)
    _choose(window, "smoothed")
    window.run_panel.run.click()
    wait_idle(qtbot, window)
    path = tmp_path / "s.crustview.json"
    assert window.save_session(str(path))
    import json

    assert json.loads(path.read_text())["normals"] == "smoothed"
    _choose(window, "paper")
    load(qtbot, window, "circle", 80)
    assert window.model.rec.normals_method == "paper"
    assert window.open_session(str(path))
    wait_idle(qtbot, window)
    assert window.model.rec.normals_method == "smoothed" and window.run_panel.normals_method == "smoothed"
    _choose(window, "paper")


def test_a_saved_result_reopens_with_its_own_planes(qtbot, window, tmp_path):
    """A result made with smoothed normals and saved reopened with Algorithm 1's planes (a new user's
    fertility), whatever the window had chosen: the .npz now stores its planes and the run follows them."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import read_run_parameters, write_result

    points = get_manifold("sphere").sample(300, seed=2).points
    rec = reconstruct(points, 2, normals="smoothed")
    path = tmp_path / "s.npz"
    write_result(path, rec)
    assert read_run_parameters(path)["normals"] == "smoothed"
    assert window.run_panel.normals_method == "paper"
    assert window.open_file(path)
    wait_idle(qtbot, window)
    assert window.model.rec.normals_method == "smoothed" and window.run_panel.normals_method == "smoothed"
    assert "Same M_S as saved" in window.statusBar().currentMessage()
    assert "Kept from the last file" not in window.statusBar().currentMessage()
    _choose(window, "paper")
