"""A d given to the window that the sample contradicts is said with the result (session 51), as the command line
says it: from ``view -d`` (``open_file(path, d=...)``) and from the Run panel; a d the window asked, with the
estimate shown in its question, and a d the sample agrees with are not questioned."""

import numpy as np
from gui_helpers import on_next_dialog

from crustview.core.samples.manifolds import get_manifold


def _result_message(qtbot, window) -> str:
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    return window.statusBar().currentMessage()


def test_a_given_d_the_sample_contradicts_is_said_with_the_result(qtbot, window, tmp_path):
    path = tmp_path / "torus.xyz"
    np.savetxt(path, get_manifold("torus").sample(800, seed=3).points)
    assert window.open_file(path, d=1)  # as `crustview view torus.xyz -d 1`
    message = _result_message(qtbot, window)
    assert "d = 1 was given, but the sample looks like d = 2 (a surface)" in message and window.model.rec.d == 1
    # the Run panel's d, back to the one the sample shows: no note
    window.run_panel.d.setValue(2)
    window.run_panel.run.click()
    qtbot.waitUntil(lambda: window.model.rec is not None and window.model.rec.d == 2, timeout=60_000)
    message = _result_message(qtbot, window)
    assert "was given" not in message
    # and to a contradicted one again, from the panel
    window.run_panel.d.setValue(1)
    window.run_panel.run.click()
    qtbot.waitUntil(lambda: window.model.rec is not None and window.model.rec.d == 1, timeout=60_000)
    assert "d = 1 was given, but the sample looks like d = 2" in _result_message(qtbot, window)


def test_a_d_the_window_asked_for_is_not_questioned_again(qtbot, window, tmp_path):
    """The question shows the estimate (d = 2 for a torus); an answer of 1 is the user's informed choice."""
    path = tmp_path / "torus.xyz"
    np.savetxt(path, get_manifold("torus").sample(800, seed=3).points)
    asked = []
    on_next_dialog(lambda dlg: (asked.append(dlg.intValue()), dlg.setIntValue(1), dlg.accept()))
    assert window.open_file(path)
    message = _result_message(qtbot, window)
    assert asked == [2] and window.model.rec.d == 1 and "was given" not in message
