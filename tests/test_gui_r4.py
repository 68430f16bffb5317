"""Reading shapes in R^4 in the real window: names, colours by coordinate, slices, stereographic view."""

import numpy as np
import pytest
from gui_helpers import load as load_builtin


def topology_row(win, name):
    table = win.info_panel.topology
    for r in range(table.rowCount()):
        if table.item(r, 0).text() == name:
            return table.item(r, 1).text(), table.item(r, 2).text()
    raise KeyError(name)


@pytest.mark.parametrize("name, words", [("hopf-link", "2 circles"), ("flat-klein", "Klein bottle")])
def test_the_window_names_the_shape_and_checks_it_against_the_truth(qtbot, window, name, words):
    load(qtbot, window, name)
    assert words in window.windowTitle()
    assert topology_row(window, "shape") == (words, words)


def load(qtbot, win, name, n=None):
    """Built-ins in R^4 and up: their Delaunay takes longer."""
    return load_builtin(qtbot, win, name, n, timeout=120_000)


def test_a_translucent_m_s_keeps_its_edges(qtbot, window):
    load(qtbot, window, "torus")
    window.model.layers["manifold"].opacity = 0.4
    prop = window.view.adapters["manifold"].part.actor.prop
    assert prop.show_edges and prop.opacity == pytest.approx(0.4)


def mesh_scalars(adapter):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    return vtk_to_numpy(adapter.part.mesh.GetPointData().GetArray("values"))


def test_m_s_is_coloured_by_the_hidden_coordinate_and_follows_the_view(qtbot, window):
    from crustview.render.view import BAR_TITLE_LINE, COLORED_SWATCH

    rec = load(qtbot, window, "flat-klein")
    m = window.model
    layer = m.layers["manifold"]
    a = window.view.adapters["manifold"]
    assert layer.colorby == "hidden depth"  # the default in R^4: the coordinate the view drops
    assert np.allclose(mesh_scalars(a), rec.points[:, 3] - m.projection.origin[3])
    assert a.part.mapper.scalar_visibility and a.scalar_title in window.view._bars
    # the legend names the coloured complex (it had no entry: a new user could not tell what the bar coloured),
    # and the bar's long title puts its direction on a second line (it ran off a 640 x 480 render)
    assert ("M_S at this step: coloured by hidden depth (bar)", COLORED_SWATCH) in window.view.legend_entries()
    assert window.plotter.scalar_bars[a.scalar_title].GetTitle() == a.scalar_title == "hidden depth (1.00 x4)"
    m.projection.set_angle(2, 3, 0.3)  # x3 and x4 mixed: a longer title
    window.view.update_bars()
    shown = window.plotter.scalar_bars[a.scalar_title].GetTitle()
    assert len(a.scalar_title) > BAR_TITLE_LINE and shown == a.scalar_title.replace(" (", "\n(", 1)
    m.projection.set_angle(2, 3, np.pi / 2)  # now x3 is hidden
    assert np.allclose(np.abs(mesh_scalars(a)), np.abs(rec.points[:, 2] - m.projection.origin[2]), atol=1e-9)
    layer.colorby = "x1"
    assert np.allclose(mesh_scalars(a), rec.points[:, 0])
    m.layers["points"].colorby = "x2"
    assert np.allclose(mesh_scalars(window.view.adapters["points"]), rec.points[:, 1])


def test_slicing_s3_gives_a_2_sphere_and_cuts_m_s_in_half(qtbot, window):
    rec = load(qtbot, window, "s3", 600)
    m = window.model
    panel = window.projection_panel.slice
    before = m.layers["manifold"].count
    panel.show_slice.setChecked(True)
    panel.set_offset(0.2)
    a = window.view.adapters["slice"]
    u = m.slice_normal()
    assert np.allclose(u, [0, 0, 0, 1])
    assert np.allclose((a.xk - m.projection.origin) @ u, m.slice_offset, atol=1e-9)
    assert abs(m.slice_offset - 0.2) < 0.02
    # the cross-section is a closed surface with the Euler characteristic of a sphere
    from vtkmodules.util.numpy_support import vtk_to_numpy

    polys = vtk_to_numpy(a.part.mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    _, vid = np.unique(np.round(a.xk, 9), axis=0, return_inverse=True)
    tris = np.sort(vid.ravel()[polys], axis=1)
    tris = tris[(tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2])]
    edges, count = np.unique(np.vstack([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]]), axis=0, return_counts=True)
    assert (count == 2).all()  # closed: every edge in two triangles
    from crustview.core.analysis.topology import graph_components

    vs = np.unique(tris)
    assert graph_components(len(vs), np.searchsorted(vs, edges))[0] == 1  # one piece
    assert len(vs) - len(edges) + len(tris) == 2
    # the half-space cut keeps only what lies below the hyperplane
    panel.cut.setChecked(True)
    cut = m.layers["manifold"].count
    assert 0 < cut < before
    ext = rec.extraction
    shown = ext.simplices[window.view.adapters["manifold"].rows]
    assert (m.slice_values()[shown] <= 0).all()
    panel.show_slice.setChecked(False)
    assert m.layers["manifold"].count == before


