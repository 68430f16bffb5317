"""Mesh files with faces, in any dimension: Geomview OFF/nOFF, PLY, and the rest via meshio.

:func:`read_mesh` returns the vertices and the polygons (or simplices) of a
mesh file; :func:`write_off` and :func:`write_ply` write points and
simplices in any ambient dimension k.  Every failure is one
:class:`~crustview.core.errors.InputError` sentence naming the file.

OFF (Geomview's definition)
---------------------------
The header keyword is ``[ST][C][N][4][n]OFF``, optionally followed by
``BINARY``.  The keyword is case-sensitive: ``N`` means per-vertex normals
(3 numbers, skipped), ``n`` means n-dimensional, ``C`` a colour (4 numbers,
skipped), ``ST`` texture coordinates (2 numbers, skipped).

* ``nOFF`` has a line with the dimension Ndim before the counts, and each
  vertex has Ndim coordinates.
* ``4OFF`` vertices have 4 components, the last one *homogeneous*: the point
  in R^3 is ``(x/w, y/w, z/w)``; ``4nOFF`` vertices have Ndim + 1 components,
  the last homogeneous.  A zero homogeneous component (a point at infinity) is
  an error.
* The counts line is ``NVertices NFaces NEdges`` (NEdges is not used).  A
  ``4OFF`` whose counts line has four numbers is Stella4D's different 4-D
  polytope format (faces *and* cells); it is reported as unsupported.
* Each face is ``Nv v0 ... v(Nv-1) [colour]`` on one line; the colour (up to
  4 numbers after the indices) is ignored.
* ``BINARY``: after the header line every number is big-endian, int32 for
  counts, dimension and indices, float32 for coordinates; each face is
  ``Nv``, the Nv indices, then ``Ncolour`` and Ncolour float32 values.
* ``#`` starts a comment.  The keyword may be missing (plain 3-D OFF).

crustview writes ``OFF`` for k <= 3 (points padded to 3-D, as other programs
expect) and ``nOFF`` with Ndim = k otherwise, or always with
:func:`write_off` ``(..., ndim=True)`` (the ``.noff`` suffix).

PLY
---
ASCII and binary (little- and big-endian).  The coordinates of a vertex are
its properties ``x, y[, z[, w]]`` or ``x0, x1, ... x(k-1)``; other vertex
properties (normals, colours) are ignored.  Polygons come from the ``face``
element's list property ``vertex_indices`` (or ``vertex_index``), segments
from an ``edge`` element's ``vertex1, vertex2``.  crustview writes binary
little-endian doubles: ``x y z`` (padded with zeros) for k <= 3,
``x y z w`` for k = 4 and ``x0 ... x(k-1)`` for k >= 5; d-simplices as
``face`` vertex lists of length d + 1 (segments too, as meshio does).
"""

from __future__ import annotations

import os
import re
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import dataclass
from io import StringIO
from pathlib import Path

import numpy as np

from crustview.core.errors import InputError

_OFF_KEY = re.compile(r"^(ST)?(C)?(N)?(4)?(n)?OFF$")


