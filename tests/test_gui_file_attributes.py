"""A scanner-style PLY (plyfile: normals, colours, intensity) in the real window: its colours, the
normal-angle colouring and histogram, the d suggestion, and the question before saving over the input."""

import numpy as np
from gui_helpers import on_next_dialog, wait_idle

N = 1500


def _scan(path, flip_top=False):
    """A torus with true normals (optionally turned 90 degrees on the top half), red on top, blue below."""
    from plyfile import PlyData, PlyElement

    from crustview.core.samples.manifolds import get_manifold

    pts = get_manifold("torus").sample(N, seed=0).points
    r = np.hypot(pts[:, 0], pts[:, 1])
    centre = np.column_stack([pts[:, 0] / r, pts[:, 1] / r, np.zeros(N)]) * 0.5 * (r.max() + r.min())
    normals = pts - centre
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    top = pts[:, 2] > 0
    if flip_top:  # a tangent direction instead of the normal: 90 degrees from AN_s
        t = np.cross(normals[top], [0.0, 0.0, 1.0])
        normals[top] = t / np.linalg.norm(t, axis=1, keepdims=True)
    dt = [(c, "f4") for c in ("x", "y", "z", "nx", "ny", "nz")] + [(c, "u1") for c in ("red", "green", "blue")]
    vert = np.zeros(N, dtype=dt + [("intensity", "f4")])
    for i, c in enumerate("xyz"):
        vert[c] = pts[:, i]
    for i, c in enumerate(("nx", "ny", "nz")):
        vert[c] = normals[:, i]
    vert["red"] = np.where(top, 230, 20)
    vert["green"] = 20
    vert["blue"] = np.where(top, 20, 230)
    vert["intensity"] = np.arange(N) % 50
    PlyData([PlyElement.describe(vert, "vertex")]).write(str(path))
    return top


def _colour_share(img, rgb, tol=60):
    diff = np.abs(img[..., :3].astype(int) - np.array(rgb)).sum(axis=2)
    return float((diff < tol).mean())


def test_a_scan_with_colours_and_normals_is_shown_in_its_colours_and_by_normal_angle(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QInputDialog

    path = tmp_path / "scan.ply"
    top = _scan(path, flip_top=True)
    asked = []

    def answer(dlg):
        assert isinstance(dlg, QInputDialog)
        asked.append((dlg.intValue(), dlg.labelText()))
        dlg.accept()

    on_next_dialog(answer)
    assert window.open_file(path)
    wait_idle(qtbot, window)
    said = " ".join(asked[0][1].split()) if asked else ""  # the dialog wraps its text into lines
    assert asked and asked[0][0] == 2 and "local PCA" in said and "confidence" in said
    points = window.model.layers["points"]
    assert points.colorby == "file colours"
    assert {"file colours", "file intensity", "file normal angle"} <= set(window.model.colorings("points"))
    points.visible = True
    window.model.layers["manifold"].visible = False
    qtbot.wait(100)
    window.view.render()
    img = window.plotter.screenshot(return_img=True)
    assert window.save_screenshot(str(tmp_path / "colours.png"))
    assert _colour_share(img, (230, 20, 20)) > 0.002 and _colour_share(img, (20, 20, 230)) > 0.002
    legend = [label for label, _ in window.view.legend_entries()]
    assert not any("not available" in label for label in legend)

    panel = window.info_panel.normal_angles
    assert not panel.isHidden()
    counts = panel.histogram.counts
    assert counts.sum() == N and counts[:2].sum() >= 0.9 * (~top).sum() and counts[-2:].sum() >= 0.9 * top.sum()
    assert "median" in panel.label.text()
    panel.color_button.click()
    qtbot.wait(100)
    assert points.colorby == "file normal angle"
    adapter = window.view.adapters["points"]
    assert adapter.scalar_title == "file normal vs AN_s (deg)"
    window.view.render()
    angled = window.plotter.screenshot(return_img=True)
    assert window.save_screenshot(str(tmp_path / "normal-angle.png"))
    assert np.abs(angled.astype(int) - img.astype(int)).sum() > 0

    # saving the result over the input asks first; No keeps the input as it was
    from PySide6.QtWidgets import QMessageBox

    before = path.read_bytes()
    on_next_dialog(lambda dlg: dlg.button(QMessageBox.StandardButton.No).click(), QMessageBox)
    assert not window.save_result(str(path))
    assert path.read_bytes() == before
    on_next_dialog(lambda dlg: dlg.button(QMessageBox.StandardButton.Yes).click(), QMessageBox)
    assert window.save_result(str(path))
    assert path.read_bytes() != before
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".ply") == ["scan.ply"]
