"""Compare in the window (dialog, layer, counts, list click) and File ▸ Export animation (GIF, cancel)."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import on_next_dialog, wait_idle

from crustview.core import reextract
from crustview.core.analysis.complexdiff import diff_complexes


@pytest.fixture()
def torus(qtbot, window):
    assert window.load_builtin("torus", n=700)
    wait_idle(qtbot, window)
    return window


def test_compare_with_another_test_through_the_dialog_and_frame_a_listed_simplex(qtbot, torus):
    from crustview.qt.compare_panel import CompareDialog

    win = torus
    rec = win.model.rec
    panel = win.info_panel.compare

    def literal(dlg):
        dlg.radio["run"].setChecked(True)
        dlg.test.setCurrentText("literal")
        dlg.theta.setValue(15.0)
        dlg.accept()

    answered = on_next_dialog(literal, CompareDialog)
    next(a for a in win.actions() if a.text() == "Co&mpare with…").trigger()
    assert answered
    qtbot.waitUntil(lambda: not panel.runner.busy, timeout=30_000)
    c = win.model.comparison
    assert c is not None, panel.label.text()
    # the same numbers as an independent run of the core
    other = reextract(rec, "literal", np.radians(15.0), prune_boundary=rec.prune_boundary, mode=rec.mode)
    ref = diff_complexes(rec.points, rec.manifold, other.points, other.manifold, 2)
    assert (len(c.diff.both), len(c.diff.only_a), len(c.diff.only_b)) == (
        len(ref.both),
        len(ref.only_a),
        len(ref.only_b),
    )
    assert len(ref.only_a) + len(ref.only_b) > 0
    text = panel.label.text()
    assert f"{len(ref.only_a):,} only in A" in text and f"{len(ref.only_b):,} only in B" in text
    assert f"Hausdorff distance {c.diff.hausdorff.words()} (" in text  # as `crustview compare` says it
    listed = [panel.list.item(i) for i in range(panel.list.count()) if panel.list.item(i).data(0x0100)]
    assert len(listed) == min(len(ref.only_a), 250) + min(len(ref.only_b), 250)
    # the layer: three parts with both / only A / only B triangles
    parts = win.view.adapters["compare"].parts
    assert [p.n_cells for p in parts] == [len(ref.both), len(ref.only_a), len(ref.only_b)]
    assert win.model.layers["compare"].count == len(ref.only_a) + len(ref.only_b)
    assert any(label.startswith("only in B") for label, _ in win.view.legend_entries())
    # and it is seen: hiding it changes the picture
    win.model.player.last()
    win.view.render()
    on = win.plotter.screenshot(return_img=True)
    win.layers_panel.rows["compare"].visible.click()
    win.view.render()
    off = win.plotter.screenshot(return_img=True)
    win.layers_panel.rows["compare"].visible.click()
    assert int((np.abs(on.astype(int) - off.astype(int)).sum(axis=2) > 30).sum()) > 100

    # a click on a listed simplex frames it: the camera looks at its centroid and it is selected
    item = listed[-1]  # an "only in B" simplex
    assert item.text().startswith("only in B")
    panel.list.itemClicked.emit(item)
    verts = np.asarray(item.data(0x0100))
    centre = win.model.projection.project(rec.points[verts]).mean(axis=0)
    assert np.allclose(win.plotter.camera.focal_point, centre, atol=1e-9)
    assert win.view.clip_plane is not None
    sel = win.model.selection.simplex
    assert sel is not None and sorted(rec.candidates.faces[sel]) == sorted(verts)

    # a new result drops the comparison and its layer
    assert win.load_builtin("circle", n=60)
    wait_idle(qtbot, win)
    assert win.model.comparison is None and win.view.adapters["compare"].shown_cells() == 0


def test_compare_with_a_saved_result_and_a_mesh_file_and_a_bad_file(qtbot, torus, tmp_path):
    win = torus
    rec = win.model.rec
    panel = win.info_panel.compare
    npz = tmp_path / "same.npz"
    assert win.save_result(str(npz))
    assert panel.start({"kind": "result", "path": str(npz)})
    qtbot.waitUntil(lambda: not panel.runner.busy, timeout=30_000)
    d = win.model.comparison.diff
    assert (len(d.both), len(d.only_a), len(d.only_b)) == (len(rec.manifold), 0, 0)

    # a mesh with 5 of M_S's triangles left out: exactly those are "only in A"
    off = tmp_path / "part.off"
    faces = np.asarray(rec.manifold)[5:]
    with open(off, "w") as f:
        f.write(f"OFF\n{rec.n} {len(faces)} 0\n")
        np.savetxt(f, rec.points)
        np.savetxt(f, np.c_[np.full(len(faces), 3), faces], fmt="%d")
    assert panel.start({"kind": "mesh", "path": str(off)})
    qtbot.waitUntil(lambda: not panel.runner.busy, timeout=30_000)
    d = win.model.comparison.diff
    assert len(d.only_a) == 5 and len(d.only_b) == 0
    assert {tuple(r) for r in d.only_a} == {tuple(sorted(r)) for r in np.asarray(rec.manifold)[:5]}

    pts = tmp_path / "points.xyz"
    np.savetxt(pts, rec.points)
    assert panel.start({"kind": "mesh", "path": str(pts)})
    qtbot.waitUntil(lambda: not panel.runner.busy, timeout=30_000)
    assert "has no faces" in panel.label.text() and win.model.comparison is not None  # the last one stays
    assert panel.button.isEnabled()


def test_export_dialog_writes_a_gif_with_the_window_layers_and_camera(qtbot, torus, tmp_path):
    import imageio.v3 as iio

    from crustview.qt.export import ExportDialog

    win = torus
    win.model.layers["manifold"].color = "#ff0000"
    win.model.layers["manifold"].colorby = "none"
    win.model.layers["normals"].visible = False
    win.model.layers["points"].visible = False
    win.plotter.camera.azimuth = 30.0
    out = tmp_path / "replay.gif"

    def fill(dlg):
        dlg.format.setCurrentText("GIF")
        dlg.path.setText(str(out))
        dlg.frames.setValue(4)
        dlg.width_.setValue(200)
        dlg.height_.setValue(160)
        assert "4 frames" in dlg.note.text()
        dlg.accept()

    answered = on_next_dialog(fill, ExportDialog)
    next(a for a in win.actions() if a.text() == "E&xport animation…").trigger()
    assert answered and win.export is not None
    job = win.export
    assert np.allclose(job.scene.plotter.camera.position, win.plotter.camera.position)
    qtbot.waitUntil(lambda: job.done, timeout=30_000)
    frames = iio.imread(out, index=None)
    assert frames.shape == (4, 160, 200, 3)
    band = job.scene.band
    assert np.abs(frames[0, :band].astype(int) - frames[-1, :band].astype(int)).sum() > 0  # captions differ
    view = frames[-1, band:].astype(int)
    red = (view[..., 0] > 120) & (view[..., 1] < 70) & (view[..., 2] < 70)
    assert red.mean() > 0.02  # M_S in the window colour
    assert "Exported 4 frames" in win.statusBar().currentMessage()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["replay.gif"]  # no temporary file left


def test_cancelling_an_export_stops_it_and_leaves_no_file(qtbot, torus, tmp_path):
    from crustview.qt.export import ExportOptions

    win = torus
    out = tmp_path / "long.mp4"
    job = win.export_animation(ExportOptions(str(out), "tour", frames=400, size=(160, 120), fps=12))
    qtbot.waitUntil(lambda: job.writer.count >= 3, timeout=30_000)
    assert job.writer.writing and job.dialog.isVisible()  # an unnamed temporary file: nothing in tmp_path yet
    from PySide6.QtWidgets import QPushButton

    button = job.dialog.findChild(QPushButton)
    assert button.text() == "Cancel"
    button.click()  # the progress dialog's Cancel
    assert job.done and job.cancelled
    count = job.writer.count
    qtbot.wait(200)
    assert job.writer.count == count < 400  # no frame after the cancel
    assert not out.exists() and list(tmp_path.iterdir()) == []
    assert "cancelled" in win.statusBar().currentMessage()
    assert win.export_animation(ExportOptions(str(tmp_path / "x.avi"))) is None
    assert "use .gif, .mp4 or a folder" in win.last_error