@dataclass(frozen=True)
class MeshData:
    """Vertices and polygons read from a mesh file.

    Attributes
    ----------
    points : ndarray of shape (n, k)
    cells : list of ndarray
        Blocks of polygons, each of shape (m_i, s_i): s_i vertex indices
        (0-based, checked to be in range) per polygon.
    path : Path
    """

    points: np.ndarray
    cells: list[np.ndarray]
    path: Path

    @property
    def n_cells(self) -> int:
        """Number of polygons in all blocks."""
        return int(sum(len(c) for c in self.cells))

    def simplices(self, d: int) -> np.ndarray:
        """The polygons as d-simplices, shape (m, d + 1).

        For d = 2, polygons with more than three vertices (quads ...) are split
        into a fan of triangles from their first vertex, which is exact for
        convex planar polygons.  Otherwise every polygon must have exactly
        d + 1 vertices.

        Raises
        ------
        InputError
            Polygons of a size that does not fit ``d``, or with a repeated vertex.
        """
        out = []
        for block in self.cells:
            s = block.shape[1]
            if d == 2 and s > 3:
                fan = [block[:, [0, i, i + 1]] for i in range(1, s - 1)]
                out.append(np.stack(fan, axis=1).reshape(-1, 3))
            elif s == d + 1:
                out.append(block)
            else:
                what = {1: "1 vertex", 2: "2 vertices (segments)"}.get(s, f"{s} vertices")
                want = "segments (2 vertices)" if d == 1 else f"{d + 1} vertices" if d != 2 else "3 or more vertices"
                raise InputError(
                    f"Cannot use the faces of '{self.path}' for d = {d}: {len(block)} of them have {what}, "
                    f"but a {d}-manifold needs {want} per face."
                )
        simp = np.concatenate(out) if out else np.empty((0, d + 1), np.int64)
        srt = np.sort(simp, axis=1)
        rep = (srt[:, 1:] == srt[:, :-1]).any(axis=1)
        if rep.any():
            raise InputError(
                f"Cannot use the faces of '{self.path}': {int(rep.sum())} face(s) repeat a vertex "
                f"(the first is {tuple(int(v) for v in simp[np.flatnonzero(rep)[0]])}, counting from 0)."
            )
        return simp.astype(np.int64)


def _bad(path: Path, what: str) -> InputError:
    return InputError(f"Cannot read '{path}' as a {path.suffix.lower() or 'mesh'} mesh ({what}).")


def _blocks(polys: list[list[int]] | list[np.ndarray]) -> list[np.ndarray]:
    """Group polygons by size, keeping the order of first appearance."""
    by: dict[int, list] = {}
    for p in polys:
        by.setdefault(len(p), []).append(p)
    return [np.asarray(v, dtype=np.int64).reshape(len(v), s) for s, v in by.items()]


def _check_indices(cells: list[np.ndarray], n: int, path: Path) -> None:
    for block in cells:
        if len(block) and (block.min() < 0 or block.max() >= n):
            bad = block[(block < 0) | (block >= n)][0]
            raise _bad(path, f"a face refers to vertex {int(bad)} but the file has {n} vertices (indices 0 to {n - 1})")


#: Suffixes whose faces :func:`read_mesh` reads.
MESH_SUFFIXES = (".off", ".noff", ".ply", ".obj", ".vtk", ".vtu", ".stl")

#: meshio cell types usable as ground truth, and types that are skipped (point markers).
_MESHIO_CELLS = ("line", "triangle", "quad", "polygon", "tetra")
_MESHIO_SKIP = ("vertex",)


