"""Sessions: what the viewer shows, saved to a small JSON file (``*.crustview.json``).

A session holds the input (a file, with its size, SHA-1 and modification
time, or a built-in manifold with its sample size and seed), the run's
parameters (d, candidate test, θ, boundary pruning, extraction mode) and the
view: the camera, the projection basis of R^k, every layer's style and the
current step.  Opening a session reconstructs the input again (the run is
deterministic) and then restores the view.

No Qt and no VTK here: the window turns its state into a :class:`Session`
and back (:mod:`crustview.qt.sessions`).  Every problem with a session file
raises :class:`SessionError` with one sentence that says what is wrong.

Examples
--------
>>> s = Session(source=BuiltinSource("torus", 1500, 0), d=2)
>>> Session.from_dict(s.to_dict()) == s
True
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from .atomic import write_text
from .core.errors import CrustviewError
from .core.result import CANDIDATE_TESTS

#: Version of the file format this module writes (and the only one it reads).
VERSION = 1
#: Ending of session files.
SUFFIX = ".crustview.json"
#: Extraction modes.
MODES = ("robust", "paper")
#: Style fields of a layer that a session keeps.
LAYER_FIELDS = ("visible", "color", "opacity", "size", "colorby", "mode", "shrink")
#: Largest session file read (a session is a few kB; anything bigger is not one).
MAX_BYTES = 2_000_000


class SessionError(CrustviewError):
    """A session file cannot be used (malformed, other version, input moved or changed)."""


def is_session_path(path: str | os.PathLike) -> bool:
    """Whether ``path`` names a session file (by its ending)."""
    return str(path).lower().endswith(SUFFIX)


def session_path(path: str | os.PathLike) -> Path:
    """``path`` with the :data:`SUFFIX` ending added when it is missing."""
    p = Path(path)
    if is_session_path(p):
        return p
    name = p.name[: -len(".json")] if p.name.lower().endswith(".json") else p.name
    return p.with_name(name + SUFFIX)


# -- the input -----------------------------------------------------------------
@dataclass(frozen=True)
class FileSource:
    """An input file and its fingerprint when the session was saved.

    Attributes
    ----------
    path : str
        Absolute path.
    relative : str
        The same path relative to the session file's folder (used when the
        two moved together).
    size : int
        Bytes.
    sha1 : str
        Hex digest of the content.
    mtime : float
        Modification time (seconds since the epoch).
    """

    path: str
    relative: str
    size: int
    sha1: str
    mtime: float
    kind: str = field(default="file", init=False)


@dataclass(frozen=True)
class BuiltinSource:
    """A built-in manifold sampled with ``n`` points and ``seed``."""

    name: str
    n: int
    seed: int = 0
    kind: str = field(default="builtin", init=False)


def sha1_of(path: str | os.PathLike, chunk: int = 1 << 20) -> str:
    """Hex SHA-1 of a file's content."""
    h = hashlib.sha1()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(chunk), b""):
            h.update(block)
    return h.hexdigest()


def file_source(path: str | os.PathLike, session_file: str | os.PathLike | None = None) -> FileSource:
    """The :class:`FileSource` of ``path`` as it is now (``session_file``: where the session goes)."""
    p = Path(path).resolve()
    st = p.stat()
    rel = ""
    if session_file is not None:
        try:
            rel = os.path.relpath(p, Path(session_file).resolve().parent)
        except ValueError:  # another drive (Windows)
            rel = ""
    return FileSource(str(p), rel, int(st.st_size), sha1_of(p), float(st.st_mtime))


