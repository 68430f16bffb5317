"""The real main window under Xvfb, driven with qtbot."""

import time
from pathlib import Path

import numpy as np
import pytest
from gui_helpers import display_xy, load, on_next_dialog
from PySide6.QtCore import Qt

from crustview.qt.info_dock import BANNER_STYLE


def shot(win):
    win.view.render()
    return win.plotter.screenshot(return_img=True)


def differs(a, b, min_pixels=30):
    return int((np.abs(a.astype(int) - b.astype(int)).sum(axis=2) > 30).sum()) >= min_pixels


def front_sample(win):
    """The sample nearest to the camera (surely visible)."""
    rec = win.model.rec
    cam = np.array(win.plotter.camera.position)
    p = win.model.projection.project(rec.points)
    return int(np.argmin(np.linalg.norm(p - cam, axis=1)))


def test_loading_a_builtin_sample(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    assert m.truth is not None and m.source.startswith("torus")
    assert m.layers["points"].count == rec.n
    assert m.layers["manifold"].count == len(rec.manifold)  # opened on the final M_S
    m.player.first()
    assert m.layers["manifold"].count == len(rec.extraction.simplices)  # step 0: all of T_S
    assert window.steps_panel.log.rowCount() == rec.extraction.n_steps
    assert window.steps_panel.slider.maximum() == rec.extraction.n_steps
    table = window.info_panel.topology
    found = {table.item(r, 0).text(): table.item(r, 1).text() for r in range(table.rowCount())}
    assert found["Betti numbers (Z/2)"] == ", ".join(map(str, rec.topology.betti))
    assert "torus" in window.windowTitle()
    assert window.run_panel.d.value() == 2


def test_menu_dialog_dimension_question_and_drop(qtbot, window, tmp_path):
    """The ways a user opens data: File > Open built-in sample (its dialog),
    a file whose d is asked for, and a file dropped on the window."""
    from PySide6.QtCore import QMimeData, QPoint, QUrl
    from PySide6.QtGui import QDropEvent
    from PySide6.QtWidgets import QInputDialog

    def pick_circle(dlg):
        dlg.name.setCurrentIndex(dlg.name.findData("circle"))
        dlg.n.setValue(90)
        dlg.accept()

    action = next(a for a in window.actions() if a.text() == "Open &built-in sample…")
    answered = on_next_dialog(pick_circle)
    action.trigger()  # modal: returns once the dialog is answered
    assert answered
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=30_000)
    rec = window.model.rec
    assert rec.n == 90 and rec.d == 1 and window.model.source.startswith("circle")
    assert window.view.adapters["manifold"].part.n_cells == len(rec.extraction.simplices)

    # a file without d: the question suggests d from local PCA (a surface: 2)
    pts = tmp_path / "torus.xyz"
    from crustview.core.samples.manifolds import get_manifold

    np.savetxt(pts, get_manifold("torus").sample(600, seed=1).points)
    asked = []

    def answer_d(dlg):
        assert isinstance(dlg, QInputDialog)
        asked.append(dlg.intValue())
        dlg.accept()

    on_next_dialog(answer_d)
    assert window.open_file(pts)
    assert asked == [2]
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.rec is not rec and window.model.rec.d == 2 and window.model.rec.n == 600

    # dropping a file opens it too (d asked again; answered 1 for a curve)
    curve = tmp_path / "trefoil.csv"
    np.savetxt(curve, get_manifold("trefoil").sample(150, seed=2).points, delimiter=",")
    on_next_dialog(lambda dlg: (dlg.setIntValue(1), dlg.accept()))
    mime = QMimeData()
    mime.setUrls([QUrl.fromLocalFile(str(curve))])
    drop = QDropEvent(
        QPoint(10, 10), Qt.DropAction.CopyAction, mime, Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier
    )
    window.dropEvent(drop)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.source == "trefoil.csv" and window.model.rec.d == 1 and window.model.rec.n == 150
    assert str(curve.resolve()) in window.recent_files()