def read_mesh(path: str | os.PathLike) -> MeshData:
    """Read the vertices and faces of a mesh file (no faces gives an empty ``cells``).

    ``.off``/``.noff`` and ``.ply`` use this module's readers (any dimension);
    ``.obj .vtk .vtu .stl`` go through meshio.

    Raises
    ------
    InputError
        One sentence naming the file for any problem, including faces that
        refer to vertices the file does not have.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise InputError(f"Cannot read faces from '{path}': use one of {' '.join(MESH_SUFFIXES)}.")
    try:
        if suffix in (".off", ".noff"):
            mesh = read_off(path)
        elif suffix == ".ply":
            mesh = read_ply(path)
        else:
            mesh = _read_meshio(path)
    except InputError:
        raise
    except OSError as err:
        raise InputError(f"Cannot read '{path}': {err.strerror or err}.") from None
    except Exception as err:  # noqa: BLE001 - any parser failure is one sentence
        text = " ".join(str(err).split())[:120] or type(err).__name__
        raise InputError(f"Cannot read '{path}' as a {suffix} mesh ({text}).") from None
    if mesh.points.ndim != 2 or len(mesh.points) == 0:
        raise _bad(path, "it has no vertices")
    return mesh


def _read_meshio(path: Path) -> MeshData:
    import meshio  # deferred: only these formats need it

    chatter = StringIO()  # meshio prints and calls sys.exit() on some malformed files
    try:
        with redirect_stdout(chatter), redirect_stderr(chatter), np.errstate(all="ignore"):
            mesh = meshio.read(path)
    except SystemExit:
        raise _bad(path, f"meshio cannot parse it as {path.suffix.lower()}") from None
    cells = []
    for block in mesh.cells:
        kind = block.type
        if kind in _MESHIO_SKIP:
            continue
        if not (kind in _MESHIO_CELLS or kind.startswith("polygon")):
            raise _bad(path, f"it has {kind} cells, which cannot be a simplicial ground truth")
        data = np.asarray(block.data, dtype=np.int64)
        if data.size and data.min() < 0:
            raise _bad(path, "it uses negative (relative) face indices, which are not supported")
        cells.append(data)
    _check_indices(cells, len(mesh.points), path)
    return MeshData(np.asarray(mesh.points, dtype=np.float64), cells, path)


# ---------------------------------------------------------------- OFF
def read_off(path: Path) -> MeshData:
    """Read a Geomview OFF / nOFF / 4OFF file (ASCII or BINARY); see the module docstring."""
    data = path.read_bytes()
    first = data.split(b"\n", 1)[0].split(b"#", 1)[0].split()
    key = first[0].decode("ascii", "replace") if first else ""
    m = _OFF_KEY.match(key)
    if m is not None and len(first) > 1 and first[1] == b"BINARY":
        return _read_off_binary(path, data[data.index(b"\n") + 1 :], m)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise _bad(path, "it is neither a text OFF file nor an 'OFF BINARY' one") from None
    lines = [ln.split("#", 1)[0].split() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln]
    if not lines:
        raise _bad(path, "the file is empty")
    hdr = _OFF_KEY.match(lines[0][0])
    if hdr is None and not lines[0][0].isdigit():
        raise _bad(path, f"it does not start with an OFF keyword (found {lines[0][0][:20]!r})")
    st, col, nrm, four, ndim = (bool(g) for g in hdr.groups()) if hdr else (False,) * 5
    # a token stream that remembers line ends (face colours run to the end of a line)
    pos = [0, 1 if hdr else 0]  # line, token
    if pos[1] >= len(lines[0]):
        pos = [1, 0]

    def take(count: int, what: str) -> list[str]:
        out: list[str] = []
        while len(out) < count:
            if pos[0] >= len(lines):
                raise _bad(path, f"it ends early, while reading {what}")
            row = lines[pos[0]]
            need = count - len(out)
            out.extend(row[pos[1] : pos[1] + need])
            pos[1] += need
            if pos[1] >= len(row):
                pos[0], pos[1] = pos[0] + 1, 0
        return out

    def ints(tokens: list[str], what: str) -> list[int]:
        try:
            return [int(t) for t in tokens]
        except ValueError:
            raise _bad(path, f"{what} must be whole numbers, found {' '.join(tokens)[:40]!r}") from None

    dim = ints(take(1, "the dimension"), "the dimension (nOFF)")[0] if ndim else 3
    if dim < 1:
        raise _bad(path, f"the nOFF dimension must be at least 1, found {dim}")
    counts_line = lines[pos[0]][pos[1] :] if pos[0] < len(lines) else []
    if four and not ndim and len(counts_line) == 4:
        raise _bad(
            path,
            "it looks like Stella4D's 4OFF (counts of vertices, faces, edges and cells), which is "
            "not supported; in Geomview's 4OFF the 4th coordinate is homogeneous; use nOFF for R^4",
        )
    nv, nf, _ = ints(take(3, "the counts"), "the vertex, face and edge counts")
    if nv < 0 or nf < 0:
        raise _bad(path, "the vertex and face counts must not be negative")
    if nrm and ndim:
        raise _bad(path, "per-vertex normals in an n-dimensional OFF (NnOFF) are not supported")
    comps = dim + (1 if four else 0)
    per = comps + 3 * nrm + 4 * col + 2 * st
    tokens = take(nv * per, "the vertices")
    try:
        values = np.array(tokens, dtype=float).reshape(nv, per)
    except ValueError:
        raise _bad(path, "a vertex coordinate is not a number") from None
    points = _dehomogenise(values[:, :comps], four, path)
    polys: list[list[int]] = []
    for i in range(nf):
        if pos[1] != 0:  # faces start on their own line
            pos[0], pos[1] = pos[0] + 1, 0
        if pos[0] >= len(lines):
            raise _bad(path, f"it has {i} faces but its header says {nf}")
        row = lines[pos[0]]
        size = ints(row[:1], f"face {i + 1}'s vertex count")[0]
        if size < 1 or len(row) < 1 + size:
            raise _bad(path, f"face {i + 1} (counting from 1) says it has {size} vertices but lists {len(row) - 1}")
        polys.append(ints(row[1 : 1 + size], f"face {i + 1}'s vertex indices"))
        pos[0], pos[1] = pos[0] + 1, 0
    cells = _blocks(polys)
    _check_indices(cells, nv, path)
    return MeshData(points, cells, path)


def _dehomogenise(values: np.ndarray, four: bool, path: Path) -> np.ndarray:
    if not four:
        return values
    w = values[:, -1:]
    if (w == 0).any():
        raise _bad(path, f"{int((w == 0).sum())} vertices have homogeneous coordinate 0 (points at infinity)")
    return values[:, :-1] / w


def _read_off_binary(path: Path, body: bytes, m: re.Match) -> MeshData:
    st, col, nrm, four, ndim = (bool(g) for g in m.groups())
    off = 0

    def get(fmt: str, count: int) -> np.ndarray:
        nonlocal off
        size = np.dtype(fmt).itemsize * count
        if off + size > len(body):
            raise _bad(path, "the binary OFF data ends early")
        out = np.frombuffer(body, dtype=fmt, count=count, offset=off)
        off += size
        return out

    dim = int(get(">i4", 1)[0]) if ndim else 3
    nv, nf, _ = (int(v) for v in get(">i4", 3))
    if dim < 1 or nv < 0 or nf < 0:
        raise _bad(path, "the binary OFF header has an impossible dimension or count")
    comps = dim + (1 if four else 0)
    per = comps + 3 * nrm + 4 * col + 2 * st
    values = get(">f4", nv * per).astype(np.float64).reshape(nv, per)
    points = _dehomogenise(values[:, :comps], four, path)
    polys = []
    for _ in range(nf):
        size = int(get(">i4", 1)[0])
        if size < 1:
            raise _bad(path, f"a binary OFF face has {size} vertices")
        polys.append(get(">i4", size).astype(np.int64))
        ncol = int(get(">i4", 1)[0])
        get(">f4", max(ncol, 0))
    cells = _blocks(polys)
    _check_indices(cells, nv, path)
    return MeshData(points, cells, path)


def write_off(path: Path, points: np.ndarray, simplices: np.ndarray, *, ndim: bool = False, comment: str = "") -> None:
    """Write points and simplices as ASCII OFF (k <= 3, padded to 3-D) or nOFF.

    Parameters
    ----------
    path : Path
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (m, s)
        Written as faces with s vertices each (any s >= 1).
    ndim : bool
        Always write ``nOFF`` with Ndim = k (the ``.noff`` suffix).
    comment : str
        One line written as a ``#`` comment after the keyword.
    """
    points = np.asarray(points, dtype=np.float64)
    simplices = np.asarray(simplices, dtype=np.int64)
    simplices = simplices.reshape(len(simplices), -1) if simplices.size else np.empty((0, 1), np.int64)
    n, k = points.shape
    with open(path, "w", encoding="ascii") as fh:
        if ndim or k > 3:
            fh.write(f"nOFF\n# {comment}\n{k}\n" if comment else f"nOFF\n{k}\n")
        else:
            points = np.column_stack([points, np.zeros((n, 3 - k))]) if k < 3 else points
            fh.write(f"OFF\n# {comment}\n" if comment else "OFF\n")
        fh.write(f"{n} {len(simplices)} 0\n")
        np.savetxt(fh, points, fmt="%.17g")
        if len(simplices):
            s = simplices.shape[1]
            np.savetxt(fh, np.column_stack([np.full(len(simplices), s), simplices]), fmt="%d")


# ---------------------------------------------------------------- PLY
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
    return MeshData(points, cells, path)


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