def resolve_input(source: FileSource, session_file: str | os.PathLike | None = None) -> tuple[Path, str]:
    """Find the session's input file and check it is the one saved.

    The saved absolute path is tried first, then the path relative to the
    session file (a folder moved as a whole).  A file found there must have
    the saved size and SHA-1 (a newer modification time alone is fine).

    Returns
    -------
    path : Path
    note : str
        '' or one sentence to show (e.g. the file was found beside the session).

    Raises
    ------
    SessionError
        When the file is missing or its content changed.
    """
    tried = [Path(source.path)]
    if source.relative and session_file is not None:
        tried.append((Path(session_file).resolve().parent / source.relative).resolve())
    name = Path(source.path).name
    found = next((p for p in tried if p.is_file()), None)
    if found is None:
        raise SessionError(
            f"the session's input file '{name}' is no longer at {source.path}"
            + (" nor beside the session" if len(tried) > 1 else "")
            + "; it was moved or deleted (open the file itself with File ▸ Open)"
        )
    size = found.stat().st_size
    if size != source.size:
        raise SessionError(
            f"the session's input file '{found}' changed since the session was saved "
            f"({source.size:,} bytes then, {size:,} now); open it with File ▸ Open instead"
        )
    if sha1_of(found) != source.sha1:
        raise SessionError(
            f"the session's input file '{found}' changed since the session was saved "
            "(same size, other content); open it with File ▸ Open instead"
        )
    note = "" if found == tried[0] else f"input file found beside the session: {found}"
    return found, note


# -- the session -----------------------------------------------------------------
@dataclass
class Session:
    """What a session file holds.

    Attributes
    ----------
    source : FileSource or BuiltinSource
    d : int
    test : str
        Candidate test (one of ``CANDIDATE_TESTS``).
    theta : float
        Angle threshold in radians.
    prune_boundary : bool
    mode : str
        ``"robust"`` or ``"paper"``.
    step : int
        Player position (0: T_S before Algorithm 3).
    camera : dict or None
        ``position``, ``focal_point``, ``up`` (3 floats each), ``view_angle``,
        ``parallel``, ``parallel_scale`` and ``window_center`` (2 floats, the image shift).
    projection : dict or None
        ``k``, ``origin`` (k floats), ``base`` (k x 3), ``angles`` (rows
        ``[i, j, radians]``), ``source`` and ``stereo_radius``.
    layers : dict of str to dict
        Per layer name, the :data:`LAYER_FIELDS` that differ from nothing in
        particular (all of them are written).
    slice : dict or None
        ``offset`` and ``cut`` of the slicing hyperplane.
    speed : float
        Playback speed in steps per second.
    selection : dict or None
        ``sample`` (an index), ``simplex`` and ``face`` (sample indices), each
        or None.
    comparison : dict or None
        What M_S was compared with (the spec of
        :func:`crustview.scene.comparison.comparison_job`): computed again on opening.
    normals : str
        The run's normal planes: ``"paper"`` (Algorithm 1) or ``"smoothed"``
        (``reconstruct(normals=...)``).
    """

    source: FileSource | BuiltinSource
    d: int
    test: str = "cocone"
    theta: float = math.pi / 8
    prune_boundary: bool = True
    mode: str = "robust"
    step: int = 0
    camera: dict | None = None
    projection: dict | None = None
    layers: dict[str, dict] = field(default_factory=dict)
    slice: dict | None = None
    speed: float = 10.0
    selection: dict | None = None
    comparison: dict | None = None
    normals: str = "paper"

    def to_dict(self) -> dict[str, Any]:
        """The JSON object written to the file."""
        out = asdict(self)
        out["source"] = {"kind": self.source.kind, **{k: v for k, v in asdict(self.source).items() if k != "kind"}}
        out["theta_degrees"] = math.degrees(self.theta)  # for people reading the file
        return {"crustview_session": VERSION, **out}

    @classmethod
    def from_dict(cls, data: Any) -> Session:
        """Validate a parsed session object; raises :class:`SessionError` naming the bad field."""
        if not isinstance(data, dict):
            raise SessionError("not a crustview session (the file holds no JSON object)")
        if "crustview_session" not in data:
            raise SessionError("not a crustview session (no 'crustview_session' version key)")
        version = data["crustview_session"]
        if version != VERSION:
            raise SessionError(
                f"session format version {version!r} is not supported (this crustview reads "
                f"version {VERSION}); save the session again with this version"
            )
        src = _source(data.get("source"))
        d = _int(data, "d", 1)
        test = data.get("test", "cocone")
        if test not in CANDIDATE_TESTS:
            raise SessionError(f"'test' is {test!r}; expected one of {', '.join(CANDIDATE_TESTS)}")
        theta = _float(data, "theta")
        if not 0.0 < theta < math.pi / 2:
            raise SessionError(f"'theta' must be between 0 and π/2 radians, got {theta}")
        mode = data.get("mode", "robust")
        if mode not in MODES:
            raise SessionError(f"'mode' is {mode!r}; expected 'robust' or 'paper'")
        prune = data.get("prune_boundary", True)
        if not isinstance(prune, bool):
            raise SessionError("'prune_boundary' must be true or false")
        normals = data.get("normals", "paper")
        if normals not in ("paper", "smoothed"):
            raise SessionError(f"'normals' is {normals!r}; expected 'paper' or 'smoothed'")
        return cls(
            src,
            d,
            test,
            theta,
            prune,
            mode,
            _int(data, "step", 0) if "step" in data else 0,
            _camera(data.get("camera")),
            _projection(data.get("projection")),
            _layers(data.get("layers", {})),
            _slice(data.get("slice")),
            _speed(data.get("speed", 10.0)),
            _selection(data.get("selection")),
            _comparison(data.get("comparison")),
            normals,
        )


