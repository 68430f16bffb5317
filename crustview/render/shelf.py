"""The shown result set aside while another file's raw points are previewed.

Opening a second file used to leave the first file's result on screen (its mesh, its red "WRONG" banner, its
legend) for the whole of the new run, with the new file's points nowhere: what a file shows the moment it
opens was another file's verdict.  :func:`shelve` hides every prop of the scene, the overlay and the HUD, and
remembers which were shown; the preview is added after it.  :func:`unshelve` shows them again: when the new
result arrives (its layers then rebuild from the state they had, as before) and when the run is cancelled or
fails (the previous result is kept, and said so).
"""

from __future__ import annotations


def _renderers(view) -> list:  # noqa: ANN001 - a SceneView (render/view.py imports this module)
    out = [view.plotter.renderer]
    out += [r for r in (getattr(view, "top_renderer", None), getattr(view, "hud", None)) if r is not None]
    return out


def shelve(view) -> None:  # noqa: ANN001
    """Hide every prop that is shown in the view's renderers; a second call while shelved does nothing."""
    if getattr(view, "shelved", None) is not None:
        return
    shown = []
    for renderer in _renderers(view):
        props = renderer.GetViewProps()
        props.InitTraversal()
        for _ in range(props.GetNumberOfItems()):
            prop = props.GetNextProp()
            if prop is not None and prop.GetVisibility():
                prop.VisibilityOff()
                shown.append(prop)
    view.shelved = shown


def unshelve(view) -> bool:  # noqa: ANN001
    """Show again what :func:`shelve` hid; returns whether anything was shelved."""
    shown = getattr(view, "shelved", None)
    view.shelved = None
    for prop in shown or ():
        prop.VisibilityOn()
    return shown is not None
