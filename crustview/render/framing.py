"""Framing one step of Algorithm 3: look at tau from its open side, cut away what is in front.

The camera looks along the normal of the step's simplices (in the view's
3-D projection), from the side with less geometry close in front of tau.
Everything farther than a margin in front of tau is clipped by one plane
on the scene's actors (not on the overlay, which holds the step itself), so
the step is never drawn over unrelated surface.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkPlane


@dataclass(frozen=True)
class StepFrame:
    """Where the camera goes for one step.

    Attributes
    ----------
    focus : ndarray of shape (3,)
        Centroid of tau in view space.
    direction : ndarray of shape (3,)
        Unit vector from the focus towards the camera.
    up : ndarray of shape (3,)
        Camera up vector (orthogonal to ``direction``).
    radius : float
        Half the size of the region to show.
    margin : float
        Geometry farther than this in front of the focus is cut away.
    """

    focus: np.ndarray
    direction: np.ndarray
    up: np.ndarray
    radius: float
    margin: float


def step_normal(pts: np.ndarray) -> np.ndarray:
    """Direction of least spread of ``pts`` (m, 3): the normal of a nearly flat patch."""
    centred = pts - pts.mean(axis=0)
    if len(pts) < 3:
        return np.array([0.0, 0.0, 1.0])
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return vt[-1] / np.linalg.norm(vt[-1])


def frame_for(
    proj: np.ndarray, tau: np.ndarray, patch: np.ndarray, spacing: float, centre: np.ndarray, up_hint: np.ndarray
) -> StepFrame:
    """Camera frame for a step.

    Parameters
    ----------
    proj : ndarray of shape (n, 3)
        Every sample in view space.
    tau : ndarray of int
        The step's face (sample indices).
    patch : ndarray of int
        Samples of the step's simplices (tau's neighbourhood).
    spacing : float
        Typical sample spacing (view units).
    centre : ndarray of shape (3,)
        Centre of the data: with equal clutter on both sides, the camera goes outside.
    up_hint : ndarray of shape (3,)
        The current camera up vector, kept where possible.
    """
    focus = proj[tau].mean(axis=0)
    pts = proj[np.unique(np.concatenate([tau, patch]))]
    radius = max(float(np.max(np.linalg.norm(pts - focus, axis=1))), 2.5 * spacing)
    margin = 1.5 * spacing
    n = step_normal(pts)
    # clutter: samples within a few radii of the axis, in front of tau but not yet cut away
    rel = proj - focus
    along = rel @ n
    across = np.linalg.norm(rel - np.outer(along, n), axis=1)
    near_axis = across < 2.0 * radius
    front_plus = int(np.count_nonzero(near_axis & (along > 0.3 * spacing) & (along < margin)))
    front_minus = int(np.count_nonzero(near_axis & (along < -0.3 * spacing) & (along > -margin)))
    outward = float(np.dot(focus - centre, n)) >= 0
    sign = 1.0 if (front_plus, not outward) < (front_minus, outward) else -1.0
    direction = sign * n
    up = up_hint - np.dot(up_hint, direction) * direction
    if np.linalg.norm(up) < 1e-6:
        alt = np.array([1.0, 0.0, 0.0]) if abs(direction[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        up = alt - np.dot(alt, direction) * direction
    return StepFrame(focus, direction, up / np.linalg.norm(up), radius, margin)


def front_plane(frame: StepFrame) -> vtkPlane:
    """The plane that keeps what lies behind ``frame.margin`` in front of the focus."""
    plane = vtkPlane()
    plane.SetOrigin(*(frame.focus + frame.margin * frame.direction))
    plane.SetNormal(*(-frame.direction))  # VTK keeps the side the normal points to
    return plane


def place_camera(camera, frame: StepFrame) -> None:
    """Put a vtkCamera (perspective) on ``frame``, with the region filling the view."""
    half = np.radians(camera.GetViewAngle()) / 2
    dist = 2.2 * frame.radius / np.tan(half) + frame.margin
    camera.SetWindowCenter(0.0, 0.0)  # a reset may have shifted the image clear of the legend
    camera.SetFocalPoint(*frame.focus)
    camera.SetPosition(*(frame.focus + dist * frame.direction))
    camera.SetViewUp(*frame.up)
