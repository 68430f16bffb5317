"""PLY, ASCII and binary, in any dimension: :func:`read_ply` and :func:`write_ply`.

ASCII and binary (little- and big-endian).  The coordinates of a vertex are
its properties ``x, y[, z[, w]]`` or ``x0, x1, ... x(k-1)``.  Normals
(``nx ny nz``, ``normal_x ...``), colours (``red green blue``, ``r g b``,
``diffuse_red ...``; 8-bit integers or floats in [0, 1]) and an intensity
(``intensity``, ``scalar_intensity``) become the mesh's ``attributes``
(:mod:`crustview.attributes`); other vertex properties are ignored.  Polygons come from the ``face``
element's list property ``vertex_indices`` (or ``vertex_index``), segments
from an ``edge`` element's ``vertex1, vertex2``.  crustview writes binary
little-endian doubles: ``x y z`` (padded with zeros) for k <= 3,
``x y z w`` for k = 4 and ``x0 ... x(k-1)`` for k >= 5; d-simplices as
``face`` vertex lists of length d + 1 (segments too, as meshio does).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .mesh import MeshData, _bad, _blocks, _check_indices

_PLY_TYPES = {
    "char": "i1",
    "int8": "i1",
    "uchar": "u1",
    "uint8": "u1",
    "short": "i2",
    "int16": "i2",
    "ushort": "u2",
    "uint16": "u2",
    "int": "i4",
    "int32": "i4",
    "uint": "u4",
    "uint32": "u4",
    "float": "f4",
    "float32": "f4",
    "double": "f8",
    "float64": "f8",
}


@dataclass
class _Element:
    name: str
    count: int
    props: list[tuple[str, str, str | None]]  # (name, value type, list count type or None)


def _ply_header(data: bytes, path: Path) -> tuple[str, list[_Element], int]:
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise _bad(path, "it is not a PLY file (no 'ply' ... 'end_header' header)")
    stop = data.index(b"\n", end) + 1 if b"\n" in data[end:] else len(data)
    fmt = ""
    elements: list[_Element] = []
    for raw in data[:end].decode("ascii", "replace").splitlines()[1:]:
        words = raw.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        try:
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements.append(_Element(words[1], int(words[2]), []))
            elif words[0] == "property" and words[1] == "list":
                elements[-1].props.append((words[4], _PLY_TYPES[words[3]], _PLY_TYPES[words[2]]))
            elif words[0] == "property":
                elements[-1].props.append((words[2], _PLY_TYPES[words[1]], None))
            else:
                raise ValueError
        except (IndexError, KeyError, ValueError):
            raise _bad(path, f"its PLY header line {raw.strip()[:50]!r} is not understood") from None
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise _bad(path, f"its PLY format {fmt!r} is unknown")
    return fmt, elements, stop


def read_ply(path: Path) -> MeshData:
    """Read an ASCII or binary PLY with coordinates in any dimension (see the module docstring)."""
    data = path.read_bytes()
    fmt, elements, start = _ply_header(data, path)
    if fmt == "ascii":
        values = _ply_ascii(data[start:], elements, path)
    else:
        values = _ply_binary(data[start:], elements, "<" if fmt == "binary_little_endian" else ">", path)
    vert = values.get("vertex")
    if vert is None:
        raise _bad(path, "it has no 'vertex' element")
    names = list(vert)
    if "x0" in names:
        coords = [f"x{i}" for i in range(len(names)) if f"x{i}" in names]
        coords = coords[: next((i for i, c in enumerate(coords) if c != f"x{i}"), len(coords))]
    else:
        coords = []
        for c in ("x", "y", "z", "w"):
            if c not in names:
                break
            coords.append(c)
    if len(coords) < 2:
        raise _bad(path, "its vertices have no coordinate properties (x, y[, z[, w]] or x0, x1, ...)")
    points = np.column_stack([np.asarray(vert[c], dtype=np.float64) for c in coords])
    polys: list = []
    face = values.get("face", {})
    lst = face.get("vertex_indices", face.get("vertex_index"))
    if lst is not None:
        polys.extend(lst)
    edge = values.get("edge", {})
    if "vertex1" in edge and "vertex2" in edge:
        polys.extend(np.column_stack([edge["vertex1"], edge["vertex2"]]))
    cells = _blocks(polys)
    _check_indices(cells, len(points), path)
    from crustview.attributes import from_columns

    return MeshData(points, cells, path, from_columns(vert, len(coords), path))


def _ply_ascii(body: bytes, elements: list[_Element], path: Path) -> dict[str, dict[str, list]]:
    rows = [ln.split() for ln in body.decode("ascii", "replace").splitlines() if ln.strip()]
    out: dict[str, dict[str, list]] = {}
    r = 0
    for el in elements:
        if r + el.count > len(rows):
            raise _bad(path, f"it ends early in the '{el.name}' element")
        cols: dict[str, list] = {p[0]: [] for p in el.props}
        for row in rows[r : r + el.count]:
            j = 0
            try:
                for name, _typ, ltyp in el.props:
                    if ltyp is None:
                        cols[name].append(float(row[j]))
                        j += 1
                    else:
                        cnt = int(row[j])
                        cols[name].append([int(v) for v in row[j + 1 : j + 1 + cnt]])
                        if len(cols[name][-1]) != cnt:
                            raise IndexError
                        j += 1 + cnt
            except (IndexError, ValueError):
                raise _bad(path, f"a '{el.name}' line of the PLY data is malformed: {' '.join(row)[:50]!r}") from None
        r += el.count
        out[el.name] = cols
    return out


def _ply_binary(body: bytes, elements: list[_Element], endian: str, path: Path) -> dict[str, dict]:
    out: dict[str, dict] = {}
    off = 0
    for el in elements:
        lists = [p for p in el.props if p[2] is not None]
        try:
            if not lists:
                dt = np.dtype([(p[0], endian + p[1]) for p in el.props])
                arr = np.frombuffer(body, dtype=dt, count=el.count, offset=off)
                off += dt.itemsize * el.count
                out[el.name] = {p[0]: arr[p[0]] for p in el.props}
                continue
            out[el.name] = _ply_binary_lists(body, el, endian, off)
            off = out[el.name].pop("__end__")
        except (ValueError, IndexError):
            raise _bad(path, f"the binary PLY data ends early or is malformed in the '{el.name}' element") from None
    return out


def _ply_binary_lists(body: bytes, el: _Element, endian: str, off: int) -> dict:
    """An element with list properties: fast path when it is one list of constant length."""
    if len(el.props) == 1 and el.count:
        name, typ, ltyp = el.props[0]
        cnt = int(np.frombuffer(body, dtype=endian + ltyp, count=1, offset=off)[0])
        dt = np.dtype([("n", endian + ltyp), ("v", endian + typ, (cnt,))])
        if off + dt.itemsize * el.count <= len(body):
            arr = np.frombuffer(body, dtype=dt, count=el.count, offset=off)
            if (arr["n"] == cnt).all():
                return {name: arr["v"].astype(np.int64), "__end__": off + dt.itemsize * el.count}
    cols: dict = {p[0]: [] for p in el.props}
    for _ in range(el.count):
        for name, typ, ltyp in el.props:
            if ltyp is None:
                cols[name].append(np.frombuffer(body, dtype=endian + typ, count=1, offset=off)[0])
                off += np.dtype(typ).itemsize
            else:
                cnt = int(np.frombuffer(body, dtype=endian + ltyp, count=1, offset=off)[0])
                off += np.dtype(ltyp).itemsize
                cols[name].append(np.frombuffer(body, dtype=endian + typ, count=cnt, offset=off).astype(np.int64))
                if len(cols[name][-1]) != cnt:
                    raise ValueError
                off += np.dtype(typ).itemsize * cnt
    cols["__end__"] = off
    return cols


def ply_coordinate_names(k: int) -> list[str]:
    """Vertex property names crustview writes for points in R^k."""
    if k <= 3:
        return ["x", "y", "z"]
    if k == 4:
        return ["x", "y", "z", "w"]
    return [f"x{i}" for i in range(k)]


def write_ply(
    path: Path, points: np.ndarray, simplices: np.ndarray | None, *, comment: str = "", binary: bool = True
) -> None:
    """Write points (any k) and simplices as PLY (see the module docstring).

    Parameters
    ----------
    path : Path
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (m, d + 1) or None
        Written as the ``face`` element's vertex lists (segments as 2-vertex
        faces, as meshio writes them).
    comment : str
    binary : bool
        Binary little-endian (default) or ASCII.
    """
    points = np.asarray(points, dtype=np.float64)
    n, k = points.shape
    names = ply_coordinate_names(k)
    if k < 3:
        points = np.column_stack([points, np.zeros((n, 3 - k))])
    simp = np.empty((0, 3), np.int64) if simplices is None else np.asarray(simplices, np.int64)
    head = ["ply", f"format {'binary_little_endian' if binary else 'ascii'} 1.0"]
    if comment:
        head.append(f"comment {comment}")
    head.append(f"element vertex {n}")
    head += [f"property double {c}" for c in names]
    if len(simp):
        head += [f"element face {len(simp)}", "property list uchar int vertex_indices"]
    head.append("end_header")
    with open(path, "wb") as fh:
        fh.write(("\n".join(head) + "\n").encode("ascii"))
        if binary:
            fh.write(points.astype("<f8").tobytes())
            if len(simp):
                rec = np.empty(len(simp), dtype=[("n", "u1"), ("v", "<i4", (simp.shape[1],))])
                rec["n"], rec["v"] = simp.shape[1], simp
                fh.write(rec.tobytes())
        else:
            np.savetxt(fh, points, fmt="%.17g")
            if len(simp):
                np.savetxt(fh, np.column_stack([np.full(len(simp), simp.shape[1]), simp]), fmt="%d")
