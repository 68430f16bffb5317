"""What a result ``.npz`` remembers of the truth it was judged against: a built-in's description or a mesh's faces.

A reopened result shows the verdict it had when it was written: a built-in sample is drawn again from its
description (:func:`crustview.scene.truth.builtin_truth`), and a mesh's faces are stored with the result
(``truth_name``, ``truth_faces`` on input rows), so a result that contradicted its mesh still says WRONG
(a new user reopened the foot bones' red result and saw it amber).
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: The keys of a built-in sample's description in a result ``.npz`` (after ``builtin_``) and their types.
BUILTIN_FIELDS = {"n": int, "seed": int, "noise": float, "density": str, "method": str}


def builtin_arrays(builtin: dict[str, Any] | None) -> dict[str, np.ndarray]:
    """The ``.npz`` members of a built-in sample's description (none without one)."""
    if not builtin:
        return {}
    out = {"builtin": np.str_(builtin["name"])}
    for key, kind in BUILTIN_FIELDS.items():
        value = builtin.get(key)
        if value is not None:
            out[f"builtin_{key}"] = np.str_(value) if kind is str else np.asarray(kind(value))
    return out


def builtin_of(archive) -> dict[str, Any] | None:
    """A built-in sample's description from an open ``.npz``, or None."""
    if "builtin" not in archive:
        return None
    out: dict[str, Any] = {"name": str(archive["builtin"])}
    for key, kind in BUILTIN_FIELDS.items():
        if f"builtin_{key}" in archive:
            out[key] = kind(archive[f"builtin_{key}"].item() if kind is not str else archive[f"builtin_{key}"])
    return out


def mesh_arrays(mesh: tuple[str, np.ndarray] | None, n_points: int, d: int) -> dict[str, np.ndarray]:
    """The ``.npz`` members of a mesh truth ``(file name, faces on input rows)`` (none without one).

    Faces that do not fit (another d, rows beyond the points) are not stored: they could not be the truth.
    """
    if mesh is None:
        return {}
    name, faces = mesh
    faces = np.asarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != d + 1 or len(faces) == 0 or faces.min() < 0 or faces.max() >= n_points:
        return {}
    return {"truth_name": np.str_(name), "truth_faces": faces}


def mesh_of(archive, n_points: int, d: int) -> tuple[str, np.ndarray] | None:
    """The mesh truth ``(file name, faces)`` stored in an open ``.npz``, or None.

    None too for members that are not a name and a non-empty integer face table on these points for this ``d``
    (an old or altered archive still opens, without its truth).
    """
    if "truth_faces" not in archive or "truth_name" not in archive:
        return None
    try:  # a member that is not what write_result stores is ignored, as faces that do not fit are
        name, faces = archive["truth_name"], np.asarray(archive["truth_faces"])
    except ValueError:  # e.g. an object array, which allow_pickle=False refuses
        return None
    if name.dtype.kind != "U" or name.ndim != 0 or faces.dtype.kind not in "iu" or faces.ndim != 2:
        return None
    if faces.shape[1] != d + 1 or len(faces) == 0 or faces.min() < 0 or faces.max() >= n_points:
        return None
    return str(name), faces.astype(np.int64)
