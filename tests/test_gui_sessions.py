"""File ▸ Save session… / Open session… in the real window under Xvfb."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import answer_file_dialog, wait_idle


def trigger(win, text):
    next(a for a in win.actions() if a.text() == text).trigger()


def test_save_then_open_restores_run_step_camera_layers_and_projection(qtbot, window, tmp_path):
    assert window.load_builtin("torus", n=600, seed=2, theta=np.radians(20.0))
    wait_idle(qtbot, window)
    m = window.model
    m.player.set_step(7)
    m.layers["points"].visible = False
    m.layers["manifold"].opacity = 0.45
    m.layers["manifold"].color = "#336699"
    m.layers["candidates"].visible = True
    m.projection.set_angle(0, 2, 0.3)
    window.plotter.camera.azimuth = 40.0
    window.plotter.camera.elevation = 15.0
    camera = np.array(window.plotter.camera_position.to_list())
    basis = m.projection.basis
    answered = answer_file_dialog(tmp_path / "mine")
    trigger(window, "Save sess&ion…")
    assert answered
    saved = tmp_path / "mine.crustview.json"
    assert saved.is_file(), window.last_error

    # something else entirely, every saved setting moved away from its saved value, then the session back
    # through its dialog (loading the circle resets some of them, not the manifold's opacity or T_S's visibility)
    assert window.load_builtin("circle", n=80)
    wait_idle(qtbot, window)
    m.layers["points"].visible = True
    m.layers["manifold"].opacity = 1.0
    m.layers["manifold"].color = "#ffffff"
    m.layers["candidates"].visible = False
    assert window.layers_panel.rows["manifold"].opacity.value() == 100
    answered = answer_file_dialog(saved)
    trigger(window, "Open sessio&n…")
    assert answered
    qtbot.waitUntil(lambda: m.source.startswith("torus"), timeout=60_000)
    wait_idle(qtbot, window)
    rec = m.rec
    assert rec.n == 600 and rec.d == 2 and np.isclose(np.degrees(rec.theta), 20.0)
    assert window.origin.name == "torus" and window.origin.seed == 2
    assert m.player.position == 7
    assert not m.layers["points"].visible and m.layers["candidates"].visible
    assert m.layers["manifold"].opacity == pytest.approx(0.45) and m.layers["manifold"].color == "#336699"
    assert np.allclose(m.projection.basis, basis) and m.projection.angles == {(0, 2): 0.3}
    assert np.allclose(np.array(window.plotter.camera_position.to_list()), camera, atol=1e-9)
    assert "restored" in window.statusBar().currentMessage()
    # what is drawn follows: the layer panel and the adapters show the restored state
    assert not window.view.adapters["points"].part.actor.GetVisibility()
    assert window.layers_panel.rows["manifold"].opacity.value() == 45


def test_a_file_session_reopens_and_a_moved_or_changed_file_gives_one_line(qtbot, window, tmp_path):
    from crustview.core.samples.manifolds import get_manifold

    pts = tmp_path / "torus.xyz"
    np.savetxt(pts, get_manifold("torus").sample(500, seed=1).points)
    window.run_panel.test.setCurrentText("cocone-all")
    assert window.open_file(pts, 2)
    wait_idle(qtbot, window)
    assert window.model.player.n_steps > 3
    window.model.player.set_step(3)
    path = window.save_session(tmp_path / "s.json")  # the ending is added
    assert path == tmp_path / "s.crustview.json" and path.is_file()
    first = window.model.rec

    window.run_panel.test.setCurrentText("cocone")
    assert window.open_file(path)  # a session path (as dropped, or from `crustview view`) opens the session
    wait_idle(qtbot, window)
    assert window.model.rec is not first and window.model.rec.test == "cocone-all"
    assert window.model.player.position == 3 and window.run_panel.test.currentText() == "cocone-all"

    shown = window.model.rec
    pts.write_text(pts.read_text() + "0 0 1.5\n")
    assert not window.open_session(path)
    assert "changed since the session was saved" in window.last_error and "\n" not in window.last_error
    assert window.error_box is not None and window.error_box.isVisible()
    pts.unlink()
    assert not window.open_session(path)
    assert "moved or deleted" in window.last_error
    path.write_text('{"crustview_session": 1, "source": ')
    assert not window.open_session(path)
    assert "not valid JSON" in window.last_error
    assert window.model.rec is shown and not window.runner.busy  # nothing started, nothing lost


def test_a_session_needs_data_that_can_be_reopened(qtbot, window, tmp_path):
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    assert window.start_reconstruction(np.c_[np.cos(t), np.sin(t)], 1, source="arrays")
    wait_idle(qtbot, window)
    assert window.save_session(tmp_path / "x") is None
    assert "neither a file nor a built-in" in window.last_error
    assert not list(tmp_path.glob("*.crustview.json"))
