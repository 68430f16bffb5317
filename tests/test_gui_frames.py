"""The window draws a finished run in one frame (render.frames), and the pictures it reads back are current."""

from __future__ import annotations

import numpy as np
from gui_helpers import load


def _count_renders(win) -> list:
    """A list that gets an entry for every frame VTK draws in the window (asked for, or a paint's)."""
    drawn: list = []
    win.plotter.ren_win.AddObserver("StartEvent", lambda *_: drawn.append(1))
    return drawn


def test_a_finished_run_is_drawn_in_one_frame(window, qtbot):
    assert window.view.frames.paint is not None  # in the window a frame is the widget's paint
    load(qtbot, window, "sphere")  # the window shown and a first result drawn
    drawn = _count_renders(window)
    at_result = []
    show = window._show_result

    def spy(result):
        at_result.append(len(drawn))
        show(result)
        at_result.append(len(drawn))

    window._show_result = spy
    load(qtbot, window, "torus")
    qtbot.wait(200)  # anything the result still causes
    assert at_result[1] == at_result[0]  # nothing drawn inside the batch
    # the result, its layers, overlays and camera: one frame after the batch (7 before render.frames)
    assert len(drawn) - at_result[0] == 1
    assert window.model.layers["manifold"].count > 0


def _differ(a, b) -> int:
    return int((np.abs(a.astype(int) - b.astype(int)).sum(axis=2) > 30).sum())


def test_a_screenshot_shows_the_model_as_it_is_now(window, qtbot):
    load(qtbot, window, "torus")
    qtbot.wait(50)
    drawn = _count_renders(window)
    before = window.plotter.screenshot(return_img=True)
    assert len(drawn) == 0  # a settled view is read as it was painted: no frame drawn for it
    # no turn of the event loop between the change and the read: the paint asked for has not run yet
    window.model.layers["manifold"].visible = False
    hidden = window.plotter.screenshot(return_img=True)
    assert _differ(before, hidden) > 500
    # inside a batch too (its frame is owed to its end, but a picture read back is of the model now)
    window.model.layers["manifold"].visible = True
    qtbot.wait(50)
    with window.view.held():
        window.model.layers["manifold"].visible = False
        inside = window.plotter.screenshot(return_img=True)
    assert _differ(inside, hidden) == 0
    # at another size: drawn at that size, not a crop of the last frame
    window.model.layers["manifold"].visible = True
    qtbot.wait(50)
    small = window.plotter.screenshot(return_img=True, window_size=(300, 200))
    assert small.shape[:2] == (200, 300)
    ink = np.abs(small.astype(int) - small[-3, -3].astype(int)).sum(axis=2) > 60
    # the torus fills the middle (a crop of the last frame's bottom-left corner, before: background there)
    assert ink[70:130, 100:200].mean() > 0.3