def write_session(path: str | os.PathLike, session: Session) -> Path:
    """Write ``session`` as JSON to ``path`` (the :data:`SUFFIX` ending added if missing); returns the path."""
    p = session_path(path)
    text = json.dumps(session.to_dict(), indent=1, allow_nan=False)
    write_text(p, text + "\n")  # atomic: a failed write leaves the previous session as it was
    return p


def read_session(path: str | os.PathLike) -> Session:
    """Read and validate a session file; every problem is a one-line :class:`SessionError`."""
    p = Path(path)
    try:
        if p.stat().st_size > MAX_BYTES:
            raise SessionError(f"'{p.name}' is {p.stat().st_size:,} bytes: too big for a crustview session")
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SessionError(f"session file '{p}' does not exist") from None
    except UnicodeDecodeError:
        raise SessionError(f"'{p.name}' is not a crustview session (not UTF-8 text)") from None
    except OSError as err:
        raise SessionError(f"cannot read '{p}': {err.strerror or err}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as err:
        raise SessionError(f"'{p.name}' is not valid JSON (line {err.lineno}, column {err.colno}: {err.msg})") from None
    try:
        return Session.from_dict(data)
    except SessionError as err:
        raise SessionError(f"'{p.name}': {err}") from None


# -- validation helpers -----------------------------------------------------------
def _int(data: dict, key: str, low: int) -> int:
    v = data.get(key)
    if isinstance(v, bool) or not isinstance(v, int) or v < low:
        raise SessionError(f"'{key}' must be an integer >= {low}, got {v!r}")
    return v


def _float(data: dict, key: str) -> float:
    v = data.get(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SessionError(f"'{key}' must be a finite number, got {v!r}")
    return float(v)


def _floats(v: Any, n: int | None, key: str) -> list[float]:
    if (
        not isinstance(v, list)
        or (n is not None and len(v) != n)
        or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)
    ):
        size = f"{n} " if n is not None else ""
        raise SessionError(f"'{key}' must be a list of {size}finite numbers")
    return [float(x) for x in v]


def _source(v: Any) -> FileSource | BuiltinSource:
    if not isinstance(v, dict) or v.get("kind") not in ("file", "builtin"):
        raise SessionError("'source' must say kind 'file' or 'builtin'")
    try:
        if v["kind"] == "builtin":
            src = BuiltinSource(str(v["name"]), _int(v, "n", 1), _int(v, "seed", 0) if "seed" in v else 0)
        else:
            src = FileSource(
                str(v["path"]), str(v.get("relative", "")), _int(v, "size", 0), str(v["sha1"]), _float(v, "mtime")
            )
    except KeyError as err:
        raise SessionError(f"'source' lacks {err.args[0]!r}") from None
    return src


def _camera(v: Any) -> dict | None:
    if v is None:
        return None
    if not isinstance(v, dict):
        raise SessionError("'camera' must be an object")
    out = {k: _floats(v.get(k), 3, f"camera.{k}") for k in ("position", "focal_point", "up")}
    out["view_angle"] = _float(v, "view_angle") if "view_angle" in v else 30.0
    out["parallel"] = bool(v.get("parallel", False))
    out["parallel_scale"] = _float(v, "parallel_scale") if "parallel_scale" in v else 1.0
    if "window_center" in v:  # the image's shift clear of the legend (Reset); older sessions have none
        out["window_center"] = _floats(v["window_center"], 2, "camera.window_center")
    return out


def _projection(v: Any) -> dict | None:
    if v is None:
        return None
    if not isinstance(v, dict):
        raise SessionError("'projection' must be an object")
    k = _int(v, "k", 2)
    base = v.get("base")
    if not isinstance(base, list) or len(base) != k:
        raise SessionError(f"'projection.base' must be {k} rows of 3 numbers")
    angles = v.get("angles", [])
    if not isinstance(angles, list):
        raise SessionError("'projection.angles' must be a list of [i, j, radians]")
    rows = []
    for a in angles:
        i, j, ang = _floats(a, 3, "projection.angles[]")
        if not (i.is_integer() and j.is_integer() and 0 <= i < j < k):
            raise SessionError(f"'projection.angles' names the plane ({i}, {j}), not one of R^{k}")
        rows.append([int(i), int(j), ang])
    return {
        "k": k,
        "origin": _floats(v.get("origin"), k, "projection.origin"),
        "base": [_floats(r, 3, "projection.base[]") for r in base],
        "angles": rows,
        "source": str(v.get("source", "custom")),
        "stereo_radius": _float(v, "stereo_radius") if "stereo_radius" in v else 0.0,
    }


def _layers(v: Any) -> dict[str, dict]:
    if not isinstance(v, dict):
        raise SessionError("'layers' must be an object of layer name to style")
    out = {}
    types = {
        "visible": bool,
        "color": str,
        "opacity": (int, float),
        "size": (int, float),
        "colorby": str,
        "mode": str,
        "shrink": (int, float),
    }
    for name, style in v.items():
        if not isinstance(style, dict):
            raise SessionError(f"layer '{name}' must be an object")
        kept = {}
        for key, value in style.items():
            if key not in types:
                continue  # a field of a later version: ignored
            if not isinstance(value, types[key]) or (key != "visible" and isinstance(value, bool)):
                raise SessionError(f"layer '{name}': '{key}' has the wrong type ({value!r})")
            kept[key] = value
        out[str(name)] = kept
    return out


def _slice(v: Any) -> dict | None:
    if v is None:
        return None
    if not isinstance(v, dict):
        raise SessionError("'slice' must be an object")
    return {"offset": _float(v, "offset"), "cut": bool(v.get("cut", False))}


def _speed(v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
        raise SessionError(f"'speed' must be a positive number of steps per second, got {v!r}")
    return float(v)


def _indices(v: Any, key: str) -> list[int] | None:
    if v is None:
        return None
    if (
        not isinstance(v, list)
        or not v
        or not all(isinstance(x, int) and not isinstance(x, bool) and x >= 0 for x in v)
    ):
        raise SessionError(f"'{key}' must be a list of sample indices")
    return [int(x) for x in v]


def _selection(v: Any) -> dict | None:
    if v is None:
        return None
    if not isinstance(v, dict):
        raise SessionError("'selection' must be an object")
    sample = v.get("sample")
    if sample is not None and (isinstance(sample, bool) or not isinstance(sample, int) or sample < 0):
        raise SessionError(f"'selection.sample' must be a sample index, got {sample!r}")
    return {
        "sample": sample,
        "simplex": _indices(v.get("simplex"), "selection.simplex"),
        "face": _indices(v.get("face"), "selection.face"),
    }


def _comparison(v: Any) -> dict | None:
    if v is None:
        return None
    if not isinstance(v, dict) or v.get("kind") not in ("run", "result", "mesh"):
        raise SessionError("'comparison' must be an object with kind 'run', 'result' or 'mesh'")
    out: dict[str, Any] = {"kind": v["kind"]}
    if v["kind"] == "run":
        test = v.get("test", "cocone")
        if test not in CANDIDATE_TESTS:
            raise SessionError(f"'comparison.test' is {test!r}; expected one of {', '.join(CANDIDATE_TESTS)}")
        mode = v.get("mode", "robust")
        if mode not in MODES:
            raise SessionError(f"'comparison.mode' is {mode!r}; expected 'robust' or 'paper'")
        out.update(test=test, theta=_float(v, "theta"), mode=mode)
    else:
        if not isinstance(v.get("path"), str) or not v["path"]:
            raise SessionError("'comparison.path' must name the file compared with")
        out["path"] = v["path"]
    return out
