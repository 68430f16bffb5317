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
import io
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
    except (KeyboardInterrupt, SystemExit, GeneratorExit):
        raise
    except BaseException as err:  # noqa: BLE001 - any library failure (a Rust panic too) is one sentence
        text = " ".join(str(err).split())[:120] or type(err).__name__
        raise InputError(f"Cannot read '{path}' as a {suffix} file ({text}).") from None


#: The most a compressed point record can shrink (LZF, LAZ, E57 bit packing): bounds what a header may declare.
MAX_RATIO = 256


def _check_size(path: Path, declared: int, item: float, ratio: float = 1.0) -> None:
    """Refuse a header that declares more points than the file can hold (before anything is allocated for them).

    ``item`` is the least number of bytes a point takes in the file when
    stored plainly, ``ratio`` how much compression may shrink it.
    """
    size = path.stat().st_size
    if declared < 0 or declared * item > size * ratio:
        raise InputError(
            f"Cannot read '{path}': its header declares {declared} points, more than its {size} bytes can hold."
        )


def _check_pcd(path: Path) -> None:
    """The PCD header's point count against the file size, and a compressed block's declared size."""
    from pypcd4.pypcd4 import MetaData

    data = path.read_bytes()
    lines, start = [], 0
    while start < len(data) and len(lines) < 10:  # as pypcd4 reads it: ten header lines at most
        end = data.find(b"\n", start)
        end = len(data) if end < 0 else end + 1
        line = data[start:end].decode("utf-8").strip()
        start = end
        if line and not line.startswith("#"):
            lines.append(line)
            if line.startswith("DATA"):
                break
    meta = MetaData.parse_header(lines)
    # the row size from the header itself: pypcd4's dtype has one field per counted value, so a
    # header with COUNT 1111111 would build a million fields (hundreds of MiB) before any check
    row = int(sum(int(a) * int(b) for a, b in zip(meta.size, meta.count)))
    if row > len(data):
        raise InputError(f"Cannot read '{path}': its header declares {row} bytes per point, more than the file holds.")
    if meta.data.value == "ascii":
        _check_size(path, meta.points, 2 * sum(meta.count))  # a digit and a separator per value
    elif meta.data.value == "binary":
        _check_size(path, meta.points, row)
    else:
        _check_size(path, meta.points, row, MAX_RATIO)
        sizes = np.frombuffer(data[start : start + 8], dtype="<u4")
        if len(sizes) == 2 and sizes[1] > MAX_RATIO * len(data):
            raise InputError(
                f"Cannot read '{path}': its compressed data declares {int(sizes[1])} bytes, "
                f"more than its {len(data)} bytes can hold."
            )


def _read_pcd(pypcd4, path: Path):
    _check_pcd(path)
    pc = pypcd4.PointCloud.from_fileobj(io.BytesIO(path.read_bytes()))
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
    # from memory: a damaged header's lengths then cannot make laspy allocate more than the file
    data = io.BytesIO(path.read_bytes())
    _check_las_header(path, data.getvalue())
    with laspy.open(data, laz_backend=laspy.LazBackend.Lazrs) as reader:
        header = reader.header
        compressed = path.suffix.lower() == ".laz" or header.are_points_compressed
        _check_size(path, int(header.point_count), header.point_format.size, MAX_RATIO if compressed else 1)
        if compressed:
            _check_chunk_table(path, data.getvalue(), int(header.offset_to_point_data), int(header.point_count))
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


def _check_las_header(path: Path, data: bytes) -> None:
    """Refuse record counts of the LAS public header that the file cannot hold (laspy would loop over each).

    ``number_of_vlrs`` is the little-endian u32 at byte 100 (a VLR header
    is 54 bytes); LAS 1.4 has ``number_of_evlrs`` at byte 243 (60 bytes each).
    """
    if len(data) < 104 or data[:4] != b"LASF":
        return  # laspy says what is wrong
    vlrs = int(np.frombuffer(data[100:104], dtype="<u4")[0])
    evlrs = int(np.frombuffer(data[243:247], dtype="<u4")[0]) if len(data) >= 247 and data[25] >= 4 else 0
    if vlrs * 54 > len(data) or evlrs * 60 > len(data):
        raise InputError(
            f"Cannot read '{path}': its header declares {vlrs} VLRs and {evlrs} extended VLRs, "
            f"more than its {len(data)} bytes hold."
        )


def _check_chunk_table(path: Path, data: bytes, start: int, points: int) -> None:
    """Refuse a LAZ chunk table that declares more chunks than points or bytes (lazrs would abort allocating it).

    The point data of a LAZ file begins with the offset of its chunk table,
    which begins with a version and the number of chunks (little-endian).
    """
    head = np.frombuffer(data[start : start + 8], dtype="<i8")
    if len(head) == 0 or head[0] < 0 or head[0] + 8 > len(data):
        return  # no chunk table (written while streaming): lazrs does not read one
    version, chunks = (int(v) for v in np.frombuffer(data[head[0] : head[0] + 8], dtype="<u4"))
    if chunks > max(points, 1) or chunks > 8 * len(data):
        raise InputError(
            f"Cannot read '{path}': its LAZ chunk table declares {chunks} chunks for {points} points "
            f"in {len(data)} bytes (version {version})."
        )


def _read_e57(pye57, path: Path):
    e57 = pye57.E57(str(path))
    try:
        parts, attrs = [], []
        for i in range(e57.scan_count):
            header = e57.get_header(i)
            _check_size(path, int(header.point_count), 1 / 8)  # bit-packed fields: a few bits per point
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
