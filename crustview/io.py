"""Read point sets and write reconstructions, chosen by file suffix.

Every failure is reported as one :class:`~crustview.core.errors.InputError`
whose message is a single sentence naming the file, so the command line and
the viewer can show it as is.

Supported suffixes
------------------
read_points
    ``.npy`` (2-D array), ``.npz`` (key ``points``), ``.csv .txt .xyz``
    (comma or whitespace separated, ``#`` comments, an optional first line of
    column names; :mod:`crustview.textpoints`),
    ``.off .noff .ply`` (any dimension, :mod:`crustview.meshfiles`),
    ``.obj`` (:mod:`crustview.meshfiles.obj`), ``.vtk .vtu .stl`` (through
    meshio).  :func:`read_mesh` also gives the faces of these files (a
    ground truth).  ``.pcd .las .laz .e57`` scanner files
    (:mod:`crustview.scanfiles`).  PLY, OBJ vertex colours and the scanner
    formats also give colours, intensity and normals (:func:`read_attributes`).
write_points
    ``.npy .npz .csv .txt .xyz .ply .vtk`` (``.ply`` in any dimension).
write_result
    ``.npz``, ``.noff``, ``.off`` and ``.ply`` for every d and k (``.off`` is
    plain OFF for k <= 3 and nOFF above); ``.obj .vtk .stl`` meshes when
    d <= 2 and k <= 3 (``.stl`` holds triangles only).
write_report
    ``.json``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from crustview.atomic import atomic_open, atomic_path
from crustview.core.errors import InputError
from crustview.core.result import EXTRACTION_MODES
from crustview.core.util.memory import small_pages
from crustview.meshfiles.flat import drop_zero_z, flat_note
from crustview.npyfiles import read_npy, read_npz
from crustview.report import REPORT_CASCADES, holes_of_candidates, report_dict, write_report  # noqa: F401
from crustview.resulttruth import builtin_arrays, builtin_of, mesh_arrays, mesh_of
from crustview.textpoints import read_text_points

if TYPE_CHECKING:
    from crustview.core.result import Reconstruction

TEXT_SUFFIXES = (".csv", ".txt", ".xyz")
MESH_SUFFIXES = (".ply", ".obj", ".off", ".noff", ".vtk", ".vtu", ".stl")
#: Scanner formats read through their libraries (:mod:`crustview.scanfiles`).
SCAN_SUFFIXES = (".pcd", ".las", ".laz", ".e57")
READ_SUFFIXES = (".npy", ".npz", *TEXT_SUFFIXES, *MESH_SUFFIXES, *SCAN_SUFFIXES)
POINT_WRITE_SUFFIXES = (".npy", ".npz", *TEXT_SUFFIXES, ".ply", ".vtk")
RESULT_MESH_SUFFIXES = (".ply", ".obj", ".off", ".noff", ".vtk", ".stl")
#: Result suffixes written in any dimension (own writers, :mod:`crustview.meshfiles`).
ND_RESULT_SUFFIXES = (".ply", ".off", ".noff")
RESULT_SUFFIXES = (".npz", *RESULT_MESH_SUFFIXES)


def _reason(err: BaseException) -> str:
    """A short one-line rendering of an exception."""
    text = " ".join(str(err).split()) or type(err).__name__
    if isinstance(err, OSError) and err.strerror:
        text = err.strerror
    text = text.rstrip(".")
    return text if len(text) <= 160 else text[:157] + "..."


def _suffix(path: Path, allowed: tuple[str, ...], action: str) -> str:
    suffix = path.suffix.lower()
    if suffix not in allowed:
        shown = suffix or "no suffix"
        raise InputError(f"Cannot {action} '{path}': unsupported file type ({shown}); use one of {' '.join(allowed)}.")
    return suffix


# ---------------------------------------------------------------- reading
def read_points(path: str | os.PathLike, notes: list[str] | None = None, attributes: dict | None = None) -> np.ndarray:
    """Read a point set.

    Parameters
    ----------
    path : str or path-like
        The suffix chooses the format (see the module docstring).  Mesh
        formats store 3-D points; a third column that is identically zero is
        dropped so planar data written by :func:`write_points` reads back as 2-D.
    notes : list of str, optional
        Sentences about what was read other than points are appended here:
        a text file's header line of column names; a mesh read in R^2 because
        its third coordinate is 0 everywhere (:func:`~crustview.meshfiles.flat.flat_note`).
    attributes : dict, optional
        Filled with the per-point ``colors``, ``intensity`` and ``normals``
        that the file holds (:mod:`crustview.attributes`; PLY and the
        scanner formats).

    Returns
    -------
    points : ndarray of shape (n, k), float64
        At least one row and ``k >= 2`` columns, all finite.

    Raises
    ------
    InputError
        For any problem (missing or unreadable file, unknown suffix, empty
        or malformed content, wrong shape, NaN or infinite values).
    """
    path = Path(path)
    if path.is_dir():  # a folder is one whatever its name (no suffix, or a point file's)
        raise InputError(f"Cannot read '{path}': it is a folder, not a regular file.")
    suffix = _suffix(path, READ_SUFFIXES, "read points from")
    if not path.exists():
        raise InputError(f"Cannot read '{path}': the file does not exist.")
    if not path.is_file():
        raise InputError(f"Cannot read '{path}': it is not a regular file.")
    if suffix == ".npy":
        data = read_npy(path)
    elif suffix == ".npz":
        data = read_npz(path)
    elif suffix in TEXT_SUFFIXES:
        text = read_text_points(path)
        data = text.points
        if notes is not None and text.header is not None:
            notes.append(text.note(path))
    elif suffix in SCAN_SUFFIXES:
        from crustview.scanfiles import read_scan

        data, found = read_scan(path)
        if attributes is not None:
            attributes.update(found)
    else:
        data = _read_mesh(path, attributes, notes)
    points = _check_points(data, path)
    if attributes:
        from crustview.attributes import check

        check(attributes, len(points), path)
    return points


def read_attributes(path: str | os.PathLike) -> dict:
    """The per-point colours, intensity and normals of a point file (empty when it has none)."""
    attributes: dict = {}
    if Path(path).suffix.lower() in (".ply", ".obj", *SCAN_SUFFIXES):
        read_points(path, None, attributes)
    return attributes


def _read_mesh(path: Path, attributes: dict | None = None, notes: list[str] | None = None) -> np.ndarray:
    from crustview.meshfiles import read_mesh

    mesh = read_mesh(path)
    note = flat_note(path, mesh) if notes is not None else None
    if note:
        notes.append(note)
    points = drop_zero_z(mesh.points)
    if attributes is not None:
        attributes.update(mesh.attributes)
        if "normals" in attributes and attributes["normals"].shape[1] != points.shape[1]:
            del attributes["normals"]  # planar points (a zero z dropped): a 3-D normal does not apply
    return points


def read_mesh(path: str | os.PathLike, notes: list[str] | None = None):
    """Points and faces of a mesh file, or None when it has no faces or is not a mesh format.

    Also None for a flat mesh whose triangles or polygons lie in R^2 once its zero third coordinate is dropped
    (regions of the plane, no curve's truth: its vertices are a point sample).  ``notes``: where a mesh is
    returned, the note that its zero third coordinate was dropped is appended
    (:func:`~crustview.meshfiles.flat.flat_note`; :func:`read_points` says it for a flat mesh it reads).

    Returns
    -------
    MeshData or None
        :class:`crustview.meshfiles.mesh.MeshData`; its points are those of
        :func:`read_points` (a zero third column dropped as there).

    Raises
    ------
    InputError
        For a malformed file or faces that refer to missing vertices.
    """
    from dataclasses import replace

    from crustview.meshfiles import read_mesh as _read

    path = Path(path)
    if path.suffix.lower() not in MESH_SUFFIXES:
        return None
    if not path.is_file():
        raise InputError(f"Cannot read '{path}': the file does not exist.")
    mesh = _read(path)
    if mesh.n_cells == 0:
        return None
    points = _check_points(drop_zero_z(mesh.points), path)
    if points.shape[1] == 2 and min(block.shape[1] for block in mesh.cells) >= 3:
        # a flat mesh's triangles or polygons, read in R^2: regions of the plane, never the truth of a curve
        # (the only d < k there); the file is a point sample (read_points says so in its notes)
        return None
    note = flat_note(path, mesh) if notes is not None else None
    if note:
        notes.append(note)
    return replace(mesh, points=points)


def _check_points(data: Any, path: Path) -> np.ndarray:
    arr = np.asarray(data)
    if arr.dtype.kind not in "iuf":
        raise InputError(f"Cannot use '{path}': it holds {arr.dtype} values, not numbers.")
    if arr.ndim != 2:
        raise InputError(f"Cannot use '{path}': expected a 2-D array of shape (n, k), got shape {arr.shape}.")
    n, k = arr.shape
    if n == 0:
        raise InputError(f"Cannot use '{path}': it contains no points.")
    if k < 2:
        raise InputError(f"Cannot use '{path}': points need at least 2 coordinates, the file has {k} column.")
    arr = arr.astype(np.float64)
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        raise InputError(
            f"Cannot use '{path}': {int(bad.sum())} point(s) have NaN or infinite "
            f"coordinates (the first is point {int(np.flatnonzero(bad)[0]) + 1}, counting from 1)."
        )
    return arr


# ---------------------------------------------------------------- writing
def _pad3(points: np.ndarray, path: Path, what: str, instead: str = ".npz or .ply") -> np.ndarray:
    points = np.asarray(points, dtype=np.float64)
    k = points.shape[1]
    if k > 3:
        raise InputError(
            f"Cannot write '{path}': {what} files hold points in at most 3 dimensions, "
            f"these have {k}; use {instead} instead."
        )
    if k < 3:
        points = np.column_stack([points, np.zeros((len(points), 3 - k))])
    return points


def _write_mesh(path: Path, points: np.ndarray, cell_type: str | None, cells: np.ndarray) -> None:
    import meshio

    try:
        if path.suffix.lower() == ".obj":
            _write_obj(path, points, cell_type, cells)
            return
        blocks = []
        if cell_type is not None and len(cells):
            blocks = [(cell_type, np.asarray(cells, dtype=np.int32))]
        elif path.suffix.lower() == ".vtk":  # legacy VTK without cells does not read back
            blocks = [("vertex", np.arange(len(points), dtype=np.int32)[:, None])]
        mesh = meshio.Mesh(points, blocks)
        fmt = {".ply": "ply", ".vtk": "vtk", ".stl": "stl", ".vtu": "vtu"}[path.suffix.lower()]
        with atomic_path(path) as tmp:
            if fmt == "ply":
                meshio.write(tmp, mesh, file_format="ply", binary=True)
            else:
                meshio.write(tmp, mesh, file_format=fmt)
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001
        raise InputError(f"Cannot write '{path}': {_reason(err)}.") from None


def _write_obj(path: Path, points: np.ndarray, cell_type: str | None, cells: np.ndarray) -> None:
    """Wavefront OBJ with ``f`` (triangles) or ``l`` (segments) records, 1-based."""
    tag = "l" if cell_type == "line" else "f"
    with atomic_open(path, "w", encoding="ascii") as fh:
        fh.write("# crustview\n")
        np.savetxt(fh, points, fmt="v %.17g %.17g %.17g")
        if cell_type is not None and len(cells):
            width = cells.shape[1]
            np.savetxt(fh, np.asarray(cells) + 1, fmt=f"{tag}" + " %d" * width)


def _write_nd(path: Path, points: np.ndarray, simplices: np.ndarray | None, comment: str) -> None:
    """PLY, OFF or nOFF in any dimension (:mod:`crustview.meshfiles`)."""
    from crustview.meshfiles.off import write_off
    from crustview.meshfiles.ply import write_ply

    try:
        with atomic_path(path) as tmp:
            if path.suffix.lower() == ".ply":
                write_ply(Path(tmp), points, simplices, comment=comment)
            else:
                simp = np.empty((0, 1), np.int64) if simplices is None else simplices
                write_off(Path(tmp), points, simp, ndim=path.suffix.lower() == ".noff", comment=comment)
    except OSError as err:
        raise InputError(f"Cannot write '{path}': {_reason(err)}.") from None


def write_points(path: str | os.PathLike, points: np.ndarray) -> None:
    """Write a point set.

    Parameters
    ----------
    path : str or path-like
        ``.npy``, ``.npz`` (key ``points``), ``.csv`` (comma separated),
        ``.txt``/``.xyz`` (space separated), ``.ply`` (any k: extra
        coordinate properties above 3, see :mod:`crustview.meshfiles`),
        ``.vtk`` (k <= 3, padded with zeros to 3-D).
    points : ndarray of shape (n, k)

    Raises
    ------
    InputError
        For an unsupported suffix, a bad array or a failed write.
    """
    path = Path(path)
    suffix = _suffix(path, POINT_WRITE_SUFFIXES, "write points to")
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2:
        raise InputError(f"Cannot write '{path}': points must have shape (n, k), got {points.shape}.")
    if suffix == ".ply":
        _write_nd(path, points, None, "crustview points")
        return
    if suffix == ".vtk":
        _write_mesh(path, _pad3(points, path, suffix), None, np.empty((0, 1), int))
        return
    try:
        with atomic_open(path, "wb") as fh:
            if suffix == ".npy":
                np.save(fh, points)
            elif suffix == ".npz":
                np.savez_compressed(fh, points=points)
            else:
                delimiter = "," if suffix == ".csv" else " "
                header = f"crustview points: {points.shape[0]} rows, {points.shape[1]} coordinates"
                np.savetxt(fh, points, fmt="%.17g", delimiter=delimiter, header=header)
    except OSError as err:
        raise InputError(f"Cannot write '{path}': {_reason(err)}.") from None


@small_pages  # its arrays' pages as the run's (see numpy_small_pages)
def write_result(
    path: str | os.PathLike,
    rec: Reconstruction,
    builtin: dict[str, Any] | None = None,
    *,
    compress: bool = False,
    mesh: tuple[str, np.ndarray] | None = None,
) -> None:
    """Write a reconstruction.

    ``.npz`` holds, all indexed by *input* rows:

    ``points`` (n_in, k)
        The input points, in input order.
    ``simplices`` (m, d + 1)
        M_S.
    ``candidates`` (c, d + 1)
        T_S, the faces admitted by ``rec.test`` at ``rec.theta``.
    ``normals`` (n_in, k, k - d), ``tangents`` (n_in, k, d)
        Estimated orthonormal bases at each input row.
    ``d``, ``k``, ``test``, ``theta``, ``prune_boundary``, ``mode``, ``normals_method``, ``labelling``
        Scalars (``theta`` in radians, ``mode`` ``"robust"`` or ``"paper"``, ``labelling`` False for a
        hypersurface grown on request, :func:`crustview.core.reconstruct.reconstruct`):
        the run's parameters, so that :func:`read_run_parameters` can redo
        exactly this run.
    ``builtin``, ``builtin_n``, ``builtin_seed``, ``builtin_noise``, ``builtin_density``, ``builtin_method``
        Only for a sample of a built-in manifold (``builtin`` given): its
        name and how it was drawn, so that a reopened result shows the true
        topology again.
    ``truth_name``, ``truth_faces`` (f, d + 1)
        Only for the vertices of a mesh (``mesh`` given): its file name and
        faces on input rows, so that a reopened result is judged against them
        again (:mod:`crustview.resulttruth`).

    ``.ply``, ``.off`` and ``.noff`` write the input points and M_S in any
    k and d (:mod:`crustview.meshfiles`; :func:`read_mesh` reads them back).
    ``.obj .vtk .stl`` write the input points (padded to 3-D) and M_S as
    triangles (d = 2) or line segments (d = 1); they need d <= 2 and k <= 3,
    and ``.stl`` holds triangles only.

    Parameters
    ----------
    path : str or path-like
    rec : Reconstruction
    builtin : dict, optional
        For a sample of a built-in manifold: ``name``, ``n``, ``seed``,
        ``noise``, ``density`` and ``method`` (stored in ``.npz`` only).
    compress : bool
        Deflate the ``.npz`` members.  Off by default: the file is about 1.9x
        larger but written 40x faster (30,000 torus points: 5.8 MB in 0.01 s
        against 3.1 MB in 0.56 s), which keeps writing off the critical path.
    mesh : (str, ndarray), optional
        For the vertices of a mesh: its file name and faces as d-simplices on
        input rows (stored in ``.npz`` only).

    Raises
    ------
    InputError
        For an unsupported suffix or dimension combination, or a failed write.
    """
    path = Path(path)
    suffix = _suffix(path, RESULT_SUFFIXES, "write a reconstruction to")
    simplices = np.asarray(rec.point_input)[np.asarray(rec.manifold, dtype=np.intp)]
    simplices = simplices.reshape(-1, rec.d + 1)
    if suffix == ".npz":
        faces = rec.candidates.select(rec.test, rec.theta)
        candidates = np.asarray(rec.point_input)[np.asarray(faces, dtype=np.intp)]
        try:
            with atomic_open(path, "wb") as fh:
                (np.savez_compressed if compress else np.savez)(
                    fh,
                    points=np.asarray(rec.input_points, dtype=np.float64),
                    simplices=simplices,
                    candidates=candidates.reshape(-1, rec.d + 1),
                    normals=np.asarray(rec.normals)[rec.input_index],
                    tangents=np.asarray(rec.tangents)[rec.input_index],
                    d=np.int64(rec.d),
                    k=np.int64(rec.k),
                    test=np.str_(rec.test),
                    theta=np.float64(rec.theta),
                    prune_boundary=np.bool_(rec.prune_boundary),
                    labelling=np.bool_(getattr(rec, "labelling", True)),
                    mode=np.str_(rec.mode),
                    normals_method=np.str_(getattr(rec, "normals_method", "paper")),
                    **builtin_arrays(builtin),
                    **mesh_arrays(mesh, len(rec.input_points), rec.d),
                )
        except OSError as err:
            raise InputError(f"Cannot write '{path}': {_reason(err)}.") from None
        return
    if suffix in ND_RESULT_SUFFIXES:
        _write_nd(
            path, rec.input_points, simplices, f"crustview: M_S, d = {rec.d}, k = {rec.k}, {len(simplices)} simplices"
        )
        return
    if rec.d > 2:
        raise InputError(
            f"Cannot write '{path}': mesh files hold curves and surfaces only, "
            f"this reconstruction is {rec.d}-dimensional; use .npz, .ply, .off or .noff instead."
        )
    if rec.d == 1 and suffix == ".stl":
        raise InputError(
            f"Cannot write '{path}': {suffix} files hold triangles only and this "
            "reconstruction is a curve; use .ply, .obj, .vtk or .npz instead."
        )
    points = _pad3(rec.input_points, path, suffix, ".npz, .ply, .off or .noff")
    _write_mesh(path, points, "triangle" if rec.d == 2 else "line", simplices)


def read_run_parameters(path: str | os.PathLike) -> dict[str, Any] | None:
    """Parameters of the run saved in a result ``.npz``, or None for a plain point file.

    Returns
    -------
    dict or None
        ``d``, ``test``, ``theta`` (radians), ``prune_boundary``, ``mode``, ``normals`` (the planes'
        method: ``"paper"`` for results saved without it) and ``simplices`` (M_S in input rows) when
        ``path`` is a result written by :func:`write_result`; reconstructing its points with these
        parameters gives the same M_S (the pipeline is deterministic).
        Results saved before the robust extraction existed have no ``mode``
        and were made by the paper's Algorithm 3: ``mode`` is then
        ``"paper"``.  ``builtin`` is the built-in sample's description
        stored by :func:`write_result` (``name``, ``n``, ``seed``, ...), or
        None; ``mesh`` the mesh truth ``(file name, faces on input rows)``
        stored with it, or None.

    Raises
    ------
    InputError
        For an unreadable archive or a ``mode`` that crustview does not know.
    """
    path = Path(path)
    if path.suffix.lower() != ".npz" or not path.is_file():
        return None
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as archive:
            if not {"d", "test", "theta", "simplices"} <= set(archive.keys()):
                return None
            out = {
                "d": int(archive["d"]),
                "test": str(archive["test"]),
                "theta": float(archive["theta"]),
                "prune_boundary": bool(archive["prune_boundary"]) if "prune_boundary" in archive else True,
                "labelling": bool(archive["labelling"]) if "labelling" in archive else True,
                "mode": str(archive["mode"]) if "mode" in archive else "paper",
                # the normal planes it was made with (Algorithm 1's before session 33 stored the choice)
                "normals": str(archive["normals_method"]) if "normals_method" in archive else "paper",
                "simplices": np.asarray(archive["simplices"], dtype=np.int64),
                "builtin": builtin_of(archive),
            }
            out["mesh"] = mesh_of(archive, len(archive["points"]), out["d"]) if "points" in archive else None
    except Exception as err:  # noqa: BLE001
        raise InputError(f"Cannot read '{path}' as a NumPy .npz archive ({_reason(err)}).") from None
    from crustview.core.reconstruct import NORMAL_METHODS

    if out["normals"] not in NORMAL_METHODS:
        raise InputError(
            f"Cannot use '{path}': its normals {out['normals']!r} are not one of {', '.join(NORMAL_METHODS)}."
        )
    if out["mode"] not in EXTRACTION_MODES:
        raise InputError(
            f"Cannot use '{path}': its extraction mode {out['mode']!r} is not one of {', '.join(EXTRACTION_MODES)}."
        )
    return out
