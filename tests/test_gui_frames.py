"""The window draws a finished run in one frame (render.frames), the same picture as before."""

from __future__ import annotations

from gui_helpers import load


def _count_frames(win) -> list:
    drawn: list = []
    real = win.view.frames._draw
    win.view.frames._draw = lambda *a, **k: (drawn.append(1), real(*a, **k))[1]
    return drawn


def test_a_finished_run_and_its_preview_draw_one_frame_each(window, qtbot):
    drawn = _count_frames(window)
    at_result = []
    show = window._show_result

    def spy(result):
        at_result.append(len(drawn))
        show(result)
        at_result.append(len(drawn))

    window._show_result = spy
    load(qtbot, window, "torus")
    # the raw points' preview: one frame; the result, its layers, overlays and camera: one more, after the batch
    assert at_result[0] == 1
    assert at_result[1] == at_result[0]  # nothing drawn inside the batch
    assert len(drawn) == 2
    assert window.model.layers["manifold"].count > 0
