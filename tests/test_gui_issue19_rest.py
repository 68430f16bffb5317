"""Issue 19's rest: readable holes, docks that fit at 1024 x 700, the camera, the d prompt, progress."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pytestqt")


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
    assert (
        a.label_actor.GetVisibility() and a.labels[0] == f"hole 1: {big.size} rim edges, {big.span:.1f} spacings across"
    )
    assert a.label_points.n_points == min(5, len(a.rims))
    layer.visible = False
    qtbot.wait(20)
    assert not a.label_actor.GetVisibility() and not patch.actor.GetVisibility()
