"""Mesh files whose third coordinate is 0 everywhere: planar data, read as points in R^2.

:func:`crustview.io.write_points` pads planar data to 3-D in the mesh formats, so reading drops a zero third
column again; a flat mesh's triangles or polygons are then regions of the plane, no curve's truth, and its
vertices are a point sample (:func:`crustview.io.read_mesh`).  :func:`flat_note` says so to the user.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np


def drop_zero_z(points: np.ndarray) -> np.ndarray:
    """``points`` without its third column where that column is 0 everywhere (3-D points only)."""
    points = np.asarray(points)
    if points.ndim == 2 and points.shape[1] == 3 and len(points) and not points[:, 2].any():
        return points[:, :2]
    return points


def flat_note(path: str | os.PathLike, raw) -> str | None:
    """The note for a mesh read in R^2 because its third coordinate is 0 everywhere, else None.

    ``raw`` is the file's :class:`~crustview.meshfiles.mesh.MeshData` as read (its points before the drop).
    Says too when its faces (triangles, polygons: regions of the plane) are not used.  A file that is 2-D
    itself (an nOFF of dimension 2) gets none.
    """
    if drop_zero_z(raw.points).shape[1:] != (2,) or np.shape(raw.points)[1:] != (3,):
        return None
    note = (
        f"{Path(path).name}: the third coordinate is 0 at every vertex, so its points are read as points in R^2 "
        "(a curve there has d = 1)"
    )
    if raw.n_cells and min(block.shape[1] for block in raw.cells) >= 3:
        note += "; its faces, regions of that plane, are not a curve's and are not used (its vertices are the sample)"
    return note + "."
