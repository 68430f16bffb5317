r"""Wavefront OBJ: :func:`read_obj`, the vertices and the ``f`` and ``l`` records of a polygonal OBJ file.

What is read (the OBJ specification's polygonal subset)
-------------------------------------------------------
* ``v x y z [w]``: a vertex; ``w`` is a weight for rational curves, not a
  homogeneous coordinate, and is ignored.  ``v x y z r g b`` (six numbers,
  MeshLab's and others' per-vertex colour) also gives the vertex a colour
  (attribute ``colors``), when every vertex has one.
* ``f v1 v2 v3 ...``: a polygon; each entry is ``v``, ``v/vt``, ``v//vn`` or
  ``v/vt/vn``, and only ``v`` is used: texture and normal indices number
  their own lists (``vt``, ``vn``), which may be longer or shorter than the
  vertex list.
* ``l v1 v2 ...``: a polyline, read as its segments (crustview writes a
  curve's M_S so).
* Indices count from 1; a negative index counts back from the last vertex
  defined before the record (-1 is the latest), as the specification says.
* ``#`` starts a comment, and a line ending in ``\`` continues on the next.
  Every other record (``vt vn vp p g o s usemtl mtllib`` and the free-form
  geometry statements) is skipped.

Why our own reader: meshio's reads ``vn`` as per-vertex normals and fails on
a file whose normal list has another length than its vertex list (common in
exported scans: ``f 1//7``), and it skips ``l`` records.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from crustview.attributes import colors_to_unit

from .mesh import MeshData, _bad, _blocks, _check_indices


def read_obj(path: Path) -> MeshData:
    """Read the vertices, polygons and polylines of an OBJ file (see the module docstring).

    Raises
    ------
    InputError
        One sentence naming the file: a vertex with fewer than three numbers
        or a value that is not a number, an index of 0 or beyond the vertices
        defined so far, a polygon with fewer than three vertices.
    """
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except OSError as err:
        raise _bad(path, err.strerror or str(err)) from None
    verts: list[list[str]] = []
    polys: list[list[int]] = []
    segs: list[list[int]] = []
    pending = ""
    for number, raw in enumerate(text.splitlines(), 1):
        line = pending + raw.split("#", 1)[0]
        if line.endswith("\\"):
            pending = line[:-1] + " "
            continue
        pending = ""
        tok = line.split()
        if not tok:
            continue
        key = tok[0]
        if key == "v":
            if len(tok) < 4:
                raise _bad(path, f"line {number}: a vertex needs three coordinates")
            verts.append(tok[1:])
        elif key == "f" or key == "l":
            idx = [_index(t, len(verts), path, number) for t in tok[1:]]
            if key == "f":
                if len(idx) < 3:
                    raise _bad(path, f"line {number}: a face needs at least three vertices")
                polys.append(idx)
            elif len(idx) >= 2:
                segs.extend([a, b] for a, b in zip(idx[:-1], idx[1:], strict=True))
    points, attributes = _vertices(verts, path)
    cells = _blocks(polys) + ([np.asarray(segs, np.int64).reshape(-1, 2)] if segs else [])
    _check_indices(cells, len(points), path)
    return MeshData(points, cells, path, attributes)


def _index(token: str, defined: int, path: Path, number: int) -> int:
    """The 0-based vertex of one ``f`` or ``l`` entry (``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``)."""
    head = token.split("/", 1)[0]
    try:
        i = int(head)
    except ValueError:
        raise _bad(path, f"line {number}: '{token}' is not a vertex index") from None
    if i == 0:
        raise _bad(path, f"line {number}: vertex index 0 (OBJ counts from 1)")
    if i < 0:
        if -i > defined:
            raise _bad(path, f"line {number}: relative index {i} goes back past the first vertex")
        return defined + i
    return i - 1


def _vertices(verts: list[list[str]], path: Path) -> tuple[np.ndarray, dict]:
    """Coordinates (n, 3), and colours where every vertex line has exactly six numbers."""
    if not verts:
        return np.empty((0, 3)), {}
    width = {len(v) for v in verts}
    try:
        if width == {6}:
            table = np.array(verts, dtype=np.float64)
            return np.ascontiguousarray(table[:, :3]), {"colors": colors_to_unit(table[:, 3:6])}
        if len(width) == 1:
            return np.array(verts, dtype=np.float64)[:, :3].copy(), {}
        return np.array([v[:3] for v in verts], dtype=np.float64), {}
    except ValueError:
        bad = next((i for i, v in enumerate(verts) if not all(_is_number(x) for x in v)), 0)
        raise _bad(path, f"vertex {bad + 1} has a value that is not a number") from None


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
