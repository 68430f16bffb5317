"""Opening a second file: its raw points, not the first file's result, until its own result arrives."""

from __future__ import annotations

from pathlib import Path

import numpy as np

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def _shown(renderer, actor) -> bool:
    return bool(renderer.HasViewProp(actor) and actor.GetVisibility())


def test_a_second_file_shows_its_points_at_once_and_its_result_when_done(qtbot, window, tmp_path):
    """A new user opened the turbine blade after the foot bones: for the whole run the window showed the
    foot bones' mesh, its red WRONG banner and its title.  Now the shown result is set aside the moment the
    next file is read, its points are drawn, the title names it; its own result replaces them, and where a
    run fails the result shown before it comes back."""
    assert window.open_file(RESOURCES / "bumpy.off", d=2)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    qtbot.wait(50)
    first = window.model.rec
    manifold = window.view.adapters["manifold"].part.actor
    main = window.plotter.renderer
    assert _shown(main, manifold)
    assert window.open_file(RESOURCES / "3holes.off", d=2)
    # before the event loop hands back the new result: the points of 3holes.off, none of bumpy's result
    preview = window.plotter.actors.get("preview")
    assert preview is not None and preview.GetVisibility()
    assert preview.GetMapper().GetInput().GetNumberOfPoints() == 3596
    assert not manifold.GetVisibility() and window.model.rec is first
    hud = window.view.hud.GetViewProps()
    assert all(not hud.GetItemAsObject(i).GetVisibility() for i in range(hud.GetNumberOfItems()))
    assert "3holes.off" in window.windowTitle() and "bumpy" not in window.windowTitle()
    assert window.status_counts.text() == "n = 3596 · reconstructing…"  # not bumpy's n and M_S counts
    assert not window.info_panel.isEnabled() and not window.steps_panel.isEnabled()  # greyed: bumpy's
    assert window.info_panel.banner.isHidden()  # bumpy's verdict
    qtbot.waitUntil(lambda: not window.runner.busy and window.model.rec is not first, timeout=60_000)
    qtbot.wait(50)
    assert window.plotter.actors.get("preview") is None and _shown(main, manifold)
    assert window.model.rec.topology.betti == (1, 6, 1) and "3holes.off" in window.windowTitle()
    assert window.info_panel.isEnabled() and window.steps_panel.isEnabled() and not window.info_panel.banner.isHidden()
    # a third file whose run fails (every point the same: one line, no traceback): the result shown before it
    # comes back as it was, with its title, and the preview goes
    title = window.windowTitle()
    counts = window.status_counts.text()
    camera = window.plotter.camera.position
    manifold = window.view.adapters["manifold"].part.actor
    # a file whose d cannot be estimated (4 distinct points) is refused in one line before anything moves
    few = tmp_path / "few.xyz"
    np.savetxt(few, np.random.default_rng(0).normal(size=(4, 3)))
    assert not window.open_file(few)
    assert "distinct points" in window.last_error and getattr(window.view, "shelved", None) is None
    assert window.windowTitle() == title and window.info_panel.isEnabled() and manifold.GetVisibility()
    same = tmp_path / "same.xyz"
    np.savetxt(same, np.ones((20, 3)))
    window.open_file(same, d=2)
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    qtbot.wait(50)
    assert window.last_error and "coincide" in window.last_error
    assert window.plotter.actors.get("preview") is None
    assert manifold.GetVisibility() and window.windowTitle() == title and window.info_panel.isEnabled()
    assert window.status_counts.text() == counts and counts.startswith("n = 3596")
    assert window.layers_panel.isEnabled() and window.plotter.camera.position == camera  # as it was shown
    assert window.model.layers["points"].count == 3596
    assert not window.info_panel.banner.isHidden()
    assert window.model.rec.n == 3596