def test_keyboard_and_slider_stepping_follow_the_recorded_steps(qtbot, window):
    rec = load(qtbot, window)
    window.model.player.first()  # data opens on its final M_S (issue 19): replay from T_S
    ext = rec.extraction

    def recorded(i):
        """Simplices alive after i steps, from the step records alone."""
        return len(ext.simplices) - sum(len(s.removed) for s in ext.steps[:i])

    manifold = window.view.adapters["manifold"].part
    window.activateWindow()
    qtbot.waitActive(window)
    window.plotter.setFocus()
    for key, want in (
        (Qt.Key.Key_Right, 1),
        (Qt.Key.Key_Right, 2),
        (Qt.Key.Key_Left, 1),
        (Qt.Key.Key_End, ext.n_steps),
        (Qt.Key.Key_Home, 0),
    ):
        qtbot.keyClick(window.plotter, key)
        assert window.model.player.position == want
        assert manifold.n_cells == recorded(want)
    window.steps_panel.slider.setValue(ext.n_steps // 2)
    assert manifold.n_cells == recorded(ext.n_steps // 2)
    assert window.steps_panel.counter.text() == f"step {ext.n_steps // 2} / {ext.n_steps}"
    # selecting a row of the event log jumps there
    window.steps_panel.table.selectRow(4)
    assert window.model.player.position == 5
    assert manifold.n_cells == recorded(5)
    # play runs to the end
    window.steps_panel.speed.setValue(500)
    qtbot.keyClick(window.plotter, Qt.Key.Key_Space)
    qtbot.waitUntil(lambda: not window.model.player.playing, timeout=20_000)
    assert window.model.player.position == ext.n_steps
    assert manifold.n_cells == len(rec.manifold)


@pytest.mark.gl
def test_toggling_each_layer_changes_pixels(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    ext = rec.extraction
    # a state in which every layer has something to show
    i = next(s.index + 1 for s in ext.steps if s.removed)
    m.player.set_step(max(i, ext.n_steps // 3))
    m.selection.select_sample(front_sample(window))
    m.layers["poles"].mode = "all"
    for _name, layer in m.layers.items():
        layer.visible = True
    m.layers["candidates"].opacity = 1.0
    assert m.cascades()  # the torus's T_S has cascades to show (the cascade layer is checked below)
    m.set_cascade(m.cascades()[0])
    qtbot.wait(50)
    assert ext.steps[m.player.position - 1].removed  # the step layer has something to show
    rows = window.layers_panel.rows
    assert set(rows) == set(m.layers)
    # three layers have nothing to show here, and are checked elsewhere: the comparison layer is empty until a
    # comparison is made (test_gui_compare_export), the torus has no uncertain features and is orientable
    # (test_gui_uncertain and test_gui_orientation draw those); every other layer, T_S's holes and the
    # cascade among them, must draw something and be toggled below
    assert not rec.uncertain_features and rec.topology.orientable
    empty = {n for n in m.layers if m.layers[n].count == 0}
    assert empty == {"compare", "uncertain", "orientation"}
    on = shot(window)  # every layer shown; each check below restores exactly this picture
    for name in sorted(set(m.layers) - empty):
        box = rows[name].visible
        assert box.isChecked()
        box.click()  # the layer panel's own check box, as a user does
        assert not m.layers[name].visible
        off = shot(window)
        box.click()
        assert m.layers[name].visible
        assert differs(on, off), f"hiding layer {name!r} did not change the picture"
        assert not differs(on, shot(window), min_pixels=1), f"showing {name!r} again did not restore the picture"


@pytest.mark.gl
def test_projection_changes_picture_not_data(qtbot, window):
    rec = load(qtbot, window, "clifford-torus")
    points = rec.points.copy()
    n_cells = window.view.adapters["manifold"].part.n_cells
    before = shot(window)
    window.projection_panel.sliders[(0, 3)].setValue(60)
    after = shot(window)
    assert differs(before, after, 500)
    window.projection_panel.pca.click()
    pca = shot(window)
    assert differs(after, pca, 500)
    assert window.model.rec is rec and np.array_equal(rec.points, points)
    assert window.view.adapters["manifold"].part.n_cells == n_cells
    assert "x4" in window.projection_panel.basis.text()
    # grand tour animates and pauses
    window.projection_panel.tour.click()
    b0 = window.model.projection.basis
    qtbot.wait(300)
    window.projection_panel.tour.click()
    assert not window.model.tour.playing
    assert not np.allclose(b0, window.model.projection.basis)


def test_bad_file_shows_error_and_keeps_previous_result(qtbot, window, tmp_path):
    rec = load(qtbot, window)
    window.model.player.set_step(3)
    cells = window.view.adapters["manifold"].part.n_cells
    before = shot(window)
    bad = tmp_path / "bad.xyz"
    bad.write_text("1 2 3\n4 five 6\n")
    assert not window.open_file(bad, d=2)
    assert "bad.xyz" in window.last_error and "line 2" in window.last_error
    assert "Traceback" not in window.error_box.text()
    assert window.error_box is not None and window.error_box.isVisible()
    assert window.model.rec is rec and window.model.player.position == 3
    window.error_box.close()
    assert window.view.adapters["manifold"].part.n_cells == cells
    assert not differs(before, shot(window), min_pixels=1)  # the picture is untouched
    # too few points for the core: reported from the worker, previous result kept
    few = tmp_path / "few.xyz"
    np.savetxt(few, rec.points[:4])
    window.last_error = None
    assert window.open_file(few, d=2)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=30_000)
    assert window.last_error and "Traceback" not in window.last_error
    assert "need at least 5 (k + 2)" in window.last_error
    assert window.error_box.isVisible()
    assert window.model.rec is rec and window.model.player.position == 3
    assert window.view.adapters["manifold"].part.n_cells == cells
    assert "previous result kept" in window.run_panel.progress.format()
    assert str(few.resolve()) in window.recent_files()
    window.error_box.close()
    # an impossible d for the file is asked again (here: cancelled), nothing lost
    good = tmp_path / "pts.xyz"
    np.savetxt(good, rec.points[:200])
    asked = []
    on_next_dialog(lambda dlg: (asked.append(dlg.intValue()), dlg.reject()))
    assert not window.open_file(good, d=7)
    assert asked == [2]  # the local-PCA suggestion for a surface in R^3
    assert window.model.rec is rec and window.model.player.position == 3


@pytest.mark.timing
@pytest.mark.fresh_runs  # needs a run long enough to act during it
def test_cancel_stops_a_long_run(qtbot, window):
    rec = load(qtbot, window)
    stages = []
    window.runner.progress.connect(lambda s, f: stages.append(s))
    assert window.load_builtin("trefoil", 2500)  # near-quadratic Delaunay: a long run
    qtbot.waitUntil(lambda: "candidates" in stages, timeout=60_000)
    assert window.runner.busy and window.run_panel.cancel.isEnabled()
    clicked_at = len(stages)
    t0 = time.monotonic()
    with qtbot.waitSignal(window.runner.cancelled, timeout=15_000):
        window.run_panel.cancel.click()
    # the run stopped inside the candidate stage, not after finishing
    assert time.monotonic() - t0 < 2.0
    assert not {"extraction", "topology"} & set(stages[clicked_at:])
    assert not window.runner.busy
    assert window.model.rec is rec
    assert "cancelled" in window.run_panel.progress.format()
    assert window.run_panel.run.isEnabled()


@pytest.mark.fresh_runs  # needs a run long enough to act during it
def test_cancel_during_the_robust_extraction_says_so_at_once_and_stops_soon(qtbot, window):
    """A new user's octopus took 13 s to stop, its bar still at "manifold extraction 47 %" with Cancel live.

    The casting's labelled path (cut-handle and join-parts, seconds of work) now checks between its
    rounds: the bar says "cancelling…" at the click, Cancel takes no second press, and the run stops soon.
    """
    path = Path(__file__).parents[1] / "resources" / "casting.off"
    fractions = []
    window.runner.progress.connect(lambda s, f: fractions.append(f) if s == "extraction" else None)
    assert window.open_file(path, d=2)
    qtbot.waitUntil(lambda: any(f > 0.2 for f in fractions), timeout=60_000)  # inside the labelled path
    assert window.runner.busy
    t0 = time.monotonic()
    window.run_panel.cancel.click()
    assert window.run_panel.progress.format() == "cancelling…"
    assert not window.run_panel.cancel.isEnabled() and not window.status_progress.cancel.isEnabled()
    assert window.status_progress.isVisible()
    with qtbot.waitSignal(window.runner.cancelled, timeout=15_000):
        pass
    assert time.monotonic() - t0 < 2.0
    assert not window.runner.busy and window.model.rec is None
    assert "cancelled" in window.run_panel.progress.format()
    assert window.run_panel.run.isEnabled()


@pytest.mark.gl
def test_clicking_selects_a_sample_and_info_follows(qtbot, window):
    rec = load(qtbot, window)
    i = front_sample(window)
    x, y = display_xy(window, window.model.projection.project(rec.points[i]))
    got = window.pick_at(int(round(x)), int(round(y)))
    assert got is not None and got[0] == "sample"
    j = got[1]
    assert np.linalg.norm(rec.points[j] - rec.points[i]) < 3 * window.model.spacing[i]
    assert f"Sample {j}" in window.info_panel.selection.text()
    assert window.view.adapters["voronoi"].part.n_cells > 0


def test_jump_to_removing_step_and_open_faces(qtbot, window):
    rec = load(qtbot, window)
    ext = rec.extraction
    e = int(np.flatnonzero(ext.removed_at < ext.n_steps)[-1])
    row = window.model.candidate_row(e)
    window.model.selection.select_simplex(row)
    assert window.info_panel.jump.isEnabled()
    window.info_panel.jump.click()
    assert window.model.player.position == ext.removed_at[e] + 1
    assert e in ext.steps[window.model.player.position - 1].removed
    window.model.player.first()
    window.docks["info"].raise_()  # the list follows the steps while it is in sight
    qtbot.wait(50)
    window.info_panel.refresh_faces()
    faces = window.info_panel.faces
    assert faces.count() > 0
    cam = window.plotter.camera.position
    item = faces.item(0)
    qtbot.mouseClick(faces.viewport(), Qt.MouseButton.LeftButton, pos=faces.visualItemRect(item).center())
    face = item.data(Qt.ItemDataRole.UserRole)
    assert window.model.selection.face == tuple(sorted(face))
    assert window.plotter.camera.position != cam  # framed
    assert window.view.adapters["selection"].part.n_cells > 0


def test_reextract_with_another_theta_and_save(qtbot, window, tmp_path):
    rec = load(qtbot, window)
    window.run_panel.theta.setValue(30)  # 15 degrees
    assert window.view.adapters["candidates"].part.n_cells == int(rec.candidates.mask(rec.test, np.radians(15)).sum())
    window.run_panel.run.click()
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=30_000)
    new = window.model.rec
    assert new is not rec and np.isclose(new.theta, np.radians(15))
    assert window.model.player.n_steps == new.extraction.n_steps
    out = tmp_path / "result.npz"
    assert window.save_result(str(out)) and out.exists()
    png = tmp_path / "view.png"
    assert window.save_screenshot(str(png)) and png.stat().st_size > 1000


def test_prune_boundary_checkbox_reextracts_a_torus_with_holes(qtbot, window):
    from crustview.core.samples.manifolds import get_manifold

    pts = get_manifold("torus").sample(1500, seed=0).points
    holed = pts[pts[:, 0] <= 0.6]  # cut open: a tube with two boundary circles, like a scan with holes
    panel, info = window.run_panel, window.info_panel
    manifold = window.view.adapters["manifold"].part
    panel.set_mode("paper")  # the paper's pruning is what this test is about (robust is the default)
    assert panel.prune.isChecked() and "paper" in panel.prune.text() and panel.prune.toolTip()
    assert window.start_reconstruction(holed, 2, source="holed torus")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    rec = window.model.rec
    assert rec is not None and rec.prune_boundary and rec.extraction.stopped == "empty"
    window.model.player.last()
    assert manifold.n_cells == 0  # the paper's prune cascade removes everything
    assert not info.banner.isHidden() and "NOT a closed manifold" in info.banner.text()
    assert rec.topology.messages[0][:50] in info.banner.text()
    assert "pruned (paper)" in info.interpretation.text() and "empty" in info.interpretation.text()
    assert window.view.legend.notes[0] == "M_S is NOT a closed manifold"  # also written in the view

    panel.prune.click()  # off: only Algorithm 3 runs again
    qtbot.waitUntil(lambda: window.model.rec is not rec and not window.runner.busy, timeout=60_000)
    kept = window.model.rec
    assert kept.delaunay_simplices is rec.delaunay_simplices and kept.candidates.faces is rec.candidates.faces
    assert not kept.prune_boundary and kept.extraction.stopped == "open"
    assert not panel.prune.isChecked()
    window.model.player.last()
    assert manifold.n_cells == len(kept.manifold) > 0
    assert window.model.layers["manifold"].count == len(kept.manifold)
    assert "kept (prune off)" in info.interpretation.text() and "open" in info.interpretation.text()

    panel.prune.click()  # on again: empty again
    qtbot.waitUntil(lambda: window.model.rec is not kept and not window.runner.busy, timeout=60_000)
    assert window.model.rec.prune_boundary and panel.prune.isChecked()
    window.model.player.last()
    assert manifold.n_cells == 0


def test_inspector_on_a_hull_sample_and_a_simplex(qtbot, window):
    rec = load(qtbot, window)
    t = len(rec.delaunay_simplices)
    hull = int(np.flatnonzero(rec.pole_index[:, 0] >= t)[0])
    window.model.selection.select_sample(hull)
    text = window.info_panel.selection.text()
    assert f"Sample {hull}" in text and "vertex at infinity (hull sample), direction (" in text
    assert window.view.adapters["voronoi"].part.n_cells > 0  # the (cut-off) cell of a hull sample draws
    assert window.view.adapters["poles"].parts[2].n_cells == 1  # the ray towards infinity
    interp = window.info_panel.interpretation.text()
    assert f"{int((rec.pole_index[:, 0] >= t).sum())} of {rec.n}" in interp
    assert "cocone (some vertex)" in interp and "pruned (paper)" in interp and "spacing" in interp
    # closed manifold through every sample: no warning, only which extraction ran
    assert window.info_panel.banner.styleSheet() == BANNER_STYLE["ok"]
    assert "through every sample</b> — robust extraction" in window.info_panel.banner.text()
    window.model.selection.select_simplex(0)
    text = window.info_panel.selection.text()
    for test in ("cocone (some vertex)", "cocone-all (every vertex)", "literal ("):
        assert test in text
    assert "cocone angle at each vertex" in text
    tips = [window.run_panel.test.itemData(i, Qt.ItemDataRole.ToolTipRole) for i in range(3)]
    assert "SOME vertex" in tips[0] and "EVERY vertex" in tips[1] and "orientation" in tips[2]


def test_saved_result_reopens_with_its_own_run_and_wrong_topology_is_flagged(qtbot, window, tmp_path):
    """A result saved with the literal test reopens as that run (no d question),
    and a closed result with the wrong Betti numbers is not called a success."""
    from crustview import io
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    sample = get_manifold("torus").sample(1500, seed=0)
    saved = reconstruct(sample.points, 2, test="literal", theta=np.radians(30))
    path = tmp_path / "lit.npz"
    io.write_result(path, saved)
    assert window.open_file(path)  # no dialog: d comes from the file
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    rec = window.model.rec
    assert (rec.d, rec.test) == (2, "literal") and np.isclose(rec.theta, np.radians(30))
    assert len(rec.manifold) == len(saved.manifold)
    assert "Same M_S as saved in lit.npz" in window.statusBar().currentMessage()
    assert window.run_panel.test.currentText() == "literal"

    # built-in torus with the literal test in the paper's mode: closed, but b1 = 0 and samples skipped
    window.run_panel.set_mode("paper")  # re-extracts the current result first
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec.mode == "paper", timeout=60_000)
    window.run_panel.test.setCurrentText("literal")
    load(qtbot, window, "torus")
    t = window.model.rec.topology
    assert t.closed_manifold and t.betti != (1, 2, 1)
    text = window.run_panel.progress.format()
    assert "WRONG" in text and "≠ true (1, 2, 1)" in text and f"{t.unused_samples} unused" in text
    # one verdict: the Information box and the note over the view say the same, in red
    from crustview.qt.info_dock import BANNER_STYLE

    banner = window.info_panel.banner
    assert banner.styleSheet() == BANNER_STYLE["bad"] and "WRONG" in banner.text()
    assert f"{t.unused_samples} unused" in banner.text() and window.view.notes()[0].startswith("M_S is WRONG")


def test_changing_the_test_marks_the_result_out_of_date_until_reextracted(qtbot, window):
    rec = load(qtbot, window)
    panel = window.run_panel
    assert not panel.stale.isVisible() and panel.run.text() == "Reconstruct"
    panel.test.setCurrentText("literal")
    assert panel.stale.isVisible() and panel.run.text() == "Re-extract"
    assert "literal" in panel.stale.text() and "cocone" in panel.stale.text()
    assert window.model.layers["candidates"].count == int(rec.candidates.mask("literal", rec.theta).sum())
    panel.run.click()
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not rec, timeout=60_000)
    assert window.model.rec.test == "literal"
    assert not panel.stale.isVisible() and panel.run.text() == "Reconstruct"
    # moving theta back and forth: out of date only while it differs
    panel.theta.setValue(panel.theta.value() + 10)
    assert panel.stale.isVisible()
    panel.theta.setValue(panel.theta.value() - 10)
    assert not panel.stale.isVisible()


def test_frame_each_step_moves_the_camera_onto_the_step_drawn_on_top(qtbot, window):
    rec = load(qtbot, window)
    ext = rec.extraction
    window.steps_panel.follow.setChecked(True)
    whole = np.array(window.plotter.camera.focal_point)
    window.model.player.set_step(40)
    step = ext.steps[39]
    focus = np.array(window.plotter.camera.focal_point)
    tau = window.model.projection.project(rec.points[list(step.tau)]).mean(axis=0)
    assert np.linalg.norm(focus - tau) < 4 * np.median(window.model.spacing)
    assert np.linalg.norm(focus - whole) > np.linalg.norm(focus - tau)
    # the step highlight lives in the overlay renderer, so M_S cannot hide it
    step_actor = window.view.adapters["step"].part.actor
    assert window.view.top_renderer.HasViewProp(step_actor)
    assert not window.plotter.renderer.HasViewProp(step_actor)
    on = shot(window)
    window.model.layers["step"].visible = False
    assert differs(on, shot(window), min_pixels=50)


@pytest.mark.fresh_runs  # needs a run long enough to act during it
def test_raw_points_are_shown_while_the_first_run_goes(qtbot, window):
    """An empty window shows the samples at once; the result replaces them."""
    before = shot(window)
    assert window.load_builtin("trefoil", 1500)  # long enough to look at mid-run
    assert window.runner.busy
    assert window.plotter.actors.get("preview") is not None
    assert differs(before, shot(window), min_pixels=200)
    assert window.layers_panel.rows["points"].count.text().replace(",", "") == "1500"
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.rec is not None
    assert window.plotter.actors.get("preview") is None


def test_small_screens_keep_half_the_window_for_the_view(qtbot, window):
    window.fit_to_screen(1024, 700)
    qtbot.wait(100)
    load(qtbot, window, "circle")
    qtbot.wait(100)
    assert window.width() <= 1024 and window.height() <= 700
    assert window.plotter.width() >= 0.5 * window.width()
    assert len(window.tabifiedDockWidgets(window.docks["steps"])) == 4
    assert not window.docks["steps"].visibleRegion().isEmpty()  # Steps is the tab in front


def test_y_up_view_for_scans(qtbot, window):
    load(qtbot, window, "circle")
    load(qtbot, window, "sphere")
    assert np.allclose(window.plotter.camera.up, (0, 0, 1), atol=1e-6)
    window.y_up.trigger()
    assert np.allclose(window.plotter.camera.up, (0, 1, 0), atol=1e-6)
    load(qtbot, window, "circle")  # stays on for the session
    load(qtbot, window, "sphere")
    assert np.allclose(window.plotter.camera.up, (0, 1, 0), atol=1e-6)
    window.y_up.trigger()
    assert np.allclose(window.plotter.camera.up, (0, 0, 1), atol=1e-6)


def test_reextraction_keeps_the_camera_and_step_a_new_sample_resets_them(qtbot, window):
    rec = load(qtbot, window)
    window.plotter.camera.zoom(2.0)
    window.model.player.set_step(5)
    cam = np.array(window.plotter.camera.position)
    window.run_panel.test.setCurrentText("cocone-all")
    window.run_panel.run.click()
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not rec, timeout=60_000)
    assert np.allclose(window.plotter.camera.position, cam)
    assert window.model.player.position == 5
    load(qtbot, window, "sphere")
    assert not np.allclose(window.plotter.camera.position, cam)
    assert window.model.player.position == 0


