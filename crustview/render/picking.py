"""Picking what is seen: the nearest visible element under the cursor.

The step overlay is drawn over everything (a second renderer layer), so
whatever of it lies under the cursor is what the user sees, and it wins.
Below it, samples and simplices are compared by their depth along the view
ray: a sample hidden behind a triangle is not picked through it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from vtkmodules.vtkRenderingCore import vtkCellPicker

#: Pick tolerance (share of the window diagonal) for samples drawn as points.
POINT_TOLERANCE = 0.006
#: Pick tolerance for cells (exact for polygons; lines need a little).
CELL_TOLERANCE = 0.0005


@dataclass(frozen=True)
class Hit:
    """One picked element and how far it lies along the view ray."""

    got: tuple[str, object]
    depth: float


def pick_layers(view, renderer, names: tuple[str, ...], x: float, y: float, tol: float) -> Hit | None:
    """The nearest element of the visible layers ``names`` under ``(x, y)``.

    Parameters
    ----------
    view : SceneView
    renderer : vtkRenderer
        The renderer holding those layers' actors.
    names : tuple of str
        Layer names (their adapters' parts are the pick list).
    x, y : float
        VTK display position (origin bottom-left).
    tol : float
        Picker tolerance.

    Returns
    -------
    Hit or None
    """
    picker = vtkCellPicker()
    picker.SetTolerance(tol)
    picker.PickFromListOn()
    owners: dict[str, tuple[object, object]] = {}
    for n in names:
        if not view.model.layers[n].visible:
            continue
        for part in view.adapters[n].parts:
            if part.n_cells:
                picker.AddPickList(part.actor)
                owners[part.actor.GetAddressAsString("")] = (view.adapters[n], part)
    if not owners or not picker.Pick(x, y, 0, renderer) or picker.GetCellId() < 0:
        return None
    actor = picker.GetActor()
    owner = owners.get(actor.GetAddressAsString("")) if actor is not None else None
    if owner is None:
        return None
    adapter, part = owner
    got = adapter.pick(part, picker.GetCellId())
    if got is None:
        return None
    cam = renderer.GetActiveCamera()
    ray = np.asarray(cam.GetDirectionOfProjection())
    depth = float(np.dot(np.asarray(picker.GetPickPosition()) - np.asarray(cam.GetPosition()), ray))
    return Hit(got, depth)


def pick_visible(view, x: float, y: float) -> tuple[str, object] | None:
    """What the user sees under ``(x, y)``.

    The step overlay first, then M_S (and the other simplicial layers), then
    samples, by depth.

    A sample wins over a simplex only when it is not behind it: its depth may
    exceed the simplex's by at most half the median sample spacing (a visible
    sample is a vertex of the surface it sits on, so the two depths nearly
    agree; a sample on the far side lies a whole layer behind).
    """
    if not view.ready:
        return None
    top = pick_layers(view, view.top_renderer, ("step",), x, y, CELL_TOLERANCE)
    if top is not None:
        return top.got
    ren = view.plotter.renderer
    surface = pick_layers(view, ren, ("manifold", "removed", "candidates"), x, y, CELL_TOLERANCE)
    sample = pick_layers(view, ren, ("points",), x, y, POINT_TOLERANCE)
    if sample is None:
        return None if surface is None else surface.got
    if surface is None:
        return sample.got
    slack = 0.5 * float(np.median(view.model.spacing))  # projections never stretch distances
    return sample.got if sample.depth <= surface.depth + slack else surface.got
