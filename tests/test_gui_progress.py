"""Issue 19: progress that moves during a long stage that reports nothing (before, the bar sat at
"manifold extraction (Algorithm 3) 0 %" for the whole extraction of a 50,000-point scan).
"""

from __future__ import annotations

import time


def test_a_silent_stage_shows_a_busy_bar_with_its_seconds(qtbot, window):
    def job(progress, cancel):
        progress("extraction", 0.0)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 2.6 and not cancel.is_set():
            time.sleep(0.02)
        return None

    bar = window.run_panel.progress
    assert window.start_job(job, "a long silent stage")
    qtbot.waitUntil(lambda: bar.maximum() == 0, timeout=5000)  # busy indicator after a second
    qtbot.waitUntil(lambda: "manifold extraction (Algorithm 3): 2 s" in bar.format(), timeout=5000)
    window.runner.cancel()
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=10_000)
    assert bar.maximum() == 1000 and "cancelled" in bar.format()


def test_reports_within_a_frame_draw_the_bar_once_and_the_latest_when_the_frame_is_up(qtbot, window):
    """A job that reports 200 times in a burst redraws the bar a few times, not 200 (each redraw is
    synchronous), and the bar ends at its last report of the stage; a new stage and the last report are
    drawn at once."""
    from crustview.qt.run_dock import PROGRESS_FRAME_SECONDS

    panel = window.run_panel
    draws = []
    panel.progress_shown.connect(lambda: draws.append(panel.progress.value()))
    panel.set_busy(True, "a test job")
    draws.clear()
    panel.show_progress("candidates", 0.0)  # a new stage: drawn at once
    assert draws == [0]
    for i in range(1, 200):
        panel.show_progress("candidates", i / 400)  # all within one frame
    assert draws == [0] and panel.progress.value() == 0
    qtbot.waitUntil(lambda: len(draws) == 2, timeout=int(2000 * PROGRESS_FRAME_SECONDS) + 1000)
    assert draws[-1] == int(1000 * 199 / 400)  # the latest report, drawn when the frame was up
    panel.show_progress("extraction", 0.1)  # a new stage: at once, whatever the frame
    assert panel.progress.format().startswith("manifold extraction") and draws[-1] == 100
    panel.show_progress("extraction", 0.2)
    panel.show_progress("extraction", 1.0)  # the last report: at once
    assert draws[-1] == 1000
    panel.show_progress("extraction", 0.5)  # kept for the next frame, then the job ends: never drawn
    panel.set_busy(False)
    qtbot.wait(int(3000 * PROGRESS_FRAME_SECONDS))
    assert 500 not in draws
