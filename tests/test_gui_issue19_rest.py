"""Issue 19's rest: readable holes, docks that fit at 1024 x 700, the camera, the d prompt, progress."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

KNIGHT = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"


def knight_points() -> np.ndarray:
    import meshio

    return np.asarray(meshio.read(KNIGHT).points, dtype=float)


def run(qtbot, window, pts, d: int = 2, mode: str = "paper"):
    window.run_panel.set_mode(mode)
    assert window.start_reconstruction(pts, d, source="knight")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.rec is not None, window.last_error
    qtbot.wait(50)
    return window.model.rec


# ---------------------------------------------------------------- 1. readable holes
def test_hole_rims_group_faces_that_share_a_sample_largest_first():
    from crustview.scene.holes import hole_rims, holes_summary, rim_patches

    # a square loop 0-1-2-3, a triangle loop 4-5-6 and a lone edge 7-8, on a unit grid
    faces = np.array([[0, 1], [4, 5], [1, 2], [7, 8], [2, 3], [5, 6], [3, 0], [6, 4]])
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [5, 0], [6, 0], [5, 1], [9, 0], [9, 3]], dtype=float)
    spacing = np.full(len(pts), 0.5)
    rims = hole_rims(faces, pts, spacing)
    assert [r.size for r in rims] == [4, 3, 1]
    assert list(rims[0].samples) == [0, 1, 2, 3] and list(rims[2].samples) == [7, 8]
    assert rims[0].span == pytest.approx(np.sqrt(2) / 0.5)  # the square's diagonal in spacings
    assert rims[2].span == pytest.approx(6.0)
    assert np.allclose(rims[0].centre, [0.5, 0.5])
    centres, tris = rim_patches(rims, len(pts))
    assert len(centres) == 2 and len(tris) == 7  # the lone edge has no patch
    assert set(tris[:4, 0]) == {9} and set(tris[4:, 0]) == {10}
    assert holes_summary(rims, 2) == "Holes of T_S: 3 (largest 4 rim edges, 2.8 spacings across)"


def test_holes_are_drawn_as_rims_with_a_faint_patch_and_their_size(qtbot, window):
    from scipy.spatial.distance import pdist

    from crustview.scene import geometry as geo

    rec = run(qtbot, window, knight_points())
    layer = window.model.layers["holes"]
    layer.visible = True
    qtbot.wait(50)
    a = window.view.adapters["holes"]
    # independently: the faces of T_S in one simplex
    faces, inc = geo.facets(rec.candidates.select(rec.test, rec.theta))
    hole = faces[np.bincount(inc.ravel(), minlength=len(faces)) == 1]
    assert a.part.mesh.n_lines == len(hole) > 0  # every rim edge still drawn
    assert sum(r.size for r in a.rims) == len(hole)
    big = a.rims[0]
    # the largest rim: hole faces, and no other hole face touches its samples
    rows = {tuple(f) for f in hole}
    assert all(tuple(f) in rows for f in big.faces)
    others = hole[~np.isin(hole, big.samples).any(axis=1)]
    assert len(others) == len(hole) - big.size
    assert big.size >= 20 and big.size == max(r.size for r in a.rims)
    sp = float(np.median(geo.local_spacing(rec.points)[big.samples]))
    assert big.span == pytest.approx(pdist(rec.points[big.samples]).max() / sp)
    # the patch: one faint triangle per rim edge of every rim of 3 or more edges
    patch = a.parts[1]
    assert patch.mesh.n_cells == sum(r.size for r in a.rims if r.size >= 3) >= big.size
    assert patch.actor.GetVisibility() and patch.actor.prop.opacity < 0.5
    # its size in the legend and as a label in the view
    line = next(t for t, _ in window.view.legend_entries() if t.startswith("Holes of T_S"))
    assert f"Holes of T_S: {len(a.rims)} (largest {big.size} rim edges, {big.span:.1f} spacings across)" == line
    assert a.label_actor.GetVisibility()
    assert a.labels[0] == f"hole 1: {big.size} edges, {big.span:.0f} spacings"
    # up to five labels, the largest hole's first, none over a bigger one's on the screen
    from crustview.render.fitting import display_points

    window.view.render()
    n = a.label_points.n_points
    assert 1 <= n <= min(5, len(a.rims)) and a.placed_labels()[0].startswith("hole 1: ")
    xy = display_points(window.plotter.renderer, np.asarray(a.label_points.points))
    half = np.array([3.6 * len(t) + 4 for t in a.placed_labels()])
    for i in range(n):
        for j in range(i + 1, n):
            assert abs(xy[i, 0] - xy[j, 0]) >= half[i] + half[j] or abs(xy[i, 1] - xy[j, 1]) >= 20
    layer.visible = False
    qtbot.wait(20)
    assert not a.label_actor.GetVisibility() and not patch.actor.GetVisibility()


# ---------------------------------------------------------------- 2. docks that fit at 1024 x 700
def _settle(qtbot, window, w: int = 1024, h: int = 700) -> None:
    window.resize(w, h)
    qtbot.wait(200)  # the tabbed column is sized again once the layout has settled
    window.layout().activate()


def test_at_1024_by_700_no_dock_scrolls_sideways_and_options_say_their_value(qtbot, window):
    from PySide6.QtWidgets import QComboBox, QScrollArea

    from tests.gui_helpers import load

    load(qtbot, window, "flat-klein")  # a built-in: the Theorems box is shown too
    _settle(qtbot, window)
    assert window.compact
    for name, dock in window.docks.items():
        dock.raise_()
        qtbot.wait(50)
        area = dock.widget()
        if not isinstance(area, QScrollArea):
            continue
        body = area.widget()
        # the contents fit the dock's width: nothing to scroll to, nothing cut at the right edge
        assert body.minimumSizeHint().width() <= area.viewport().width(), name
        assert area.horizontalScrollBar().maximum() == 0, name
    panel = window.layers_panel
    for row in panel.rows.values():
        for w in (row.visible, row.count, row.opacity, row.size, row.extra):
            if w is not None:  # every widget of the row lies inside the visible part of the panel
                right = w.mapTo(panel.viewport(), w.rect().topRight()).x()
                assert right <= panel.viewport().width(), (row.layer.name, type(w).__name__)
        if isinstance(row.extra, QComboBox):
            assert f"<b>{row.extra.currentText()}</b>" in row.extra.toolTip()
    points = panel.rows["points"].extra
    points.setCurrentText("hidden depth")
    assert window.model.layers["points"].colorby == "hidden depth"
    assert "<b>hidden depth</b>" in points.toolTip()


def test_at_1024_by_700_the_topology_table_shows_every_value_whole(qtbot, window):
    from tests.gui_helpers import load

    load(qtbot, window, "flat-klein")
    _settle(qtbot, window)
    window.docks["info"].raise_()
    qtbot.wait(50)
    t = window.info_panel.topology
    area = window.docks["info"].widget()
    assert t.mapTo(area.widget(), t.rect().topRight()).x() <= area.viewport().width()
    fm = t.fontMetrics()
    assert t.item(0, 2).text() == "Klein bottle"
    for r in range(t.rowCount()):
        for c in range(3):
            item = t.item(r, c)
            if item is None or not item.text():
                continue
            assert fm.horizontalAdvance(item.text()) + 6 <= t.columnWidth(c), (r, c, item.text())
            assert item.text() in item.toolTip()
    assert sum(t.columnWidth(c) for c in range(3)) <= t.viewport().width() + 1


def test_a_thinned_count_takes_two_lines_in_the_narrow_column(qtbot, window):
    window.resize(1024, 700)
    qtbot.wait(200)
    layer = window.model.layers["points"]
    layer.count, layer.total = 60_000, 1_000_000
    row = window.layers_panel.rows["points"]
    assert row.count.text() == "60,000\nof 1,000,000"
    right = row.count.mapTo(window.layers_panel.viewport(), row.count.rect().topRight()).x()
    assert right <= window.layers_panel.viewport().width()


# ---------------------------------------------------------------- 3. the camera
#: An open scan with an amber result: notes and a long legend over the top of the view (the casting
#: served here before at 12 s a run, as its second opinion and resample check both run; the camelhead
#: fails this test as well when the fit ignores the text, at a third of the cost).
SCAN = Path(__file__).resolve().parents[1] / "resources" / "camelhead.off"


def _on_screen(window, pts: np.ndarray) -> np.ndarray:
    from crustview.render.fitting import display_points

    return display_points(window.plotter.renderer, window.model.projection.project(pts))


@pytest.mark.parametrize("size", [(1600, 1000), (1024, 700)])
def test_reset_shows_all_of_a_scan_clear_of_the_legend(qtbot, window, size):
    from crustview.render.fitting import text_block
    from tests.gui_helpers import wait_idle

    _settle(qtbot, window, *size)
    assert window.open_file(SCAN, d=2)
    wait_idle(qtbot, window)
    qtbot.wait(100)
    window.plotter.camera.zoom(2.0)  # wherever the user left it
    window.view.reset_camera()
    window.view.render()
    ren = window.plotter.renderer
    w, h = ren.GetSize()
    xy = _on_screen(window, window.model.rec.points)
    assert (xy[:, 0] >= 0).all() and (xy[:, 0] <= w).all() and (xy[:, 1] >= 0).all() and (xy[:, 1] <= h).all()
    x0, y0, x1, y1 = text_block(window.view.legend.actors, window.view.hud)
    assert y1 - y0 > 100  # notes and 6 or more legend lines: the top of the part would be under them
    under = (xy[:, 0] > x0) & (xy[:, 0] < x1) & (xy[:, 1] > y0) & (xy[:, 1] < y1)
    assert not under.any()
    span = xy.max(axis=0) - xy.min(axis=0)
    assert max(span[0] / w, span[1] / h) > 0.55  # and still big


def test_switching_to_the_stereographic_view_frames_the_new_geometry(qtbot, window):
    from tests.gui_helpers import load

    load(qtbot, window, "clifford-torus")
    window.projection_panel.stereo.setChecked(True)
    qtbot.wait(50)
    assert window.model.projection.stereographic
    rec = window.model.rec
    p3 = window.model.projection.project(rec.points)
    cam = np.asarray(window.plotter.camera.position)
    centre = (p3.min(axis=0) + p3.max(axis=0)) / 2
    # the camera stands outside the new geometry and sees all of it
    assert np.linalg.norm(cam - centre) > np.linalg.norm(p3 - centre, axis=1).max()
    w, h = window.plotter.renderer.GetSize()
    xy = _on_screen(window, rec.points)
    assert (xy >= 0).all() and (xy[:, 0] <= w).all() and (xy[:, 1] <= h).all()
    window.projection_panel.stereo.setChecked(False)  # and back
    qtbot.wait(50)
    xy = _on_screen(window, rec.points)
    span = xy.max(axis=0) - xy.min(axis=0)
    assert (xy >= 0).all() and max(span[0] / w, span[1] / h) > 0.5


def test_turning_frame_each_step_off_returns_to_the_full_view(qtbot, window):
    from crustview.render.camera import camera_state
    from tests.gui_helpers import load

    load(qtbot, window, "torus")
    window.view.reset_camera()
    full = camera_state(window.plotter)
    window.model.player.set_step(40)
    window.steps_panel.follow.setChecked(True)
    window.model.player.next()
    qtbot.wait(50)
    framed = camera_state(window.plotter)
    assert not np.allclose(framed["position"], full["position"])
    assert window.view.clip_plane is not None
    window.steps_panel.follow.setChecked(False)
    qtbot.wait(50)
    back = camera_state(window.plotter)
    assert window.view.clip_plane is None
    assert np.allclose(back["position"], full["position"]) and np.allclose(back["focal_point"], full["focal_point"])
    assert np.allclose(back["window_center"], full["window_center"])


# ---------------------------------------------------------------- 4. the d question fits its text
def test_the_d_question_is_as_wide_as_its_text_and_inside_the_screen(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QApplication, QInputDialog, QLabel

    from crustview.core.samples.manifolds import get_manifold
    from tests.gui_helpers import on_next_dialog

    m = get_manifold("torus")
    name = "scan-of-a-cast-part-" + "very-long-name-" * 14 + "end.xyz"  # 234 characters
    path = tmp_path / name
    np.savetxt(path, m.sample(400, seed=1).points)
    seen: list = []

    def look(dlg):
        label = dlg.findChild(QLabel)
        fm = label.fontMetrics()
        lines = label.text().split("\n")
        right = label.mapTo(dlg, label.rect().topLeft()).x() + max(fm.horizontalAdvance(t) for t in lines)
        screen = QApplication.primaryScreen().availableGeometry()
        seen.append((dlg.intValue(), lines, right, dlg.width(), screen.width(), dlg.toolTip()))
        dlg.reject()

    done = on_next_dialog(look, QInputDialog)
    assert not window.open_file(path)  # cancelled: no d
    assert done
    d, lines, right, width, screen, tip = seen[0]
    assert d == 2 and any(t.startswith("Suggested d = 2") for t in lines)
    assert width <= screen  # inside the screen
    assert right + 8 <= width  # every line whole, with a margin before the right edge
    assert "…" in lines[0] and tip == name  # the long name elided, whole in the tooltip


# ---------------------------------------------------------------- 5. progress during a 50,000-point extraction
def test_the_bar_moves_during_the_extraction_of_a_50k_scan(qtbot, window):
    """50,000 samples of a torus with the scanner noise crustview is judged with (0.3 of the median
    spacing): the paper's loop gives up and the robust extraction runs; its bar moves (the window
    showed 0 % to the end on a 50,000-point scan)."""
    from scipy.spatial import cKDTree

    from crustview.core.samples.manifolds import get_manifold
    from tests.gui_helpers import wait_idle

    pts = get_manifold("torus").sample(50_000, seed=1, method="random").points
    h = float(np.median(cKDTree(pts).query(pts, k=2)[0][:, 1]))
    pts = pts + np.random.default_rng(1).normal(scale=0.3 * h, size=pts.shape)
    bar = window.run_panel.progress
    seen: list = []
    # what the bar shows after each report, in the GUI thread
    window.runner.progress.connect(lambda stage, f: seen.append((stage, bar.value(), bar.format())))
    assert window.start_reconstruction(pts, 2, source="noisy torus")
    wait_idle(qtbot, window, timeout=240_000)
    assert window.model.rec.n > 49_000 and window.model.rec.extraction.steps[0].rule != "prune-sharp"
    during = [v for stage, v, fmt in seen if stage == "extraction" and "Algorithm 3" in fmt]
    inside = sorted({v for v in during if 0 < v < bar.maximum()})
    assert len(inside) >= 3, during  # it moves between the robust rules, not 0 % until the end
    assert during == sorted(during)  # and never back


# ---------------------------------------------------------------- 6. found in the new-user trial
def test_progress_is_in_the_status_bar_whatever_tab_is_in_front(qtbot, window):
    import time

    def job(progress, cancel):
        progress("delaunay", 0.0)
        progress("delaunay", 0.4)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 5 and not cancel.is_set():
            time.sleep(0.02)

    window.resize(1024, 700)
    qtbot.wait(200)
    window.docks["steps"].raise_()  # the Run panel (and its bar) is a tab behind
    qtbot.wait(50)
    assert window.run_panel.progress.visibleRegion().isEmpty()
    status = window.status_progress
    assert not status.isVisible()
    assert window.start_job(job, "a job")
    qtbot.waitUntil(lambda: status.bar.value() == 400, timeout=5000)
    assert status.isVisible() and status.bar.format() == window.run_panel.progress.format()
    assert status.bar.format().startswith("Delaunay triangulation") and "Qhull" not in status.bar.format()
    status.cancel.click()  # Cancel from the status bar
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=10_000)
    qtbot.waitUntil(lambda: not status.isVisible(), timeout=2000)


def test_a_mesh_shows_its_faces_with_its_result_not_over_the_last_one_while_it_runs(qtbot, window):
    from tests.gui_helpers import load, wait_idle

    load(qtbot, window, "torus")
    truth = window.model.layers["truth"]
    truth.visible = False
    assert window.open_file(KNIGHT, d=2)
    assert window.runner.busy or window.model.source != "torus"
    if window.runner.busy:  # while the knight runs, the torus is shown without a truth turned on for it
        assert not truth.visible
        assert not any(t.startswith("ground truth") for t, _ in window.view.legend_entries())
    wait_idle(qtbot, window)
    assert truth.visible and window.model.truth is not None
    assert any("the mesh's faces" in t for t, _ in window.view.legend_entries())


def test_the_uncertain_features_legend_says_they_are_of_the_final_result_before_the_last_step(qtbot, window):
    from tests.test_gui_uncertain import _run, two_spheres

    rec = _run(qtbot, window, two_spheres())
    assert rec.uncertain_features

    def line():
        return next(t for t, _ in window.view.legend_entries() if t.startswith("uncertain: "))

    assert not line().endswith("(of the final M_S)")  # at the last step it is this M_S
    window.model.player.first()  # T_S: the loops and rims drawn are not of what is shown
    assert line().endswith("(of the final M_S)")
    window.model.player.last()
    assert not line().endswith("(of the final M_S)")


def test_new_data_shows_its_m_s_even_when_the_last_file_had_it_hidden(qtbot, window):
    from tests.gui_helpers import load

    load(qtbot, window, "torus")
    window.model.layers["manifold"].visible = False  # the user looked at the holes without M_S
    load(qtbot, window, "sphere")
    assert window.model.layers["manifold"].visible
    assert window.view.adapters["manifold"].part.actor.GetVisibility()
    assert window.layers_panel.rows["manifold"].visible.isChecked()
    assert "Shown again: M_S at this step." in window.statusBar().currentMessage()


def test_at_1024_by_700_the_step_table_headers_are_whole(qtbot, window):
    from PySide6.QtCore import Qt

    from tests.gui_helpers import load

    load(qtbot, window, "torus")
    _settle(qtbot, window)
    window.docks["steps"].raise_()
    qtbot.wait(50)
    table = window.steps_panel.table
    header = table.horizontalHeader()
    fm = header.fontMetrics()
    model = table.model()
    for c in range(model.columnCount()):
        text = model.headerData(c, Qt.Orientation.Horizontal)
        assert fm.horizontalAdvance(text) + 8 <= header.sectionSize(c), (c, text, header.sectionSize(c))
    for c in range(model.columnCount()):
        assert model.headerData(c, Qt.Orientation.Horizontal, Qt.ItemDataRole.ToolTipRole)
    assert model.headerData(4, Qt.Orientation.Horizontal) == "rem."
    assert "removed" in model.headerData(4, Qt.Orientation.Horizontal, Qt.ItemDataRole.ToolTipRole)


@pytest.mark.parametrize("name", ["decimated-knight.off", "casting.off"])
def test_at_1024_by_700_a_long_cut_loop_does_not_widen_the_step_table(qtbot, window, name):
    """A new user found the τ column 657 px wide on a noisy casting (a cut-handle loop of many samples): the
    table scrolled sideways and 'rem.' and 'add.' left the view; a second found it 200 px wide on the clean
    casting (loops of 5 samples).  A τ of more vertices than a triangle has is counted ("9 samples"); the
    tooltip still gives every one."""
    from PySide6.QtCore import Qt

    from tests.gui_helpers import wait_idle

    assert window.open_file(KNIGHT.parent / name, d=2)
    wait_idle(qtbot, window, 60_000)
    _settle(qtbot, window)
    window.docks["steps"].raise_()
    ext = window.model.rec.extraction
    (row, step), *_ = [(i, s) for i, s in enumerate(ext.steps) if s.rule == "cut-handle"]
    assert len(step.tau) > 2  # longer than an edge, the (d-1)-face of a surface
    table = window.steps_panel.table
    model = table.model()
    tau = list(model.headerData(c, Qt.Orientation.Horizontal) for c in range(model.columnCount())).index("τ")
    table.scrollTo(model.index(row, tau))
    qtbot.wait(100)
    assert model.data(model.index(row, tau)) == f"{len(step.tau)} samples"
    assert ext.steps[0].rule == "label-cells" and model.data(model.index(0, tau)) == "—"  # no place: no count
    tip = model.data(model.index(row, tau), Qt.ItemDataRole.ToolTipRole)
    assert all(str(int(v)) in tip for v in step.tau)
    assert table.horizontalScrollBar().maximum() == 0  # nothing to scroll sideways
    # the labelled run never has a boundary face: its timeline's legend says 0, not the scale's 1
    assert "boundary faces ≤ 0" in window.steps_panel.timeline.legend_texts()
    header = table.horizontalHeader()
    right = max(header.sectionViewportPosition(c) + header.sectionSize(c) for c in range(model.columnCount()))
    assert right <= table.viewport().width()
    # the simplex lists keep room for a vertex id or two ("(2106)" read "(…" beside a 200 px τ)
    fm = table.fontMetrics()
    for title in ("rem.", "add."):
        c = [model.headerData(i, Qt.Orientation.Horizontal) for i in range(model.columnCount())].index(title)
        assert header.sectionSize(c) >= fm.horizontalAdvance("(26953, …)"), (title, header.sectionSize(c))


def test_a_dense_mesh_opens_with_its_faces_hidden_and_says_so(qtbot, window, monkeypatch):
    from crustview.qt import files
    from tests.gui_helpers import load, wait_idle

    load(qtbot, window, "torus")
    window.model.layers["truth"].visible = True  # shown for the last data
    monkeypatch.setattr(files, "TRUTH_SHOWN_FACES", 100)  # the knight's faces count as dense here
    assert window.open_file(KNIGHT, d=2)
    wait_idle(qtbot, window)
    faces = len(window.model.truth.faces)
    assert faces > 100
    assert not window.model.layers["truth"].visible  # the result is not greyed out by a wireframe
    assert f"The mesh's {faces:,} faces are not drawn" in window.statusBar().currentMessage()


def test_compare_waits_for_a_change_and_the_result_is_scrolled_into_view(qtbot, window):
    from crustview.qt.compare_panel import CompareDialog
    from tests.gui_helpers import load

    rec = load(qtbot, window, "torus", n=700)
    dlg = CompareDialog(window, rec.test, float(rec.theta), rec.mode)
    qtbot.addWidget(dlg)
    dlg.show()
    ok = dlg.buttons.button(dlg.buttons.StandardButton.Ok)
    assert not ok.isEnabled() and dlg.same.isVisible()  # B = the shown run: nothing to compare
    dlg.test.setCurrentText("literal")
    assert ok.isEnabled() and not dlg.same.isVisible()
    dlg.test.setCurrentText(rec.test)
    dlg.mode.setCurrentIndex(dlg.mode.findData("paper" if rec.mode == "robust" else "robust"))
    assert ok.isEnabled()
    dlg.radio["result"].setChecked(True)  # a file: OK once one is named
    assert not ok.isEnabled() and not dlg.same.isVisible()
    dlg.close()
    window.docks["info"].raise_()
    panel = window.info_panel.compare
    area = window.docks["info"].widget()
    area.verticalScrollBar().setValue(0)
    qtbot.wait(50)
    assert panel.visibleRegion().isEmpty()  # below the topology and the histogram
    assert panel.start({"kind": "run", "test": "literal", "theta": float(rec.theta), "mode": rec.mode})
    qtbot.waitUntil(lambda: window.model.comparison is not None, timeout=30_000)
    qtbot.wait(50)
    assert not panel.visibleRegion().isEmpty()


def test_the_raw_points_preview_looks_from_where_the_result_will_be_seen(qtbot, window):
    from crustview.core.samples.manifolds import get_manifold
    from tests.gui_helpers import wait_idle

    def direction():
        cam = window.plotter.camera
        v = np.asarray(cam.position) - np.asarray(cam.focal_point)
        return v / np.linalg.norm(v), np.asarray(cam.up)

    pts = get_manifold("torus").sample(800, seed=3).points
    window.view.show_preview(pts)  # while d is asked and the first run goes
    before, up_before = direction()
    assert window.start_reconstruction(pts, 2, source="torus 800")
    wait_idle(qtbot, window)
    after, up_after = direction()
    assert np.degrees(np.arccos(np.clip(before @ after, -1, 1))) < 1.0  # the view does not turn
    assert np.allclose(up_before, up_after)


def test_a_run_without_kept_pairs_hides_the_empty_kept_and_angle_columns(qtbot, window):
    from crustview.qt.steps_dock import COLUMNS
    from tests.gui_helpers import load

    rec = load(qtbot, window, "torus")
    table = window.steps_panel.table
    kept, angle = COLUMNS.index("kept"), COLUMNS.index("angle")
    assert any(len(st.kept) for st in rec.extraction.steps)  # the paper's resolve steps keep pairs
    assert not table.isColumnHidden(kept) and not table.isColumnHidden(angle)
    assert window.open_file(KNIGHT, d=2)  # the labelling path: cells labelled, no pairs kept
    from tests.gui_helpers import wait_idle

    wait_idle(qtbot, window)
    steps = window.model.rec.extraction.steps
    assert steps and not any(len(st.kept) for st in steps)
    assert table.isColumnHidden(kept) and table.isColumnHidden(angle)


def test_largest_free_rect_avoids_every_block():
    from crustview.render.fitting import largest_free_rect

    # a legend in the upper left and a caption in the lower left of a 600 x 600 view
    legend, caption = (0.0, 420.0, 380.0, 600.0), (0.0, 0.0, 260.0, 40.0)
    x0, y0, x1, y1 = largest_free_rect(600, 600, [legend, caption])
    for b in (legend, caption):
        assert not (x0 < b[2] and b[0] < x1 and y0 < b[3] and b[1] < y1)
    assert (x0, y0, x1, y1) == (0.0, 40.0, 600.0, 420.0)  # below the legend: 380 high, the larger side
    assert largest_free_rect(600, 600, []) == (0.0, 0.0, 600.0, 600.0)
