"""Colourings of the samples by what their file carried: its colours, its intensity, its normals (Qt-free).

The attributes (:mod:`crustview.attributes`) have one row per *input* point;
the samples layer draws the prepared points (``rec.points``), so every value
is taken at ``rec.point_input``.  ``file normal angle`` is the angle between
the file's normal and AN_s (:func:`crustview.attributes.normal_angles`).
"""

from __future__ import annotations

import numpy as np

#: The colourings, offered only when the opened file has the attribute.
FILE_COLORINGS = ("file colours", "file intensity", "file normal angle")
#: The attribute each colouring needs.
NEEDS = {"file colours": "colors", "file intensity": "intensity", "file normal angle": "normals"}


def applies(rec, attributes: dict, how: str) -> bool:
    """Whether ``how`` can colour this reconstruction (the attribute is there, one row per input point)."""
    need = NEEDS.get(how)
    if rec is None or need not in attributes or len(attributes[need]) != len(rec.input_points):
        return False
    return need != "normals" or attributes[need].shape[1] == rec.k


def input_angles(rec, attributes: dict) -> np.ndarray | None:
    """The angle (degrees) between the file's normal and AN_s at each input point, or None."""
    if not applies(rec, attributes, "file normal angle"):
        return None
    from crustview.attributes import normal_angles

    return normal_angles(rec, attributes["normals"])


def file_values(rec, attributes: dict, how: str) -> tuple[np.ndarray, str] | None:
    """Per sample: (n, 3) colours in [0, 1] for ``file colours``, else a scalar, with a label; None when absent."""
    if not applies(rec, attributes, how):
        return None
    rows = np.asarray(rec.point_input)
    if how == "file colours":
        return np.asarray(attributes["colors"], dtype=float)[rows], "colours of the file"
    if how == "file intensity":
        return np.asarray(attributes["intensity"], dtype=float)[rows], "intensity of the file"
    return input_angles(rec, attributes)[rows], "file normal vs AN_s (deg)"


def angle_histogram(rec, attributes: dict) -> dict | None:
    """The Information panel's histogram: :func:`crustview.attributes.angle_summary` of the angles, or None."""
    angles = input_angles(rec, attributes)
    if angles is None:
        return None
    from crustview.attributes import angle_summary

    return angle_summary(angles)