def test_arrow_keys_move_a_focused_slider_not_the_replay(qtbot, window):
    load(qtbot, window)
    window.model.player.first()  # data opens on its final M_S (issue 19): replay from T_S
    window.activateWindow()
    qtbot.waitActive(window)
    theta = window.run_panel.theta
    theta.setFocus()
    qtbot.waitUntil(theta.hasFocus)
    before = theta.value()
    qtbot.keyClick(theta, Qt.Key.Key_Right)
    qtbot.keyClick(theta, Qt.Key.Key_Right)
    assert theta.value() == before + 2
    assert window.model.player.position == 0
    window.plotter.setFocus()
    qtbot.keyClick(window.plotter, Qt.Key.Key_Right)
    assert window.model.player.position == 1


def test_the_event_log_shows_exactly_the_current_step(qtbot, window):
    load(qtbot, window)
    window.model.player.first()  # data opens on its final M_S (issue 19): replay from T_S
    table = window.steps_panel.table
    player = window.model.player

    def selected():
        return [ix.row() for ix in table.selectionModel().selectedRows()]

    for _ in range(5):
        player.next()
    assert selected() == [4]
    table.selectRow(2)  # a click on row 3 jumps to step 3
    assert player.position == 3 and selected() == [2]
    player.next()
    player.next()
    assert selected() == [4]
    player.first()
    assert selected() == []
    window.steps_panel.rule.setCurrentText("resolve-nonmanifold")
    player.last()
    words = window.steps_panel.words.text()
    window.steps_panel.to_rule.click()  # nothing after the last step
    assert window.steps_panel.words.text() == words
    assert "No further step" in window.statusBar().currentMessage()


