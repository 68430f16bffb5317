"""The camera of a pyvista plotter as plain numbers, and back (session files, exports)."""

from __future__ import annotations

import numpy as np


def camera_state(plotter) -> dict:
    """Position, focal point, up vector, view angle, parallel projection and window centre of the camera."""
    cam = plotter.renderer.GetActiveCamera()
    return {
        "position": [float(v) for v in cam.GetPosition()],
        "focal_point": [float(v) for v in cam.GetFocalPoint()],
        "up": [float(v) for v in cam.GetViewUp()],
        "view_angle": float(cam.GetViewAngle()),
        "parallel": bool(cam.GetParallelProjection()),
        "parallel_scale": float(cam.GetParallelScale()),
        "window_center": [float(v) for v in cam.GetWindowCenter()],
    }


def set_camera_state(plotter, state: dict) -> None:
    """Put ``plotter``'s camera where :func:`camera_state` found it.

    Raises
    ------
    ValueError
        When the position and the focal point coincide or the up vector is
        zero or along the view direction (VTK would draw nothing sensible).
    """
    pos, focus, up = (np.asarray(state[k], dtype=float) for k in ("position", "focal_point", "up"))
    view = focus - pos
    if np.linalg.norm(view) < 1e-12:
        raise ValueError("the saved camera sits on its focal point")
    if np.linalg.norm(np.cross(view, up)) < 1e-9 * np.linalg.norm(view) * max(np.linalg.norm(up), 1e-300):
        raise ValueError("the saved camera's up vector is zero or along its view direction")
    cam = plotter.renderer.GetActiveCamera()
    cam.SetParallelProjection(bool(state.get("parallel", False)))
    cam.SetPosition(*pos)
    cam.SetFocalPoint(*focus)
    cam.SetViewUp(*up)
    cam.SetViewAngle(float(state.get("view_angle", 30.0)))
    cam.SetWindowCenter(*(state.get("window_center") or (0.0, 0.0)))
    if state.get("parallel_scale"):
        cam.SetParallelScale(float(state["parallel_scale"]))
    plotter.renderer.ResetCameraClippingRange()
