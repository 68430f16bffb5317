"""The Run panel's choice of normal planes: Algorithm 1 or the smoothed planes (issue 18, item 1)."""

import numpy as np
import pytest

pytest.importorskip("pytestqt")
from gui_helpers import load, wait_idle  # noqa: E402


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
