"""The window asks for one frame per finished run (render.frames), and the pictures it gives are current."""

from __future__ import annotations

import numpy as np
from gui_helpers import load


def test_a_finished_run_and_its_preview_ask_one_frame_each(window, qtbot):
    frames = window.view.frames
    assert frames.paint is not None  # in the window a frame is the widget's paint
    at_result = []
    show = window._show_result

    def spy(result):
        at_result.append(frames.frames)
        show(result)
        at_result.append(frames.frames)

    window._show_result = spy
    start = frames.frames
    load(qtbot, window, "torus")
    # the raw points' preview: one frame; the result, its layers, overlays and camera: one more, after the batch
    assert at_result[0] == start + 1
    assert at_result[1] == at_result[0]  # nothing asked inside the batch
    assert frames.frames == start + 2
    assert window.model.layers["manifold"].count > 0


def test_a_screenshot_right_after_a_change_shows_the_change(window, qtbot):
    load(qtbot, window, "torus")
    qtbot.wait(50)
    before = window.plotter.screenshot(return_img=True).astype(int)
    # no turn of the event loop between the change and the read: the paint asked for has not run yet
    window.model.layers["manifold"].visible = False
    after = window.plotter.screenshot(return_img=True).astype(int)
    assert (np.abs(before - after).sum(axis=2) > 30).sum() > 500
