"""Issue 19, overlays: text, legends and colour bars over every layer; the comparison seen when made.

Each test says what it checks; both failed before (the legend, the bars and
the view-axes caption were in the scene's renderer, under the overlay layer
that draws the step, the cascade and the truth; the comparison layer lay
under an opaque M_S).
"""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import load


def _geometry_layers(win) -> set[int]:
    """Layers of every renderer that holds a 3-D actor of the view."""
    out = set()
    rens = win.plotter.render_window.GetRenderers()
    rens.InitTraversal()
    for _ in range(rens.GetNumberOfItems()):
        r = rens.GetNextItem()
        if r.GetActors().GetNumberOfItems():
            out.add(r.GetLayer())
    return out


def test_text_legend_and_bars_are_drawn_over_all_geometry(qtbot, window):
    """The legend lines, the ε bar and the view-axes caption live in a renderer above every geometry layer."""
    load(qtbot, window, "torus")
    m = window.model
    m.layers["points"].colorby = "epsilon"
    m.layers["removed"].visible = True
    m.player.set_step(m.player.n_steps // 2)
    window.steps_panel.follow.setChecked(True)  # framing a step: geometry fills the view
    view = window.view
    hud = view.hud
    top = max(_geometry_layers(window))
    assert hud.GetLayer() > top
    props = hud.GetViewProps()
    legend = view.legend.actors
    assert legend and all(props.IsItemPresent(a) for a in legend)
    assert props.IsItemPresent(view.basis_text)
    bar = window.plotter.scalar_bars["estimated epsilon"]
    assert props.IsItemPresent(bar)
    assert not window.plotter.renderer.GetViewProps().IsItemPresent(bar)
    # a bar that goes away leaves the text layer too
    m.layers["points"].colorby = "none"
    assert "estimated epsilon" not in window.plotter.scalar_bars
    assert not hud.GetViewProps().IsItemPresent(bar)


@pytest.mark.gl
def test_a_comparison_is_seen_and_named_when_created(qtbot, window):
    """A new comparison: its layer is switched on, drawn in the overlay over M_S, and named in the legend at once.

    Before, it was drawn in the scene under an opaque M_S (what lay inside M_S never
    showed), a layer hidden earlier stayed hidden, and the legend waited for the next step.
    """
    from crustview.core import reextract
    from crustview.core.analysis.complexdiff import diff_complexes
    from crustview.scene.comparison import Comparison

    rec = load(qtbot, window, "torus", n=700)
    m = window.model
    for name in ("points", "normals", "step", "uncertain"):
        m.layers[name].visible = False
    m.layers["compare"].visible = False  # hidden for an earlier comparison
    window.view.render()
    before = window.plotter.screenshot(return_img=True).astype(int)
    other = reextract(rec, "literal", np.radians(15.0), prune_boundary=rec.prune_boundary, mode=rec.mode)
    diff = diff_complexes(rec.points, rec.manifold, other.points, other.manifold, 2)
    assert len(diff.only_b) > 0
    assert m.set_comparison(Comparison("A", "B", diff, rec))
    assert m.layers["compare"].visible
    labels = [label for label, _ in window.view.legend.entries]
    assert any(str(label).startswith("only in B") for label in labels), labels
    top = window.view.top_renderer
    for part in window.view.adapters["compare"].parts:
        assert top.GetActors().IsItemPresent(part.actor)
        assert not window.plotter.renderer.GetActors().IsItemPresent(part.actor)
    after = window.plotter.screenshot(return_img=True).astype(int)
    blue = (after[..., 2] > 150) & (after[..., 0] < 110) & (before[..., 2] < 150)
    assert blue.sum() > 500  # the only-B simplices (blue) are seen
