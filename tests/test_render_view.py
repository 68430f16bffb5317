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


def test_manifold_cells_follow_alive_exactly(scene):
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
        assert adapter.part.n_cells == int(ext.alive(i).sum())
        assert removed.part.n_cells == int((~ext.alive(i)).sum())
        assert model.layers["manifold"].count == int(ext.alive(i).sum())
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
    model.selection.select_sample(3)
    assert view.adapters["voronoi"].part.n_cells > 0
    poles = view.adapters["poles"]
    assert poles.part.n_cells == model.rec.k - model.rec.d
    model.layers["poles"].mode = "all"
    assert poles.part.n_cells == model.rec.n * (model.rec.k - model.rec.d)


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