def test_the_out_of_date_note_does_not_squash_the_run_panel(qtbot, window):
    load(qtbot, window)
    panel = window.run_panel
    heights = {w: w.height() for w in (panel.d, panel.test, panel.theta, panel.prune)}
    panel.test.setCurrentText("literal")
    qtbot.waitUntil(panel.stale.isVisible)
    qtbot.wait(100)
    for w, h in heights.items():
        assert w.height() >= min(h, w.sizeHint().height()), w
    assert panel.d.height() >= panel.d.sizeHint().height()


def test_saved_result_with_another_d_keeps_its_test_and_theta(qtbot, window, tmp_path):
    from crustview import io
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    saved = reconstruct(get_manifold("sphere").sample(300, seed=0).points, 2, test="literal", theta=np.radians(30))
    path = tmp_path / "s.npz"
    io.write_result(path, saved)
    assert window.open_file(path, d=1)
    assert "saved with d = 2" in window.statusBar().currentMessage()
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    rec = window.model.rec
    assert rec.d == 1 and rec.test == "literal" and np.isclose(rec.theta, np.radians(30))


def test_saved_result_reopens_in_its_mode_unless_told_otherwise(qtbot, window, tmp_path):
    """Issue 7: a result saved by the paper's Algorithm 3 reopens in paper mode although the
    window's default is robust; ``open_file(..., mode=)`` (``crustview view --paper``) wins."""
    from pathlib import Path

    from crustview import io
    from crustview.core import reconstruct

    knight = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"
    points = io.read_mesh(knight).points
    saved = reconstruct(points, 2, mode="paper")
    path = tmp_path / "knight.npz"
    io.write_result(path, saved)
    assert window.run_panel.mode == "robust"
    assert window.open_file(path)
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not None, timeout=60_000)
    rec = window.model.rec
    assert rec.mode == "paper" and window.run_panel.mode == "paper"
    assert len(rec.manifold) == len(saved.manifold)
    assert "Same M_S as saved in knight.npz" in window.statusBar().currentMessage()

    assert window.open_file(path, mode="robust")
    assert "saved in paper mode; reconstructing in robust mode" in window.statusBar().currentMessage()
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not rec, timeout=60_000)
    assert window.model.rec.mode == "robust" and window.run_panel.mode == "robust"
    assert len(window.model.rec.manifold) != len(saved.manifold)


