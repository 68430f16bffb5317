"""Issue 19: progress that moves during a long stage that reports nothing (before, the bar sat at
"manifold extraction (Algorithm 3) 0 %" for the whole extraction of a 50,000-point scan).
"""

from __future__ import annotations

import time

import pytest

pytest.importorskip("pytestqt")


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
