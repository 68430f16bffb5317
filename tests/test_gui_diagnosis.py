"""The window says why: epsilon colouring and histogram, holes of T_S, cascades, extraction mode."""

from __future__ import annotations

from pathlib import Path

import numpy as np

KNIGHT = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"


def knight_points() -> np.ndarray:
    import meshio

    return np.asarray(meshio.read(KNIGHT).points, dtype=float)


def run(qtbot, window, pts, mode):
    window.run_panel.set_mode(mode)
    assert window.start_reconstruction(pts, 2, source="knight")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    assert window.model.rec is not None, window.last_error
    return window.model.rec


def test_epsilon_colouring_marks_the_paper_bounds_and_the_histogram_counts_every_sample(qtbot, window):
    from PySide6.QtGui import QColor

    from crustview.core.analysis.quality import sampling_quality

    pts = knight_points()
    rec = run(qtbot, window, pts, "robust")
    points = window.model.layers["points"]
    points.colorby = "epsilon"
    a = window.view.adapters["points"]
    q = sampling_quality(rec)  # recomputed here, independently of the window's cache
    values = np.asarray(a.part.mesh.point_data["values"])
    assert np.allclose(values, q.epsilon, equal_nan=True)
    lut = a.part.mapper.lookup_table
    assert 0.25 in [round(float(k), 6) for k in lut.annotations]  # the bound is a labelled tick
    # colours change at the bound: just below is not the colour just above
    below, above = (np.array(lut.map_value(v)[:3]) for v in (0.24, 0.26))
    assert np.abs(below - above).sum() > 0.3
    assert any("estimated epsilon" in t for t in window.view._bars)
    hist = window.info_panel.diagnosis.histogram
    assert hist.counts.sum() == int(np.isfinite(q.epsilon).sum()) == rec.n
    assert hist.counts[-1] == int((q.epsilon >= hist.edges[-1]).sum())
    beyond = int(q.beyond(0.25).sum())
    assert f"<b>{beyond:,}</b> of {rec.n:,}" in window.info_panel.diagnosis.quality_label.text()
    # the bound is drawn as a dashed line where the bars change colour: at the left edge of the bar that
    # begins at 0.25, dark pixels down most of the plot, and none in a column halfway between two bounds
    assert set(q.thresholds.values()) == {0.25}
    start = int(np.argmin(np.abs(hist.edges - 0.25)))
    assert abs(hist.edges[start] - 0.25) < 1e-12  # 0.25 is a bar edge (the bars run to 4 times the bound)
    x = hist.x_of(0.25)
    assert abs(hist.bar_rects()[start].left() - 0.5 - x) < 1e-9
    hist.resize(max(hist.width(), 300), max(hist.height(), 140))
    img = hist.grab().toImage()
    top, bottom = 14 + 13, hist.height() - 17  # below the one label line, above the axis

    def dark(col: int) -> int:
        return sum(QColor(img.pixel(col, y)).lightness() < 60 for y in range(top, bottom))

    assert dark(int(x)) >= 0.4 * (bottom - top), (dark(int(x)), bottom - top)  # dashes: about half the column
    assert dark(int(hist.x_of(0.6))) == 0


