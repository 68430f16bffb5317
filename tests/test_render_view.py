"""Render adapters against an off-screen pyvista plotter (no Qt)."""

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")

from crustview.render import SceneView  # noqa: E402
from crustview.scene import SceneModel  # noqa: E402


@pytest.fixture()
def scene(torus_run):
    rec, sample = torus_run
    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=(400, 300))
    view = SceneView(model, plotter)
    model.set_reconstruction(rec, truth=sample, source="torus")
    yield model, view, plotter
    plotter.close()


def test_manifold_cells_follow_the_recorded_steps(scene):
    model, view, _ = scene
    ext = model.rec.extraction
    adapter = view.adapters["manifold"]
    removed = view.adapters["removed"]
    mesh_before = adapter.part.mesh
    actor_before = adapter.part.actor
    model.layers["removed"].visible = True
    positions = [0, 1, 2, 3, ext.n_steps // 2, ext.n_steps, 2, 0]
    for i in positions:
        model.player.set_step(i)
        # what the step records say, independent of Extraction.alive
        gone = sum(len(s.removed) for s in ext.steps[:i])
        assert adapter.part.n_cells == len(ext.simplices) - gone
        assert removed.part.n_cells == gone
        assert model.layers["manifold"].count == len(ext.simplices) - gone
    # updated in place: same PolyData and actor throughout
    assert adapter.part.mesh is mesh_before and adapter.part.actor is actor_before


def test_hidden_layers_catch_up_when_shown(scene):
    model, view, _ = scene
    ext = model.rec.extraction
    removed = view.adapters["removed"]
    assert not model.layers["removed"].visible
    model.player.set_step(ext.n_steps // 2)
    model.projection.set_angle(0, 1, 0.4)
    model.layers["removed"].visible = True
    assert removed.part.n_cells == int((~ext.alive(ext.n_steps // 2)).sum())
    pts = removed.drawing.points(model.projection.project(model.rec.points))
    assert np.allclose(np.array(removed.part.mesh.points), pts)


def test_step_highlight_matches_the_recorded_step(scene):
    model, view, _ = scene
    ext = model.rec.extraction
    step = view.adapters["step"]
    for i in range(1, min(ext.n_steps, 6) + 1):
        model.player.set_step(i)
        s = ext.steps[i - 1]
        assert step.part.n_cells == len(s.kept) + len(s.removed)
        assert step.parts[1].mesh.n_points == len(s.tau)


def test_a_delivered_result_shows_no_step_markers_until_the_player_moves(scene):
    """A run lands at its final M_S: the last step's tau and removed simplices are not drawn over it (a new
    user read the cap open-cap removed from an open scan, drawn red, as a lid over the opening).  Stepping
    back and forward to the same position draws them, as every other position does."""
    model, view, _ = scene
    ext = model.rec.extraction
    step = view.adapters["step"]
    last = ext.steps[-1]
    assert model.player.position == ext.n_steps and model.player.current_step is last
    assert model.player.shown_step is None
    assert step.part.n_cells == 0 and step.parts[1].mesh.n_points == 0
    assert not any(label.startswith("tau") for label, _ in view.legend_entries())
    model.player.prev()
    model.player.next()
    assert model.player.shown_step is last
    assert step.part.n_cells == len(last.kept) + len(last.removed) and step.parts[1].mesh.n_points == len(last.tau)
    assert any(label.startswith("tau") for label, _ in view.legend_entries())
    # asked for the last step itself (End, its row in the table): its markers, as at every other step
    model.set_reconstruction(model.rec, source="torus")
    assert model.player.shown_step is None
    model.player.last()
    assert model.player.shown_step is last and step.parts[1].mesh.n_points == len(last.tau)
    # the same result shown again (a re-extraction keeps the step): clean again at its end
    model.set_reconstruction(model.rec, source="torus")
    assert model.player.shown_step is None and step.part.n_cells == 0


def test_projection_moves_points_but_not_data(scene):
    model, view, _ = scene
    rec = model.rec
    pts_before = rec.points.copy()
    mesh = view.adapters["points"].part.mesh
    a = np.array(mesh.points)
    model.projection.set_angle(0, 2, 0.8)
    b = np.array(mesh.points)
    assert not np.allclose(a, b)
    assert np.allclose(b, model.projection.project(rec.points))
    assert np.array_equal(rec.points, pts_before)
    n = view.adapters["manifold"].part.n_cells
    model.projection.set_pca(rec.points)
    assert view.adapters["manifold"].part.n_cells == n


def test_candidates_follow_theta(scene):
    model, view, _ = scene
    c = view.adapters["candidates"]
    model.set_candidate_display(theta=np.radians(10))
    n10 = c.part.n_cells
    model.set_candidate_display(theta=np.radians(30))
    n30 = c.part.n_cells
    assert n10 == int(model.rec.candidates.mask(model.test, np.radians(10)).sum())
    assert n30 >= n10
    ang = np.array(c.part.mesh.cell_data["values"])
    assert ang.max() < 30 + 1e-9


def test_selected_cell_and_poles(scene):
    model, view, _ = scene
    rec = model.rec
    hull = np.flatnonzero(rec.pole_index[:, 0] >= len(rec.delaunay_simplices))
    inner = np.flatnonzero(rec.pole_index[:, 0] < len(rec.delaunay_simplices))
    poles = view.adapters["poles"]
    finite, rays = poles.parts[0], poles.parts[2]
    model.selection.select_sample(int(inner[0]))
    assert view.adapters["voronoi"].part.n_cells > 0
    assert (finite.n_cells, rays.n_cells) == (1, 0)
    # a hull sample: its pole is the vertex at infinity, drawn as a ray to the box; its cell still draws
    i = int(hull[0])
    model.selection.select_sample(i)
    assert view.adapters["voronoi"].part.n_cells > 0
    assert (finite.n_cells, rays.n_cells) == (0, 1)
    start, end = poles.rays  # ambient end points of the ray
    lo, hi = model.box
    u = rec.voronoi_vertices[rec.pole_index[i, 0]] - rec.points[i]
    assert np.allclose(start, rec.points[i])
    assert np.isclose(end, lo).any() or np.isclose(end, hi).any()  # reaches the edge of the box
    cos = np.dot(end - start, u) / np.linalg.norm(end - start) / np.linalg.norm(u)
    assert cos > 1 - 1e-9  # in the direction of the vertex at infinity
    assert "Pole at infinity (hull sample)" in [label for label, _ in view.legend_entries()]
    model.layers["poles"].mode = "all"
    assert finite.n_cells == rec.n - len(hull) and rays.n_cells == len(hull)
    assert model.layers["poles"].count == rec.n * (rec.k - rec.d)


def test_flat_input_has_no_phantom_poles():
    """A curve in a plane of R^3: the normal orthogonal to the plane has no pole (index -1)."""
    from crustview.core import reconstruct
    from crustview.scene.describe import interpretation_rows
    from crustview.scene.inspector_text import sample_text

    t = np.linspace(0, 2 * np.pi, 80, endpoint=False)
    rec = reconstruct(np.c_[np.cos(t), 2 * np.sin(t), np.zeros_like(t)], 1)
    assert rec.subspace_dim == 2 and (rec.pole_index[:, 1] == -1).all()
    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=(300, 200))
    try:
        view = SceneView(model, plotter)
        model.set_reconstruction(rec, source="flat ellipse")
        model.layers["poles"].mode = "all"
        poles = view.adapters["poles"]
        drawn = poles.parts[0].n_cells + poles.parts[2].n_cells
        assert drawn == rec.n == model.layers["poles"].count
        assert "pole 2: none" in sample_text(model, 0)
        rows = {a: b for a, b, _ in interpretation_rows(rec)}
        assert rows["affine hull"].startswith("2-dimensional")
        model.layers["points"].colorby = "pole distance"
        assert view.adapters["points"].n_missing == int((rec.pole_index[:, 0] >= len(rec.delaunay_simplices)).sum())
    finally:
        plotter.close()


def test_d3_boundary_triangles_with_shrink(s3_run):
    rec, sample = s3_run
    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=(300, 200))
    try:
        view = SceneView(model, plotter)
        model.set_reconstruction(rec, truth=sample, source="s3")
        a = view.adapters["manifold"]
        m = int(rec.extraction.alive(0).sum())
        assert a.part.n_cells == 4 * m  # 4 triangles per tetrahedron
        assert a.part.mesh.n_points == 4 * len(rec.extraction.simplices)
        p1 = np.array(a.part.mesh.points)
        model.layers["manifold"].shrink = 0.5
        p2 = np.array(a.part.mesh.points)
        # shrinking moves every vertex towards its simplex centroid
        c = p1.reshape(-1, 4, 3).mean(axis=1, keepdims=True)
        assert np.allclose(p2.reshape(-1, 4, 3), c + (p1.reshape(-1, 4, 3) - c) * 0.5 / 0.8)
    finally:
        plotter.close()


def test_a_note_longer_than_the_view_is_wide_wraps_and_rewraps_when_it_widens(scene):
    """A verdict with a note on the file's mesh ran off the right edge of a 726-px view; now the notes wrap
    to the view's width, and again before the next frame once that width changed."""
    _, view, plotter = scene
    legend = view.legend
    long = "M_S is a closed manifold through every sample; it has the mesh's topology but for 1 hole " * 2
    legend.set([("Samples", "#222222")], [long, "short"])
    notes = [a.GetInput() for a in legend.actors if a.GetTextProperty().GetBold()]
    assert len(notes) >= 4 and notes[-1].strip() == "short"
    assert " ".join(n.strip() for n in notes[:-1]) == long.strip()
    assert all(len(n.strip()) <= legend._chars() for n in notes)
    plotter.window_size = (2400, 300)
    plotter.ren_win.Render()  # a frame: the view's observer re-wraps first
    wide = [a.GetInput() for a in legend.actors if a.GetTextProperty().GetBold()]
    assert len(wide) == 2 and wide[0].strip() == long.strip()


def test_legend_lines_do_not_overlap_on_a_small_export():
    """At 240 pixels high the legend's 3.2 % line step was 7.7 px for an 8-point font: the lines overlapped
    in a new user's 320 x 240 GIF.  The step is now at least 1.3 times the font."""
    from crustview.render.overlay import Legend

    plotter = pv.Plotter(off_screen=True, window_size=(320, 240))
    try:
        legend = Legend(plotter, font_size=8)
        legend.set([("Samples", "#222222"), ("M_S", "#e0b070"), ("Normal planes", "#22aaaa")], ["a note"])
        ys = sorted(
            {a.GetPositionCoordinate().GetReferenceCoordinate().GetValue()[1] for a in legend.actors}, reverse=True
        )
        gaps = np.diff(ys) * -240
        assert len(ys) == 4 and gaps.min() >= 1.3 * 8 - 1e-6, gaps
    finally:
        plotter.close()


def test_notes_wrap_at_spaces_and_keep_betti_tuples_whole():
    from crustview.render.overlay import _wrap

    text = "M_S is WRONG: Betti (1, 4, 1) ≠ mesh (26, 0, 26) (uncertain: 2 handles, 0 holes, 14 components)"
    lines = _wrap(text, 30)
    assert " ".join(lines) == text and all(len(x) <= 30 for x in lines)
    assert any(x.endswith("(1, 4, 1)") for x in lines) and any("(26, 0, 26)" in x for x in lines)
    assert _wrap("a-b-c-d-e-f-g", 3) == ["a-b-c-d-e-f-g"]  # no break at hyphens
