"""Geomview OFF and nOFF in any dimension: :func:`read_off` and :func:`write_off`.

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
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np

from .mesh import MeshData, _bad, _blocks, _check_indices

_OFF_KEY = re.compile(r"^(ST)?(C)?(N)?(4)?(n)?OFF$")


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
    uniform = _uniform_faces(lines, pos[0] + (pos[1] != 0), nf)
    if uniform is not None:
        _check_indices([uniform], nv, path)
        return MeshData(points, [uniform], path)
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


def _uniform_faces(lines: list[list[str]], start: int, nf: int) -> np.ndarray | None:
    """The faces as one (nf, size) block when every face line is ``size`` and its ``size`` indices, else None.

    The common case (a triangle or quad mesh without face colours) in one pass: the same ``int`` of every
    token as the line-by-line reading, which gives the faces every other case, and its messages for
    anything malformed (None here sends it there).
    """
    block = lines[start : start + nf]
    if nf == 0 or len(block) != nf:
        return None
    width = len(block[0])
    if width < 2 or any(len(row) != width for row in block):
        return None
    try:
        flat = np.fromiter(map(int, itertools.chain.from_iterable(block)), dtype=np.int64, count=nf * width)
    except (ValueError, OverflowError):
        return None
    table = flat.reshape(nf, width)
    if (table[:, 0] != width - 1).any():
        return None
    return np.ascontiguousarray(table[:, 1:])


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
