"""Issue 19, focus and keys: typing a value then Enter, or Esc, gives the keys back to the replay.

Before, after typing a playback speed → moved the cursor in that box and R did
nothing until the view was clicked, which selected what was under the mouse.
"""

from __future__ import annotations

import numpy as np
from gui_helpers import load
from PySide6.QtCore import Qt


def _focus(qtbot, window, widget):
    window.activateWindow()
    qtbot.waitActive(window)
    widget.setFocus()
    qtbot.waitUntil(widget.hasFocus)


def test_enter_after_typing_a_speed_returns_the_keys_to_the_view(qtbot, window):
    """Type 500 in the speed box, Enter: the speed is set, then → steps and R resets the camera."""
    load(qtbot, window)
    p = window.model.player
    p.first()
    speed = window.steps_panel.speed
    _focus(qtbot, window, speed)
    speed.lineEdit().selectAll()
    qtbot.keyClicks(speed, "500")
    qtbot.keyClick(speed, Qt.Key.Key_Return)
    assert speed.value() == 500.0
    qtbot.waitUntil(window.plotter.hasFocus, timeout=2000)
    qtbot.keyClick(QApplication_focus(), Qt.Key.Key_Right)
    assert p.position == 1
    window.plotter.camera.position = (30.0, 1.0, 2.0)
    cam = np.array(window.plotter.camera.position)
    qtbot.keyClick(QApplication_focus(), Qt.Key.Key_R)
    assert not np.allclose(window.plotter.camera.position, cam)  # R reset the camera


def test_escape_returns_focus_without_touching_the_selection(qtbot, window):
    """Esc in a field moves the focus to the view and keeps the selection; Esc on the view clears it."""
    load(qtbot, window)
    sel = window.model.selection
    sel.select_sample(3)
    goto = window.steps_panel.goto
    _focus(qtbot, window, goto)
    qtbot.keyClick(goto, Qt.Key.Key_Escape)
    qtbot.waitUntil(window.plotter.hasFocus, timeout=2000)
    assert sel.sample == 3
    p = window.model.player
    before = p.position
    qtbot.keyClick(QApplication_focus(), Qt.Key.Key_Home)
    assert p.position == 0 != before
    qtbot.keyClick(QApplication_focus(), Qt.Key.Key_Escape)
    assert sel.sample is None


def QApplication_focus():  # noqa: N802 - reads like the Qt call it wraps
    from PySide6.QtWidgets import QApplication

    return QApplication.focusWidget()
