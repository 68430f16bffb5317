"""The viewer on a big sample: glyph layers drawn as a subset and saying so,
steps that touch only what they change, thinned frames while stepping.

A 20,000-point torus stands in for a million points: the glyph limit and the
level-of-detail budget are lowered so that the same code paths run (the
benchmark ``benchmarks/bench_viewer.py --torus 1000000`` measures the real
size and its times).  Wall-clock ratios do not separate a step from a
rebuild at this size (both are a few milliseconds of fixed costs), so the
step is compared with a rebuild by the work both do, counted in the same
process: the sample rows each projects.
"""

import numpy as np
import pytest

N = 20_000


@pytest.fixture(scope="module")
def big_torus():
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    return reconstruct(get_manifold("torus").sample(N, seed=0, method="random").points, 2)


def test_glyph_layers_say_they_draw_a_subset(qtbot, window, big_torus, monkeypatch):
    from crustview.scene import subset

    monkeypatch.setattr(subset, "GLYPH_LIMIT", 5_000)
    window.model.set_reconstruction(big_torus, source="torus 20k")
    window.model.layers["normals"].visible = True  # hidden by default at this size
    layer = window.model.layers["normals"]
    assert layer.count == 5_000 and layer.total == N
    assert layer.note.startswith("Normal planes: drawn 5,000 of 20,000 (every 4th sample)")
    row = window.layers_panel.rows["normals"]
    assert row.count.text().split() == ["5,000", "of", "20,000"] and row.count.toolTip() == layer.note
    assert layer.note in window.view.notes()  # said over the 3-D view too
    assert window.view.adapters["normals"].part.n_cells == 5_000  # a subset, not nothing
    window.model.layers["poles"].mode = "all"
    poles = window.model.layers["poles"]
    assert poles.count == 5_000 and poles.total == N and "drawn 5,000 of 20,000" in poles.note
    window.model.layers["normals"].visible = False
    assert layer.note not in window.view.notes()


def _counting_projection(model) -> list[int]:
    """Rows given to ``model.projection.project`` from now on (the real projection still runs)."""
    rows: list[int] = []
    proj = model.projection
    real = type(proj).project.__get__(proj)
    proj.project = lambda x: (rows.append(len(np.atleast_2d(x))), real(x))[1]
    return rows


def test_a_step_updates_only_what_it_changes(qtbot, window, big_torus):
    window.model.set_reconstruction(big_torus, source="torus 20k")
    view, player = window.view, window.model.player
    player.set_step(player.n_steps // 2)
    manifold = view.adapters["manifold"].part.mesh
    points = view.adapters["points"].part.mesh
    before = (manifold.GetPoints(), manifold.GetPoints().GetMTime(), points.GetMTime())
    projected = _counting_projection(window.model)
    player.next()
    step_rows = sum(projected)
    # no mesh of the whole sample is rebuilt: the same points, untouched
    assert (manifold.GetPoints(), manifold.GetPoints().GetMTime(), points.GetMTime()) == before
    step = view.adapters["step"]
    assert 0 < step_rows == len(step.verts) and 0 < step.part.mesh.n_points <= 3 * len(step.ids)
    # the floor, counted the same way in this process: rebuilding the shown layers, as a
    # step that redrew whole meshes would (seconds at 10^6 points: see bench_viewer.py)
    projected.clear()
    for a in view.adapters.values():
        if a.layer.visible:
            a.rebuild()
    assert step_rows < 0.01 * sum(projected), (step_rows, sum(projected))
    del window.model.projection.project


def test_stepping_draws_big_layers_thinned_then_whole(qtbot, window, big_torus):
    window.model.set_reconstruction(big_torus, source="torus 20k")
    view, player = window.view, window.model.player
    view.lod.budget = 10_000
    whole = view.adapters["manifold"].part
    player.first()  # data opens on its final M_S (issue 19): step from T_S
    view.lod.end()
    player.next()
    assert view.lod.active
    drawn, total = view.lod.drawn()["manifold"]
    assert drawn <= 10_000 < total == whole.n_cells and not whole.actor.GetVisibility()
    qtbot.waitUntil(lambda: not view.lod.active, timeout=5_000)  # stepping paused: whole again
    assert whole.actor.GetVisibility()


def test_raw_points_preview_draws_a_subset_and_says_so(qtbot, window, big_torus, monkeypatch):
    from crustview.render import view as view_module

    monkeypatch.setattr(view_module, "PREVIEW_POINTS", 5_000)
    window.view.show_preview(big_torus.input_points)
    layer = window.model.layers["points"]
    assert window.plotter.actors["preview"].GetMapper().GetInput().GetNumberOfPoints() == 5_000
    assert window.layers_panel.rows["points"].count.text().split() == ["5,000", "of", "20,000"]
    assert layer.note.startswith("Raw points: drawn 5,000 of 20,000")
    window.model.set_reconstruction(big_torus, source="torus 20k")  # the result replaces the preview
    assert layer.count == N and layer.total == 0 and layer.note == ""
    assert window.plotter.actors.get("preview") is None