def test_holes_layer_counts_the_holes_of_t_s_as_its_legend_does(qtbot, window):
    """The layer's count is the number of holes, the legend's number: a new user read the Layers dock's count
    of hole edges (session 50: 3,992) beside the legend's count of holes as two answers to one question."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from crustview.scene import geometry as geo

    rec = run(qtbot, window, knight_points(), "paper")
    layer = window.model.layers["holes"]
    # independent counts: (d-1)-faces of T_S (the test's candidates at theta) in one simplex, and the groups
    # of them that share a sample
    faces, inc = geo.facets(rec.candidates.select(rec.test, rec.theta))
    edges = faces[np.bincount(inc.ravel(), minlength=len(faces)) == 1]
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(rec.n, rec.n))
    groups = connected_components(graph, directed=False)[1]
    holes = len(np.unique(groups[edges[:, 0]]))
    assert len(edges) > holes > 1 and layer.count == holes
    layer.visible = True
    assert any(label.startswith(f"Holes of T_S: {holes:,} ") for label, _ in window.view.legend_entries())
    assert window.view.adapters["holes"].part.mesh.n_lines == len(edges)  # one thick line per hole edge
    qtbot.waitUntil(lambda: window.layers_panel.rows["holes"].count.text() == f"{holes:,}", timeout=5000)
    assert "holes" in window.layers_panel.rows["holes"].count.toolTip()
    # the robust run's note counts the faces on holes, not holes (a review: "(244 holes in T_S)" beside 44)
    from crustview.core import reconstruct

    robust = reconstruct(knight_points(), 2)  # the robust extraction, which notes why the paper's was abandoned
    (note,) = [m for m in robust.topology.messages if "lost its last simplex" in m]
    assert f"({len(edges):,} edges on holes of T_S)" in note


def test_clicking_a_cascade_frames_its_origin_and_highlights_every_simplex_it_removed(qtbot, window):
    from PySide6.QtCore import Qt

    rec = run(qtbot, window, knight_points(), "paper")
    panel = window.info_panel.diagnosis
    assert panel.cascades.count() > 0 and not panel.to_paper.isVisible()
    ext = rec.extraction
    first = panel.list[0]
    assert panel.cascades.item(0).text().startswith(("hole at", "resolve at", "sharp face at"))
    assert f"{first.removed:,} simplices" in panel.cascades.item(0).text()
    # every step in the cascade follows its cause chain back to the origin
    for i in first.steps:
        j = int(i)
        while ext.steps[j].cause >= 0:
            j = ext.steps[j].cause
        assert j == first.origin
    cam_before = np.array(window.plotter.camera.position)
    rect = panel.cascades.visualItemRect(panel.cascades.item(0))
    qtbot.mouseClick(panel.cascades.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())
    assert window.model.cascade is first
    removed = sum(len(ext.steps[int(i)].removed) for i in first.steps)
    assert window.model.layers["cascade"].count == removed == first.removed
    cascade = window.view.adapters["cascade"]
    assert cascade.part.mesh.n_cells == removed and cascade.parts[0].actor in window.view.top_renderer.GetActors()
    assert not np.allclose(np.array(window.plotter.camera.position), cam_before)  # framed
    # the origin face is on screen, near the centre of the view
    p = window.model.projection.project(rec.points[list(first.tau)]).mean(axis=0)
    ren = window.plotter.renderer
    ren.SetWorldPoint(*p, 1.0)
    ren.WorldToDisplay()
    x, y, _ = ren.GetDisplayPoint()
    w, h = ren.GetSize()
    assert 0.2 * w < x < 0.8 * w and 0.2 * h < y < 0.8 * h


def test_extraction_mode_option_switches_the_verdict_and_back(qtbot, window):
    rec = run(qtbot, window, knight_points(), "robust")
    panel, info = window.run_panel, window.info_panel
    assert rec.mode == "robust" and rec.topology.unused_samples == 0  # closed through every sample
    assert "robust extraction" in info.banner.text() and "abandoned" in info.banner.text()
    assert "Delaunay by CGAL Delaunay_triangulation_3 (crustview extension)" in info.timings.text()
    assert info.diagnosis.to_paper.isVisible() and info.diagnosis.cascades.count() == 0
    words = info.banner.text()

    info.diagnosis.to_paper.click()  # "look at the paper's run": re-extracts with Algorithm 3
    qtbot.waitUntil(lambda: window.model.rec is not rec and not window.runner.busy, timeout=60_000)
    paper = window.model.rec
    assert paper.mode == "paper" and panel.mode == "paper"
    assert paper.delaunay_simplices is rec.delaunay_simplices  # only Algorithm 3 ran again
    assert paper.topology.closed_manifold and paper.topology.unused_samples > 0  # a tiny closed blob
    assert "the paper's Algorithm 3" in info.banner.text() and info.banner.text() != words
    assert "closed but skips" in info.banner.text() and "paper" in panel.progress.format()
    assert info.diagnosis.cascades.count() > 0 and panel.prune.isEnabled()

    panel.set_mode("robust")
    qtbot.waitUntil(lambda: window.model.rec is not paper and not window.runner.busy, timeout=60_000)
    back = window.model.rec
    assert back.mode == "robust" and info.banner.text() == words
    assert len(back.manifold) == len(rec.manifold) and not panel.prune.isEnabled()


def test_a_robust_run_whose_paper_loop_succeeded_does_not_say_the_loop_was_abandoned(qtbot, window):
    # S^3 in R^4: T_S is already a closed manifold, so the robust run is the
    # paper's own (empty) log; the cascade box must say so, not that the
    # paper's loop was abandoned and M_S grown
    from crustview.core.samples.manifolds import get_manifold

    pts = get_manifold("s3").sample(600, seed=0).points
    window.run_panel.set_mode("robust")
    assert window.start_reconstruction(pts, 3, source="s3")
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    rec = window.model.rec
    assert rec is not None and rec.mode == "robust" and rec.extraction.added_at is None
    info = window.info_panel
    assert "extension was not needed" in info.banner.text()
    label = info.diagnosis.cascade_label.text()
    assert "abandoned" not in label and "grown" not in label
    assert not info.diagnosis.to_paper.isVisible()


def grown_points() -> np.ndarray:
    """A sample whose robust result is grown (the growing path is the only one off R^3): the flat
    Klein bottle in R^4 with noise of 1 % of its size, where the paper's loop gives up."""
    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold("flat-klein")
    pts = m.sample(m.default_n, seed=1).points
    return pts + np.random.default_rng(1).normal(scale=0.01 * np.ptp(pts, axis=0).max(), size=pts.shape)


def test_step_overlay_shows_added_simplices_and_removed_so_far_ignores_not_yet_added(qtbot, window):
    rec = run(qtbot, window, grown_points(), "robust")
    ext = rec.extraction
    grow = next(s for s in ext.steps if s.rule == "grow")
    player = window.model.player
    player.set_step(grow.index + 1)
    step = window.view.adapters["step"]
    kinds = np.asarray(step.part.mesh.cell_data["values"])
    assert (kinds == 3).sum() == len(grow.added) and not (kinds == 2).any()
    assert ("added now (robust extension)", "#1f5fd6") in window.view.legend_entries()
    row = window.steps_panel.log.data(window.steps_panel.log.index(grow.index, 5))
    assert row and str(grow.added[0]) in row
    core = ext.steps[0]  # the manifold core of T_S, added in one step
    assert core.rule == "seed-core" and len(core.added) > 4
    assert window.steps_panel.log.data(window.steps_panel.log.index(0, 5)) == f"{len(core.added)} simplices"
    # at step 0 M_S is T_S only (nothing added yet) and nothing counts as removed
    player.set_step(0)
    assert window.model.layers["manifold"].count == int(ext.added_at.__eq__(0).sum())
    window.model.layers["removed"].visible = True
    assert window.model.layers["removed"].count == 0
    player.last()
    assert window.model.layers["removed"].count == int((ext.removed_at < ext.n_steps).sum())
