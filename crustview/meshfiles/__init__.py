"""Mesh files with faces, in any dimension: Geomview OFF/nOFF, PLY, OBJ, and the rest via meshio.

:func:`read_mesh` returns the vertices and the polygons (or simplices) of a
mesh file; :func:`.off.write_off` and :func:`.ply.write_ply` write points and
simplices in any ambient dimension k.  Every failure is one
:class:`~crustview.core.errors.InputError` sentence naming the file.

* :mod:`.mesh`: :class:`~.mesh.MeshData`, what every reader returns.
* :mod:`.off`: Geomview OFF and nOFF (all variants, read and write).
* :mod:`.ply`: PLY, ASCII and binary (read and write).
* :mod:`.obj`: Wavefront OBJ's polygons and polylines (read; :mod:`crustview.io` writes it).
"""

from __future__ import annotations

import os
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO
from pathlib import Path

import numpy as np

from crustview.core.errors import InputError

from .mesh import MeshData, _bad, _check_indices
from .obj import read_obj
from .off import read_off
from .ply import read_ply

#: Suffixes whose faces :func:`read_mesh` reads.
MESH_SUFFIXES = (".off", ".noff", ".ply", ".obj", ".vtk", ".vtu", ".stl")

#: meshio cell types usable as ground truth, and types that are skipped (point markers).
_MESHIO_CELLS = ("line", "triangle", "quad", "polygon", "tetra")
_MESHIO_SKIP = ("vertex",)


def read_mesh(path: str | os.PathLike) -> MeshData:
    """Read the vertices and faces of a mesh file (no faces gives an empty ``cells``).

    ``.off``/``.noff`` and ``.ply`` use this module's readers (any dimension),
    ``.obj`` its own reader too (:mod:`.obj`); ``.vtk .vtu .stl`` go through meshio.

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
        with np.errstate(all="ignore"):  # overflowing or NaN values are reported by the point checks
            if suffix in (".off", ".noff"):
                mesh = read_off(path)
            elif suffix == ".ply":
                mesh = read_ply(path)
            elif suffix == ".obj":
                mesh = read_obj(path)
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
