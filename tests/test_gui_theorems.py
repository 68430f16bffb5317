"""The Information panel's Theorem 2/10 box, the sample colouring and M_S's distance colouring."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QTimer


def test_theorem_box_checks_a_builtin_and_colours_samples_and_ms(qtbot, window):
    from crustview.core.analysis.theorems import check_theorems

    assert window.load_builtin("circle", n=120)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    rec = window.model.rec
    panel = window.info_panel.theorems
    assert panel.isVisibleTo(window.info_panel) and panel.button.isEnabled()
    assert window.model.theorems is None
    panel.button.click()  # runs in the panel's worker thread: the click returns at once
    assert panel.runner.busy and panel.progress.isVisible() and panel.cancel.isVisible()
    assert not panel.button.isEnabled() and window.model.theorems is None
    ticks = []
    timer = QTimer()
    timer.timeout.connect(lambda: ticks.append(1))
    timer.start(10)  # the GUI thread keeps turning while the check runs
    qtbot.waitUntil(lambda: window.model.theorems is not None, timeout=60_000)
    timer.stop()
    assert len(ticks) >= 2 and not panel.progress.isVisible()
    c = window.model.theorems
    assert c is not None and not panel.button.isEnabled()
    assert f"<b>{len(c.violations)}</b> beyond" in panel.label.text()
    # every sample is a dot; the bound's curve and the dots share the axes
    assert panel.scatter.checks is c
    # an independent run gives the same per-sample epsilon (seeded dense sample)
    again = check_theorems(rec, "circle", window.model.truth.tangents)
    assert np.allclose(again.epsilon, c.epsilon)
    points = window.model.layers["points"]
    points.colorby = "Thm 2 error / bound"
    values = np.asarray(window.view.adapters["points"].part.mesh.point_data["values"])
    assert np.allclose(values, c.normal_error / c.bound)
    m = window.model.layers["manifold"]
    window.model.player.last()
    m.colorby = "distance to M"
    a = window.view.adapters["manifold"]
    cells = np.asarray(a.part.mesh.cell_data["values"])
    assert len(cells) == len(rec.manifold)
    assert np.isclose(np.nanmax(cells), c.ms_distance.max())
    assert any("distance of M_S to M" in t for t in window.view._bars)


def test_theorem_box_hidden_for_a_file_without_truth(qtbot, window):
    t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    assert window.start_reconstruction(np.c_[np.cos(t), 0.7 * np.sin(t)], 1, source="ellipse-ish")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert not window.info_panel.theorems.isVisibleTo(window.info_panel)
    assert window.model.check_theorems() is None


def test_theorem_check_cancels_and_can_run_again(qtbot, window):
    assert window.load_builtin("sphere", n=400)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    panel = window.info_panel.theorems
    stages = []
    panel.runner.progress.connect(lambda stage, f: stages.append(stage))
    assert panel.run()
    assert not panel.run()  # one check at a time
    qtbot.waitUntil(lambda: len(stages) > 0, timeout=20_000)  # the worker reports progress
    panel.cancel.click()
    qtbot.waitUntil(lambda: not panel.runner.busy, timeout=30_000)
    assert window.model.theorems is None and "Cancelled" in panel.label.text()
    assert panel.button.isEnabled() and not panel.cancel.isVisible()
    # a new result while a check runs: the old check's numbers are not shown on it
    assert panel.run()
    assert window.load_builtin("circle", n=100)
    qtbot.waitUntil(lambda: not window.runner.busy and not panel.runner.busy, timeout=60_000)
    assert window.model.theorems is None and panel.button.isEnabled()
