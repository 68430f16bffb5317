"""One frame per change of the picture (render.frames): a batch of view edits draws once, at its end."""

from __future__ import annotations

import numpy as np
import pytest

from crustview.render.frames import FrameGate


class _Plotter:
    """Stands for a plotter's ``render`` only: the gate's own logic, checked by hand."""

    def __init__(self) -> None:
        self.drawn = 0

    def render(self) -> str:
        self.drawn += 1
        return "frame"


def test_outside_a_batch_every_render_draws():
    p = _Plotter()
    gate = FrameGate(p)
    assert p.render() == "frame" and p.render() == "frame"
    assert p.drawn == 2 and gate.frames == 2 and not gate.holding


def test_a_nested_batch_draws_one_frame_when_the_outermost_ends():
    p = _Plotter()
    gate = FrameGate(p)
    with gate.held():
        p.render()
        with gate.held():
            p.render()
            p.render()
        assert p.drawn == 0 and gate.owed and gate.holding  # the inner batch's end draws nothing
        p.render()
    assert p.drawn == 1 and not gate.owed and not gate.holding


def test_a_batch_that_asked_for_nothing_draws_nothing():
    p = _Plotter()
    gate = FrameGate(p)
    with gate.held():
        pass
    assert p.drawn == 0 and gate.frames == 0


def test_a_batch_that_raised_still_draws_what_it_owed():
    p = _Plotter()
    gate = FrameGate(p)
    with pytest.raises(RuntimeError), gate.held():
        p.render()
        raise RuntimeError("an edit failed")
    assert p.drawn == 1 and not gate.holding  # the picture is not left behind the model


# ---------------------------------------------------------------- the real view, off screen
pv = pytest.importorskip("pyvista")


def _drawing_view():
    """A SceneView on an off-screen plotter that draws every render asked for (pyvista draws nothing before
    its first screenshot or show), and a list that gets an entry per frame VTK draws."""
    from crustview.render import SceneView
    from crustview.scene import SceneModel

    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=(400, 300))
    view = SceneView(model, plotter)
    plotter.screenshot(return_img=True)
    drawn: list = []
    plotter.ren_win.AddObserver("StartEvent", lambda *_: drawn.append(1))
    return model, view, plotter, drawn


def _no_batch():
    """A ``held`` that batches nothing."""
    from contextlib import nullcontext

    return nullcontext()


def test_a_new_result_draws_one_frame_and_the_same_picture(torus_run):
    rec, sample = torus_run
    model, view, plotter, drawn = _drawing_view()
    with view.held():  # as the window shows a finished run (running._job_done)
        model.set_reconstruction(rec, truth=sample, source="torus")
    # the layers shown and styled, the overlays, the camera's reset (pyvista's own render calls too): one frame
    assert len(drawn) == 1
    batched = plotter.screenshot(return_img=True)
    # the same edits with a frame drawn for every render asked for give the same picture (the legend's layout
    # and the camera's fit do not depend on a frame drawn between them)
    m2, v2, other, drawn2 = _drawing_view()
    v2.held = _no_batch  # every render asked for is drawn at once, as before the gate
    m2.set_reconstruction(rec, truth=sample, source="torus")
    assert len(drawn2) > 3  # it did draw several
    each = other.screenshot(return_img=True)
    plotter.close()
    other.close()
    assert batched.shape == each.shape
    assert np.abs(batched.astype(int) - each.astype(int)).max() == 0


def test_the_raw_points_preview_and_a_result_on_its_own_draw_one_frame_each(torus_run):
    model, view, plotter, drawn = _drawing_view()
    view.show_preview(torus_run[1].points)  # the first access to the camera renders in pyvista: owed, not drawn
    assert len(drawn) == 1
    model.rec = torus_run[0]
    view.on_reconstruction()  # without the window's batch: the view's own handler is one batch
    assert len(drawn) == 2
    plotter.close()