def test_keys_in_a_floating_dock_and_a_busy_window(qtbot, window, tmp_path):
    load(qtbot, window)
    window.model.player.first()  # data opens on its final M_S (issue 19): replay from T_S
    dock = window.docks["run"]
    dock.setFloating(True)
    dock.show()
    qtbot.waitExposed(dock)
    dock.activateWindow()
    theta = window.run_panel.theta
    theta.setFocus()
    qtbot.waitUntil(theta.hasFocus)
    before = theta.value()
    qtbot.keyClick(theta, Qt.Key.Key_Right)
    assert theta.value() == before + 1 and window.model.player.position == 0
    dock.setFloating(False)
    # opening a file while a run goes is refused, and the running job is untouched
    assert window.load_builtin("trefoil", 1500)
    pts = tmp_path / "p.xyz"
    np.savetxt(pts, window.model.rec.points[:100])
    assert not window.open_file(pts, d=2)
    assert "already running" in window.last_error
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.source.startswith("trefoil")
    assert "saved" not in window.statusBar().currentMessage()


def test_a_result_between_slider_steps_is_not_out_of_date(qtbot, window):
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    sample = get_manifold("circle").sample(80, seed=0)
    rec = reconstruct(sample.points, 1, theta=np.radians(22.3))
    window.model.set_reconstruction(rec, truth=sample, source="circle")
    assert window.run_panel.theta.value() == 45  # shown as 22.5°
    assert not window.run_panel.stale.isVisible()


