"""The smaller things of issue 10, each in the real window."""

from pathlib import Path

import pytest

pytest.importorskip("pytestqt")


def load(qtbot, win, name="torus", n=None):
    assert win.load_builtin(name, n)
    qtbot.waitUntil(lambda: not win.runner.busy, timeout=60_000)
    assert win.model.rec is not None, win.last_error
    return win.model.rec


def test_status_bar_counts_the_candidates_the_layer_shows_while_a_change_is_pending(qtbot, window):
    load(qtbot, window)
    layer = window.model.layers["candidates"]
    window.run_panel.test.setCurrentText("literal")
    qtbot.wait(20)
    text = window.status_counts.text()
    assert f"candidates {layer.count:,} (pending change)" in text
    assert layer.count != len(window.model.rec.extraction.simplices)  # the two used to disagree
    window.run_panel.test.setCurrentText(window.model.rec.test)
    assert "pending" not in window.status_counts.text()


def test_boundary_pruning_off_does_not_carry_over_silently_to_new_data(qtbot, window):
    load(qtbot, window, "circle", 60)
    window.run_panel.set_mode("paper")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    window.run_panel.prune.setChecked(False)  # re-extracts with the faces kept
    qtbot.waitUntil(lambda: not window.runner.busy and not window.model.rec.prune_boundary, timeout=60_000)
    rec = load(qtbot, window, "circle", 80)
    assert rec.prune_boundary and window.run_panel.prune.isChecked()
    assert "Prune boundary faces is on again" in window.statusBar().currentMessage()


def test_save_suggests_a_name_in_the_last_folder_and_says_when_a_change_is_pending(qtbot, window, tmp_path):
    load(qtbot, window)
    assert Path(window.suggested_path("-crust.npz")).name == "torus-crust.npz"
    out = tmp_path / "sub"
    out.mkdir()
    assert window.save_result(str(out / "first.npz"))
    assert Path(window.suggested_path("-crust.npz")).parent == out  # the next dialog starts there
    assert Path(window.suggested_path(".png")).parent == out
    window.run_panel.theta.setValue(window.run_panel.theta.value() - 6)  # pending θ change
    assert window.save_result(str(out / "second.npz"))
    msg = window.statusBar().currentMessage()
    assert "not extracted yet" in msg and "Re-extract" in msg
