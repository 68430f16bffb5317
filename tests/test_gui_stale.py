"""Issue 19, no stale display: what the last file left (labels, settings, menus, counts) is reset or named.

Each test fails on the code before: the slice label kept its value, Frame each
step, Holes of T_S, the slice cut and the paper mode carried over silently,
menus offered x4/x5 for R^3 data and the true epsilon without a ground truth,
"Next of rule" listed rules the run never applied, and a hidden layer kept the
count of the step at which it was hidden.
"""

from __future__ import annotations

import numpy as np
from gui_helpers import load, wait_idle


def _items(combo) -> list[str]:
    return [combo.itemText(i) for i in range(combo.count())]


def test_slice_label_and_cut_start_again_for_a_new_file(qtbot, window):
    """Slice moved and cut on a Klein bottle in R^4; the next file shows 0.000, no cut, and says so."""
    load(qtbot, window, "flat-klein", n=600)
    panel = window.projection_panel.slice
    window.model.layers["slice"].visible = True
    panel.set_offset(0.3)
    panel.cut.setChecked(True)
    assert window.model.slice_cut and panel.readout.text() != "0.000"
    load(qtbot, window, "torus")
    assert panel.readout.text() == "0.000" and panel.offset.value() == 0
    assert not window.model.slice_cut and not panel.cut.isChecked()
    assert "the slice cut" in window.statusBar().currentMessage()


def test_frame_each_step_holes_and_paper_mode_are_reset_or_named(qtbot, window):
    """Frame each step and Holes of T_S are turned off for new data; a kept paper mode is named."""
    load(qtbot, window, "circle")
    window.steps_panel.follow.setChecked(True)
    window.model.layers["holes"].visible = True
    window.run_panel.set_mode("paper")
    wait_idle(qtbot, window)
    load(qtbot, window, "torus")
    assert window.model.rec.mode == "paper"
    assert not window.steps_panel.follow.isChecked() and not window.model.layers["holes"].visible
    message = window.statusBar().currentMessage()
    assert "Frame each step" in message and "Holes of T_S" in message, message
    assert "Kept from the last file: the paper's Algorithm 3" in message
    assert window.view.clip_plane is None  # the last step was not framed


def test_menus_offer_only_what_applies(qtbot, window):
    """Colourings by coordinates up to k, ground-truth ones only with a truth; rules this run applied."""
    load(qtbot, window, "torus")
    points = window.layers_panel.rows["points"].extra
    got = _items(points)
    assert "x3" in got and "x4" not in got and "x5" not in got and "hidden depth" not in got
    assert "true epsilon" in got and "normal error" in got  # a built-in has its truth
    load(qtbot, window, "flat-klein", n=600)
    got = _items(points)
    assert "x4" in got and "x5" not in got and "hidden depth" in got
    # points without a ground truth
    window.model.layers["points"].colorby = "x4"
    pts = window.model.rec.input_points[:, :3].copy()
    assert window.start_reconstruction(np.asarray(pts), 2, source="plain points")
    wait_idle(qtbot, window)
    got = _items(points)
    assert not {"true epsilon", "Thm 2 error / bound", "normal error", "x4"} & set(got)
    assert window.model.layers["points"].colorby == "none"  # x4 does not exist here
    assert "distance to M" not in _items(window.layers_panel.rows["manifold"].extra)
    # a paper run's "Next of rule" lists only the rules it applied
    window.run_panel.set_mode("paper")
    wait_idle(qtbot, window)
    rules = _items(window.steps_panel.rule)
    assert rules and set(rules) <= {"prune-sharp", "resolve-nonmanifold"}, rules
    assert window.steps_panel.to_rule.isEnabled()
    # a run of no steps (T_S is M_S already) has no rule to offer (a new user was offered all 16)
    rec = load(qtbot, window, "trefoil")
    assert rec.extraction.n_steps == 0
    steps = window.steps_panel
    assert _items(steps.rule) == [] and not steps.to_rule.isEnabled() and not steps.only_rule.isEnabled()


def test_a_hidden_layer_shows_no_stale_count(qtbot, window):
    """Hide M_S, step: its count is a dash, not the count of the step at which it was hidden; shown again, current."""
    rec = load(qtbot, window, "torus")
    row = window.layers_panel.rows["manifold"]
    layer = window.model.layers["manifold"]
    row.visible.click()
    window.model.player.set_step(5)
    assert row.count.text() == "–"
    row.visible.click()
    alive = int(np.count_nonzero(rec.extraction.alive(5)))
    assert layer.count == alive and row.count.text() == f"{alive:,}"


def test_a_kept_test_and_angle_are_named_and_a_rerun_of_the_same_data_keeps_nothing(qtbot, window):
    """A new user's torus came out WRONG under the literal test at 30 degrees kept from the last built-in,
    and nothing said so; and pressing Reconstruct on the same file with smoothed normals said they were
    "kept from the last file"."""
    load(qtbot, window, "sphere")
    run = window.run_panel
    run.test.setCurrentText("literal")
    run.theta.setValue(60)  # half-degree steps: 30 degrees
    load(qtbot, window, "torus")
    assert window.model.rec.test == "literal"
    message = window.statusBar().currentMessage()
    assert "Kept from the last file: the literal test, θ = 30.0° (Run panel)." in message, message
    run.normals.setCurrentIndex(run.normals.findData("smoothed"))
    run.run.click()  # the same data again, with the planes chosen for it
    wait_idle(qtbot, window)
    assert window.model.rec.normals_method == "smoothed"
    assert "Kept from the last file" not in window.statusBar().currentMessage()
