"""What scanner files carry besides coordinates, and the file's normals held against AN_s.

A reader gives a dict of per-point arrays (one row per input point):

``colors``
    (n, 3) float in [0, 1] (8- or 16-bit integers are scaled).
``intensity``
    (n,) float, as stored.
``normals``
    (n, k) float: the scanner's (or the mesh tool's) normal at each point.

:func:`normal_angles` measures, per sample, the angle between the file's
normal and the reconstruction's approximate normal plane AN_s
(``rec.normals``, Algorithm 1): 0 where the normal lies in AN_s, 90° where it
is orthogonal to it.  :func:`report_section` is the report's
``input_attributes`` key.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crustview.core.errors import InputError

#: Property names of each attribute, in the order tried (PLY, PCD and E57 spellings).
NORMAL_NAMES = (("nx", "ny", "nz"), ("normal_x", "normal_y", "normal_z"), ("normalx", "normaly", "normalz"))
COLOR_NAMES = (
    ("red", "green", "blue"),
    ("r", "g", "b"),
    ("diffuse_red", "diffuse_green", "diffuse_blue"),
    ("colorRed", "colorGreen", "colorBlue"),
)
INTENSITY_NAMES = ("intensity", "scalar_intensity", "scalar_Intensity", "Intensity")
#: Bins of the normal-angle histogram (degrees).
ANGLE_BINS = np.arange(0.0, 90.0 + 1e-9, 5.0)


def colors_to_unit(values: np.ndarray) -> np.ndarray:
    """Colours as floats in [0, 1]: 8-bit (or 16-bit, by their range) integers scaled, floats clipped."""
    arr = np.asarray(values)
    if arr.dtype.kind in "iu":
        top = 65535.0 if arr.size and arr.max() > 255 else 255.0
        return np.clip(arr.astype(np.float64) / top, 0.0, 1.0)
    arr = arr.astype(np.float64)
    if arr.size and np.nanmax(arr) > 1.0:  # floats written as 0..255
        arr = arr / (65535.0 if np.nanmax(arr) > 255 else 255.0)
    return np.clip(np.nan_to_num(arr, nan=0.0), 0.0, 1.0)


def from_columns(columns: dict, k: int, path: Path | None = None) -> dict[str, np.ndarray]:
    """The attributes among named per-point columns (a PLY vertex element, a PCD's fields ...)."""
    out: dict[str, np.ndarray] = {}
    names = set(columns)
    for triple in COLOR_NAMES:
        if set(triple) <= names:
            out["colors"] = colors_to_unit(np.column_stack([np.asarray(columns[c]) for c in triple]))
            break
    for name in INTENSITY_NAMES:
        if name in names:
            out["intensity"] = np.asarray(columns[name], dtype=np.float64)
            break
    for triple in NORMAL_NAMES:
        if set(triple) <= names and k == 3:
            out["normals"] = np.column_stack([np.asarray(columns[c], dtype=np.float64) for c in triple])
            break
    return out


def check(attributes: dict, n: int, path: Path) -> dict[str, np.ndarray]:
    """Attributes with one row per point, or an InputError naming the file."""
    for name, arr in attributes.items():
        if len(arr) != n:
            raise InputError(f"Cannot use '{path}': it has {len(arr)} {name} values for {n} points.")
    return attributes


def normal_angles(rec, normals: np.ndarray) -> np.ndarray:
    """Angle (degrees) per input point between the file's normal and AN_s; NaN where the normal is zero.

    Parameters
    ----------
    rec : Reconstruction
    normals : ndarray of shape (n_input, k)

    Returns
    -------
    ndarray of shape (n_input,)
    """
    v = np.asarray(normals, dtype=np.float64)
    basis = np.asarray(rec.normals)[np.asarray(rec.input_index)]  # (n_input, k, k - d)
    if v.shape != basis.shape[:2]:
        raise InputError(f"The file's normals have shape {v.shape}, the points {basis.shape[:2]}.")
    length = np.linalg.norm(v, axis=1)
    inside = np.linalg.norm(np.einsum("nkj,nk->nj", basis, v), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.clip(inside / length, 0.0, 1.0)
    angles = np.degrees(np.arccos(cos))
    angles[~(length > 0) | ~np.isfinite(length)] = np.nan
    return angles


def angle_summary(angles: np.ndarray) -> dict:
    """Median, 90th percentile, count over 30 degrees and a 5-degree histogram of the angles."""
    ok = angles[np.isfinite(angles)]
    counts, edges = np.histogram(ok, bins=ANGLE_BINS)
    if not len(ok):
        return {"n": 0, "histogram": {"edges_degrees": edges.tolist(), "counts": counts.tolist()}}
    return {
        "n": int(len(ok)),
        "missing": int(len(angles) - len(ok)),
        "median_degrees": float(np.median(ok)),
        "mean_degrees": float(np.mean(ok)),
        "p90_degrees": float(np.percentile(ok, 90)),
        "over_30_degrees": int(np.count_nonzero(ok > 30.0)),
        "histogram": {"edges_degrees": edges.tolist(), "counts": counts.tolist()},
    }


def report_section(rec, attributes: dict) -> dict:
    """The report's ``input_attributes``: which attributes the file had, and the normal angles."""
    out: dict = {"colors": "colors" in attributes, "normals": "normals" in attributes}
    if "intensity" in attributes:
        inten = np.asarray(attributes["intensity"], dtype=np.float64)
        out["intensity"] = {"min": float(np.nanmin(inten)), "max": float(np.nanmax(inten))}
    if "normals" in attributes and attributes["normals"].shape[1] == rec.k:
        out["normal_angles"] = angle_summary(normal_angles(rec, attributes["normals"]))
    return out