def test_stereographic_view_of_the_clifford_torus(qtbot, window):
    rec = load(qtbot, window, "clifford-torus")
    m = window.model
    linear = m.projection.project(rec.points)
    window.projection_panel.stereo.setChecked(True)
    p = m.projection
    assert p.stereographic
    y = rec.points - p.origin
    r = p.stereo_radius
    want = y[:, :3] * (r / (r - y[:, 3]))[:, None]
    got = p.project(rec.points)
    assert np.allclose(got, want)
    # drawn: the samples layer holds the stereographic positions
    from vtkmodules.util.numpy_support import vtk_to_numpy

    pts = vtk_to_numpy(window.view.adapters["points"].part.mesh.GetPoints().GetData())
    assert np.allclose(pts, want) and not np.allclose(pts, linear)
    # the Clifford torus |x12| = |x34| becomes a torus of revolution about the view's z axis:
    # the distance from that axis is spread out, not constant as in the linear view's annulus
    assert np.ptp(np.hypot(got[:, 0], got[:, 1])) > 1.5 * np.ptp(np.hypot(linear[:, 0], linear[:, 1]))
    # the caption says the drawn coordinates are no longer the linear combinations alone
    assert window.view.basis_text.GetText(0).startswith("view axes: stereographic, each axis times r / (r - h)")
    window.projection_panel.stereo.setChecked(False)
    assert np.allclose(m.projection.project(rec.points), linear)
    assert "stereographic" not in window.view.basis_text.GetText(0)


def test_rotation_sliders_show_their_angle(qtbot, window):
    load(qtbot, window, "clifford-torus")
    panel = window.projection_panel
    panel.sliders[(0, 3)].setValue(45)
    assert panel.readouts[(0, 3)].text() == "45°"
    window.model.projection.set_angle(1, 2, np.radians(-30))
    assert panel.readouts[(1, 2)].text() == "-30°" and panel.sliders[(1, 2)].value() == -30


def test_rotation_sliders_follow_the_grand_tour(qtbot, window):
    load(qtbot, window, "clifford-torus")
    m = window.model
    panel = window.projection_panel
    tour = m.tour
    tour.speed = 1.0
    seen = []
    for _ in range(8):
        tour.advance(0.05)
        angles = m.projection.angles
        # the sliders' angles are the view: rotating the coordinate basis by them gives the tour's basis
        r = np.eye(4)
        for (i, j), a in sorted(angles.items()):
            from crustview.scene.projection import givens

            r = givens(4, i, j, a) @ r
        assert np.allclose(r[:, :3], m.projection.basis, atol=1e-6)
        for key, s in panel.sliders.items():
            deg = np.degrees(angles.get(key, 0.0))
            assert abs(s.value() - deg) <= 0.51 and panel.readouts[key].text() == f"{deg:.0f}°"
        seen.append(np.array([angles.get(p, 0.0) for p in m.projection.planes()]))
    assert np.abs(seen[-1] - seen[0]).max() > np.radians(1)  # the sliders moved
    jumps = [np.abs(np.angle(np.exp(1j * (b - a)))).max() for a, b in zip(seen, seen[1:])]
    assert max(jumps) < np.radians(20)  # and moved continuously


def test_all_poles_in_r4_are_short_ticks(qtbot, window):
    rec = load(qtbot, window, "clifford-torus")
    m = window.model
    poles = m.layers["poles"]
    poles.mode = "all"
    poles.visible = True
    a = window.view.adapters["poles"]
    half = len(a.xk) // 2
    assert half >= rec.n  # every sample has its poles drawn
    seg = np.linalg.norm(a.xk[half:] - a.xk[:half], axis=1)
    from crustview.render.samples import TICK_SPACINGS

    assert seg.max() <= TICK_SPACINGS * m.spacing.max() + 1e-9
    assert np.median(seg) < 0.15 * np.ptp(rec.points, axis=0).max()  # not lines across the whole view
    assert a.parts[1].n_cells == 0  # no end dots


def test_scalar_bars_never_overlap_when_new_data_adds_one(qtbot, window):
    """xdotool trial: "removed by step" (shown on the torus) and the hidden depth of a shape
    in R^4 were drawn at the same place, their labels over each other."""
    assert window.load_builtin("circle", 60)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    window.model.layers["removed"].visible = True
    assert list(window.view._bars) == ["removed by step"]
    assert window.load_builtin("circle-r4", 60)
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec.k == 4, timeout=60_000)
    titles = list(window.view._bars)
    assert len(titles) >= 2 and "removed by step" in titles
    bars = window.plotter.scalar_bars
    heights = [round(bars[t].GetPosition()[1], 3) for t in titles]
    assert len(set(heights)) == len(heights), dict(zip(titles, heights))


def test_the_hidden_depth_bar_names_the_direction_after_a_rotation(qtbot, window):
    """xdotool trial: after turning x1-x4 the bar still said "hidden depth (1.00 x4)"."""
    assert window.load_builtin("circle-r4", 60)
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec.k == 4, timeout=60_000)
    before = [t for t in window.view._bars if t.startswith("hidden depth")]
    assert before == ["hidden depth (1.00 x4)"]
    window.model.projection.set_angle(0, 3, 1.0)
    titles = [t for t in window.view._bars if t.startswith("hidden depth")]
    assert len(titles) == 1 and titles[0] != before[0] and "x1" in titles[0]
    assert titles[0] in window.plotter.scalar_bars