def test_legend_names_all_poles_and_a_colouring_that_needs_the_truth(qtbot, window, tmp_path):
    load(qtbot, window, "s3")
    window.model.layers["poles"].mode = "all"
    labels = [label for label, _ in window.view.legend_entries()]
    assert "Pole at infinity (hull sample)" in labels  # S^3: every sample is on the hull
    from crustview.render.overlay import OK_COLOR

    # the notes (the verdict, green for this closed S^3) follow the entries
    notes = window.view.notes()
    assert notes and window.view.legend.entries == window.view.legend_entries() + [(n, OK_COLOR) for n in notes]
    # a point file has no true manifold: the normal-error colouring says so
    pts = tmp_path / "torus.xyz"
    np.savetxt(pts, load_points_of("torus"))
    assert window.open_file(pts, d=2)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    window.model.layers["points"].colorby = "normal error"
    labels = [label for label, _ in window.view.legend_entries()]
    assert any(label.startswith("normal error: not available") for label in labels)


def load_points_of(name, n=600):
    from crustview.core.samples.manifolds import get_manifold

    return get_manifold(name).sample(n, seed=0).points


def test_focus_entering_the_open_faces_list_selects_nothing(qtbot, window):
    load(qtbot, window)
    window.docks["info"].raise_()  # the list follows the steps while it is in sight
    qtbot.wait(50)
    window.model.player.set_step(5)
    window.info_panel.refresh_faces()
    faces = window.info_panel.faces
    assert faces.count() > 0
    cam = np.array(window.plotter.camera.position)
    faces.setFocus()
    faces.setCurrentRow(0)  # keyboard focus and current row, no click
    qtbot.wait(50)
    assert window.model.selection.face is None
    assert np.allclose(window.plotter.camera.position, cam)
    faces.itemClicked.emit(faces.item(0))  # a click selects and frames
    assert window.model.selection.face is not None


def test_opening_a_mesh_shows_its_faces_as_ground_truth(qtbot, window):
    """Issue 7, item 3: a mesh file's vertices are the sample, its faces the truth layer,
    and the Information dock compares M_S with them."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"
    assert window.open_file(path, 2)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    m = window.model
    assert m.rec is not None and m.rec.n == 502, window.last_error
    truth = m.truth
    assert truth.faces.shape == (1000, 3) and truth.comparison is not None
    layer = m.layers["truth"]
    assert layer.visible and layer.count == 1000
    assert window.view.adapters["truth"].part.n_cells == 1000
    box = window.info_panel
    assert box.truth_box.isVisible()
    text = box.truth_text.text()
    c = truth.comparison
    assert "1,000" in text and f"{c.recovered:,} ({100 * c.recovered_share:.1f} %)" in text
    assert "genus 0" in text  # the knight mesh is a closed genus-0 surface
    # a re-extraction with another angle compares again
    old = c
    window.run_panel.reconstruct_requested.emit(2, "cocone", np.radians(30.0), True)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert m.truth.comparison is not None and m.truth.comparison is not old
    assert m.truth.comparison.result_faces == m.rec.topology.n_simplices
