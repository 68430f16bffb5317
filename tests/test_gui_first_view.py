"""Issue 19: what a file shows when it is opened, and displays that must not outlive their file.

Each test says in its docstring what it checks and why it failed before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from gui_helpers import display_xy, load, wait_idle

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def test_file_opens_on_its_final_result_with_samples_framed(qtbot, window):
    """A mesh opens at its last step with M_S and the samples drawn and all of M_S in view.

    Before, the view sat at step 0 (M_S empty: a blank view for a robust run)
    and a 10,000-point scan had its samples off.
    """
    assert window.open_file(RESOURCES / "bumpy.off", d=2)
    wait_idle(qtbot, window)
    qtbot.wait(50)
    m = window.model
    rec = m.rec
    assert m.player.position == rec.extraction.n_steps > 0
    assert m.layers["manifold"].count == len(rec.manifold) > 0
    assert m.layers["points"].visible and m.layers["points"].count == rec.n
    # every sample projects inside the view (not clipped by the framing)
    w, h = window.plotter.window_size
    proj = m.projection.project(rec.points)
    xy = np.array([display_xy(window, p) for p in proj[:: max(1, rec.n // 300)]])
    assert (xy[:, 0] > 0).all() and (xy[:, 0] < w).all() and (xy[:, 1] > 0).all() and (xy[:, 1] < h).all()


def test_samples_shown_for_a_ten_thousand_point_scan(qtbot, window):
    """The model shows the samples of a 10,044-point result (they were off above 10,000)."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold("sphere")
    rec = reconstruct(m.sample(10_044, seed=0, method="random").points, 2)  # i.i.d.: the even sampler takes 2 s
    window.model.set_reconstruction(rec, source="scan")
    assert window.model.layers["points"].visible
    assert window.model.player.position == rec.extraction.n_steps


def test_mesh_truth_is_a_wireframe_named_in_the_legend(qtbot, window):
    """A mesh's ground truth is drawn as edges and the legend says it is not the result.

    Before, its faces were a shaded surface named only "Ground truth".
    """
    assert window.open_file(RESOURCES / "bumpy.off", d=2)
    wait_idle(qtbot, window)
    truth = window.view.adapters["truth"]
    assert window.model.layers["truth"].visible
    assert truth.part.actor.prop.style == "Wireframe"
    labels = [label for label, _ in window.view.legend_entries()]
    assert any("ground truth" in label and "not the result" in label for label in labels), labels


def test_play_and_home_replay_from_the_start(qtbot, window):
    """From the final M_S, Home goes to T_S and Play starts again from step 0."""
    load(qtbot, window, "torus")
    p = window.model.player
    assert p.position == p.n_steps
    p.play()
    assert p.position == 0 and p.playing
    p.pause()
    assert not p.playing
    p.last()
    assert p.position == p.n_steps
    p.first()
    assert p.position == 0


def test_epsilon_bar_follows_the_new_file(qtbot, window):
    """The ε colour bar shows the current file's range and bound marks.

    Before, after an R^4 file the torus kept the old bar (0-0.707, marks of
    the R^4 bounds) while its samples used the torus's own ε scale: the bar
    was kept because its title and mapper were the same.
    """
    points = window.model.layers["points"]
    load(qtbot, window, "flat-klein", n=600)
    points.colorby = "epsilon"
    load(qtbot, window, "torus")
    assert points.colorby == "epsilon"
    lut = window.view.adapters["points"].part.mapper.GetLookupTable()
    bar = window.plotter.scalar_bars["estimated epsilon"]
    assert bar.GetLookupTable() is lut
    want = 4.0 * max(window.model.quality.thresholds.values())
    assert np.allclose(bar.GetLookupTable().GetRange(), (0.0, want))
