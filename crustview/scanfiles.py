"""Scanner point clouds through their own libraries: PCL's PCD, LiDAR LAS/LAZ and E57.

Each reader returns the points (n, 3) and their attributes
(:mod:`crustview.attributes`: ``colors``, ``intensity``, ``normals``).  The
libraries are the optional extra ``crustview[scans]`` (the test extra
installs them): ``pypcd4`` for ``.pcd``, ``laspy`` with the ``lazrs`` codec
for ``.las``/``.laz``, ``pye57`` for ``.e57``.  Without one, reading that
suffix is one InputError saying what to install; any failure inside a
library is one InputError naming the file.
"""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np

from crustview.attributes import colors_to_unit, from_columns
from crustview.core.errors import InputError

#: Suffixes read here, and the module each needs.
SCAN_SUFFIXES = (".pcd", ".las", ".laz", ".e57")
_NEEDS = {".pcd": "pypcd4", ".las": "laspy", ".laz": "laspy", ".e57": "pye57"}


def _library(path: Path):
    name = _NEEDS[path.suffix.lower()]
    try:
        return importlib.import_module(name)
    except ImportError:
        raise InputError(
            f"Cannot read '{path}': {path.suffix.lower()} files need the '{name}' package "
            "(pip install 'crustview[scans]')."
        ) from None


def read_scan(path: Path) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Points and attributes of a ``.pcd``, ``.las``, ``.laz`` or ``.e57`` file."""
    path = Path(path)
    suffix = path.suffix.lower()
    lib = _library(path)
    reader = {".pcd": _read_pcd, ".las": _read_las, ".laz": _read_las, ".e57": _read_e57}[suffix]
    try:
        with np.errstate(all="ignore"):
            return reader(lib, path)
    except InputError:
        raise
    except MemoryError:
        raise InputError(f"Cannot read '{path}': it declares more data than fits in memory.") from None
    except Exception as err:  # noqa: BLE001 - any library failure is one sentence
        text = " ".join(str(err).split())[:120] or type(err).__name__
        raise InputError(f"Cannot read '{path}' as a {suffix} file ({text}).") from None


def _check_size(path: Path, declared: int, item: int) -> None:
    """Refuse a header that declares more points than the file can hold (before allocating them)."""
    size = path.stat().st_size
    if declared < 0 or declared * max(item, 1) > size:
        raise InputError(
            f"Cannot read '{path}': its header declares {declared} points, more than its {size} bytes can hold."
        )


def _read_pcd(pypcd4, path: Path):
    from pypcd4.pypcd4 import MetaData

    with open(path, "rb") as fh:
        header = []
        while len(header) < 64:
            line = fh.readline(4096)
            if not line:
                break
            header.append(line.decode("ascii", "replace").strip())
            if line.startswith(b"DATA"):
                break
    meta = MetaData.parse_header(header)
    _check_size(path, int(meta.points), 1)
    pc = pypcd4.PointCloud.from_path(path)
    fields = list(pc.fields)
    if not {"x", "y", "z"} <= set(fields):
        raise InputError(f"Cannot read '{path}': its fields ({', '.join(fields)}) have no x y z.")
    data = pc.numpy()
    cols = {name: data[:, i] for i, name in enumerate(fields)}
    points = np.column_stack([cols["x"], cols["y"], cols["z"]]).astype(np.float64)
    attributes = from_columns(cols, 3, path)
    if "rgb" in fields or "rgba" in fields:
        packed = cols.get("rgb", cols.get("rgba"))
        attributes["colors"] = colors_to_unit(pypcd4.PointCloud.decode_rgb(np.asarray(packed, dtype=np.float32)))
    return points, attributes


def _read_las(laspy, path: Path):
    with laspy.open(path) as reader:
        header = reader.header
        _check_size(path, int(header.point_count), 1)
        las = reader.read()
    points = np.column_stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)]).astype(np.float64)
    names = set(las.point_format.dimension_names)
    attributes: dict[str, np.ndarray] = {}
    if {"red", "green", "blue"} <= names:
        rgb = np.column_stack([np.asarray(las.red), np.asarray(las.green), np.asarray(las.blue)])
        attributes["colors"] = np.clip(rgb.astype(np.float64) / (65535.0 if rgb.max(initial=0) > 255 else 255.0), 0, 1)
    if "intensity" in names:
        attributes["intensity"] = np.asarray(las.intensity, dtype=np.float64)
    extra = {name: np.asarray(las[name]) for name in las.point_format.extra_dimension_names}
    attributes.update({k: v for k, v in from_columns(extra, 3, path).items() if k == "normals"})
    return points, attributes


def _read_e57(pye57, path: Path):
    e57 = pye57.E57(str(path))
    try:
        parts, attrs = [], []
        for i in range(e57.scan_count):
            header = e57.get_header(i)
            _check_size(path, int(header.point_count), 1)
            scan = e57.read_scan(i, intensity=True, colors=True, transform=True, ignore_missing_fields=True)
            xyz = np.column_stack([scan["cartesianX"], scan["cartesianY"], scan["cartesianZ"]]).astype(np.float64)
            parts.append(xyz)
            attrs.append(from_columns({k: v for k, v in scan.items() if len(v) == len(xyz)}, 3, path))
    finally:
        close = getattr(e57, "close", None)
        if close is not None:
            close()
    if not parts:
        raise InputError(f"Cannot read '{path}': it holds no scan.")
    points = np.concatenate(parts)
    keys = set.intersection(*(set(a) for a in attrs))
    attributes = {k: np.concatenate([a[k] for a in attrs]) for k in keys}
    if "colors" in attributes:
        attributes["colors"] = colors_to_unit(attributes["colors"])
    return points, attributes
