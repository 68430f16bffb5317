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


def flat_note(path: str | os.PathLike, points: np.ndarray, suffixes: tuple[str, ...]) -> str | None:
    """The note for a mesh file (a suffix in ``suffixes``) read in R^2 because its z is 0 everywhere, else None.

    Says too when its faces (triangles, polygons: regions of the plane) are not used.  A file that is 2-D
    itself (an nOFF of dimension 2) gets none.
    """
    path = Path(path)
    if np.shape(points)[1:] != (2,) or path.suffix.lower() not in suffixes:
        return None
    from . import read_mesh

    raw = read_mesh(path)
    if np.shape(raw.points)[1:] != (3,):
        return None
    note = (
        f"{path.name}: the third coordinate is 0 at every vertex, so its points are read as points in R^2 "
        "(a curve there has d = 1)"
    )
    if raw.n_cells and min(block.shape[1] for block in raw.cells) >= 3:
        note += "; its faces, regions of that plane, are not a curve's and are not used (its vertices are the sample)"
    return note + "."
