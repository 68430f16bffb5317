"""Opening a mesh in the window: the d question suggests the d of its faces where its vertices alone say another."""

from __future__ import annotations


def test_the_d_question_on_a_cad_mesh_suggests_its_faces_d(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QInputDialog, QLabel

    from tests.gui_helpers import on_next_dialog
    from tests.test_dimension_faces import _rings_cylinder

    pts, tris = _rings_cylinder()
    path = tmp_path / "cylinder.off"
    rows = ["OFF", f"{len(pts)} {len(tris)} 0"] + [" ".join(f"{c:.17g}" for c in p) for p in pts]
    path.write_text("\n".join(rows + [f"3 {a} {b} {c}" for a, b, c in tris]) + "\n")
    seen: list = []

    def look(dlg):
        seen.append((dlg.intValue(), dlg.findChild(QLabel).text()))
        dlg.reject()

    done = on_next_dialog(look, QInputDialog)
    assert not window.open_file(path)  # cancelled: no d
    assert done
    d, text = seen[0]
    text = " ".join(text.split())  # the dialog wraps its text into lines
    assert d == 2 and "Suggested d = 2" in text and "taken from the file's faces" in text
