"""Issue 19, research controls: θ typed in a box, ε in the sample inspector, select by index,
jump to a cascade's first step and play it alone.  None of these existed before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from gui_helpers import load, wait_idle
from PySide6.QtCore import Qt

KNIGHT = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"


def test_theta_typed_in_a_box(qtbot, window):
    """Typing 31.5 and Enter sets θ to exactly 31.5° (the slider follows, the candidates layer too)."""
    load(qtbot, window)
    box = window.run_panel.theta_box
    window.activateWindow()
    qtbot.waitActive(window)
    box.setFocus()
    box.lineEdit().selectAll()
    qtbot.keyClicks(box.lineEdit(), "31.5")
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    assert box.value() == 31.5
    assert window.run_panel.theta.value() == 63
    assert np.isclose(window.model.theta, np.radians(31.5))
    window.run_panel.theta.setValue(50)  # the slider moves the box too
    assert box.value() == 25.0


def test_sample_inspector_shows_epsilon(qtbot, window):
    """The selected sample's text gives its estimated ε and the bounds it is beyond."""
    load(qtbot, window)
    window.model.selection.select_sample(7)
    text = window.info_panel.selection.text()
    eps = window.model.quality.epsilon[7]
    assert f"estimated ε {eps:.3g}" in text


def test_select_by_index(qtbot, window):
    """A sample number, 's N' for a T_S simplex, d + 1 samples, d samples; a bad entry says why."""
    rec = load(qtbot, window)
    box = window.info_panel.lookup
    sel = window.model.selection
    cam = np.array(window.plotter.camera.position)
    box.setText("12")
    box.returnPressed.emit()
    assert sel.sample == 12
    assert not np.allclose(window.plotter.camera.position, cam)  # framed
    tri = sorted(int(v) for v in rec.manifold[0])
    box.setText(" ".join(map(str, tri)))
    box.returnPressed.emit()
    assert sel.simplex is not None and sorted(rec.candidates.faces[sel.simplex]) == tri
    box.setText("s 3")
    box.returnPressed.emit()
    assert sorted(rec.candidates.faces[sel.simplex]) == sorted(rec.extraction.simplices[3])
    box.setText(f"{tri[0]} {tri[1]}")
    box.returnPressed.emit()
    assert tuple(sel.face) == (tri[0], tri[1])
    box.setText(str(rec.n + 5))
    box.returnPressed.emit()
    assert "samples" in window.statusBar().currentMessage() and "#fdecea" in box.styleSheet()
    # a row of the file, as the inspector's "input row" names it: samples are numbered in spatial order
    row = int(np.flatnonzero(rec.input_index != np.arange(len(rec.input_index)))[0])
    box.setText(f"row {row}")
    box.returnPressed.emit()
    assert sel.sample == rec.input_index[row] != row and box.styleSheet() == ""
    assert f"(input row {row})" in window.info_panel.selection.text()
    box.setText(f"r {len(rec.input_index)}")
    box.returnPressed.emit()
    assert "rows" in window.statusBar().currentMessage()
    # the other ways of writing a row, the inspector's own words pasted back included (a review: they selected
    # the sample of that number); several numbers after 'r' are refused, not read as a face
    for text in (f"r{row}", f"rows {row}", f"(input row {row})"):
        sel.select_sample(0)
        box.setText(text)
        box.returnPressed.emit()
        assert sel.sample == rec.input_index[row], text
    box.setText("r 1 2")
    box.returnPressed.emit()
    assert "one row number" in window.statusBar().currentMessage() and sel.sample == rec.input_index[row]
    box.setText("row")
    box.returnPressed.emit()
    assert "'r N'" in window.statusBar().currentMessage()


def test_cascade_first_step_and_play_alone(qtbot, window):
    """From a listed cascade: jump to its first step; play only its steps, in order, then stop."""
    import meshio

    pts = np.asarray(meshio.read(KNIGHT).points, dtype=float)
    window.run_panel.set_mode("paper")
    assert window.start_reconstruction(pts, 2, source="knight")
    wait_idle(qtbot, window)
    panel = window.info_panel.diagnosis
    assert panel.cascades.count() > 0 and not panel.play_alone.isEnabled()
    c = panel.list[1] if len(panel.list) > 1 else panel.list[0]
    panel._clicked(panel.cascades.item(panel.list.index(c)))
    assert panel.to_first.isEnabled() and panel.play_alone.isEnabled()
    player = window.model.player
    panel.to_first.click()
    assert player.position == c.origin + 1 and player.current_step.tau == c.tau
    seen = []
    player.step_changed.connect(seen.append)
    window.steps_panel.speed.setValue(2000)
    panel.play_alone.click()
    assert player.playing
    qtbot.waitUntil(lambda: not player.playing, timeout=30_000)
    want = set(int(i) + 1 for i in c.steps)
    visited = [p for p in seen if p != int(min(c.steps))]
    assert visited and set(visited) <= want and visited == sorted(visited)
    assert player.position == max(want)
