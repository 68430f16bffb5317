"""Picking what is seen, in the real window under Xvfb: depth, the step overlay, the step table."""

import numpy as np
from gui_helpers import display_xy, load
from PySide6.QtCore import Qt


def ray_hits(origin, target, tris):
    """Parameters t in (0, 1) where the segment origin -> target crosses triangles ``tris`` (m, 3, 3)."""
    d = target - origin
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - tris[:, 0]
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < 1)
    return np.flatnonzero(hit), t


def test_a_click_on_a_hidden_sample_selects_the_triangle_in_front(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    m.player.last()  # the closed torus, opaque
    m.layers["step"].visible = False
    window.plotter.camera.zoom(2.0)  # samples further apart on screen
    window.view.render()
    cam = np.array(window.plotter.camera.position)
    proj = m.projection.project(rec.points)
    ext = rec.extraction
    alive = ext.simplices[ext.alive(ext.n_steps)]
    tris = proj[alive]
    spacing = float(np.median(m.spacing))
    screen = np.array([display_xy(window, p) for p in proj])
    depth = np.linalg.norm(proj - cam, axis=1)
    # samples far from the camera whose line of sight crosses M_S well in front of them,
    # with no nearer sample within the pick tolerance (that one is seen, and rightly picked)
    from crustview.render.picking import POINT_TOLERANCE

    w, h = window.plotter.render_window.GetSize()
    near_px = POINT_TOLERANCE * np.hypot(w, h) + 3
    hidden = None
    for i in np.argsort(-depth)[:600]:
        nearer = depth < depth[i] - 4 * spacing
        if np.min(np.linalg.norm(screen[nearer] - screen[i], axis=1)) < near_px:
            continue
        idx, t = ray_hits(cam, proj[i], tris)
        idx = [j for j in idx if i not in alive[j]]
        dist = depth[i]
        if idx and min(t[j] for j in idx) * dist < dist - 4 * spacing:
            hidden = int(i)
            front = {int(j) for j in idx if t[j] * dist < dist - 4 * spacing}
            break
    assert hidden is not None
    x, y = display_xy(window, proj[hidden])
    got = window.pick_at(int(round(x)), int(round(y)))
    assert got is not None and got[0] == "simplex", (got, hidden)
    # the selected triangle is one of those between the camera and the hidden sample
    picked = tuple(sorted(rec.candidates.faces[got[1]]))
    assert picked in {tuple(sorted(alive[j])) for j in front}
    assert m.selection.simplex == got[1] and m.selection.sample is None


def test_a_visible_sample_still_wins_over_its_own_triangles(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    m.player.last()
    cam = np.array(window.plotter.camera.position)
    proj = m.projection.project(rec.points)
    i = int(np.argmin(np.linalg.norm(proj - cam, axis=1)))
    x, y = display_xy(window, proj[i])
    got = window.pick_at(int(round(x)), int(round(y)))
    assert got is not None and got[0] == "sample"
    assert np.linalg.norm(rec.points[got[1]] - rec.points[i]) < 3 * m.spacing[i]


def test_a_click_on_the_steps_removed_triangle_selects_it_even_inside_m_s(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    ext = rec.extraction
    # a resolve step: the removed triangles lie inside M_S, drawn over it by the overlay
    j = next(s.index for s in ext.steps if s.removed and s.kept)
    m.player.set_step(j + 1)
    step = ext.steps[j]
    window.view.render()
    proj = m.projection.project(rec.points)
    own = {m.candidate_row(int(e)) for e in list(step.kept) + list(step.removed)}
    hits = []
    for e in step.removed:
        c = proj[ext.simplices[e]]
        for w in ((0.6, 0.2, 0.2), (0.2, 0.6, 0.2), (0.2, 0.2, 0.6), (1 / 3, 1 / 3, 1 / 3)):
            x, y = display_xy(window, np.asarray(w) @ c)
            got = window.pick_at(int(round(x)), int(round(y)))
            hits.append(got)
    assert all(g is not None and g[0] in ("simplex", "face") for g in hits), hits
    rows = {g[1] for g in hits if g[0] == "simplex"}
    assert rows and rows <= own
    assert rows & {m.candidate_row(int(e)) for e in step.removed}


def test_clicking_kept_and_removed_cells_of_the_step_table_selects_those_simplices(qtbot, window):
    rec = load(qtbot, window)
    m = window.model
    ext = rec.extraction
    j = next(s.index for s in ext.steps if len(s.removed) and len(s.kept) == 2)
    step = ext.steps[j]
    panel = window.steps_panel
    table = panel.table
    m.player.set_step(j + 1)
    qtbot.wait(20)

    def click(col):
        idx = panel.log.index(j, col)
        table.scrollTo(idx)
        rect = table.visualRect(idx)
        qtbot.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())

    click(4)  # removed
    assert m.selection.simplex == m.candidate_row(step.removed[0])
    click(3)  # kept: first of the pair, then the second
    assert m.selection.simplex == m.candidate_row(step.kept[0])
    click(3)
    assert m.selection.simplex == m.candidate_row(step.kept[1])
    click(2)  # tau
    assert m.selection.face == tuple(sorted(step.tau))
    assert m.player.position == j + 1
