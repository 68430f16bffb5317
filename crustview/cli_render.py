"""``crustview render``: a replay of Algorithm 3 or a grand tour, rendered headless to GIF, MP4 or PNGs.

Kept apart from :mod:`crustview.__main__`, which only registers the
sub-command (:func:`add_parser`) and calls :func:`run`.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

from .cli_reconstruct import dimension_arg, positive_int
from .core.errors import InputError
from .core.result import CANDIDATE_TESTS

#: Default frame size.
DEFAULT_SIZE = (640, 480)


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT, e.g. 640x480, got {text!r}") from None
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise argparse.ArgumentTypeError(f"frame size must be between 16 and 4096 pixels a side, got {text}")
    return w, h


def _fps(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected frames per second, got {text!r}") from None
    if not (math.isfinite(v) and 0.5 <= v <= 60):
        raise argparse.ArgumentTypeError(f"fps must be between 0.5 and 60, got {text}")
    return v


def _degrees(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an angle in degrees, got {text!r}") from None
    if not (math.isfinite(v) and 0.0 < v < 90.0):
        raise argparse.ArgumentTypeError(f"θ must be between 0 and 90 degrees, got {text}")
    return math.radians(v)


def add_parser(sub) -> None:
    """Register ``render`` on the sub-parsers action ``sub``."""
    p = sub.add_parser("render", help="render a replay or a grand tour to .gif, .mp4 or a folder of PNGs (headless)")
    p.add_argument(
        "input",
        help="point file, saved result .npz, a session SESSION.crustview.json, or a built-in manifold name "
        "(see 'crustview list')",
    )
    p.add_argument(
        "-d",
        type=dimension_arg,
        default=None,
        help="intrinsic dimension, or 'auto' (default: the built-in's, the result's, or a mesh file's faces')",
    )
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--replay", action="store_true", help="replay the steps of Algorithm 3")
    what.add_argument("--tour", action="store_true", help="a grand tour of R^k around the final M_S")
    p.add_argument("-o", "--output", type=Path, required=True, help="OUT.gif, OUT.mp4 or a folder for PNG frames")
    p.add_argument("--size", type=_size, default=DEFAULT_SIZE, help="frame size WxH (default 640x480)")
    p.add_argument("--fps", type=_fps, default=12.0, help="frames per second (default 12)")
    p.add_argument("--steps", default=None, help="replay only steps A:B (default: all)")
    p.add_argument(
        "--frames",
        type=positive_int,
        default=None,
        help="frame budget: a longer replay is subsampled (default 90); tour length (default 8 s)",
    )
    p.add_argument(
        "--mode",
        choices=("robust", "paper"),
        default=None,
        dest="mode_given",
        help="extraction mode (default robust, or the session's)",
    )
    p.add_argument(
        "--layers",
        default=None,
        help="comma-separated layers to show instead of the defaults, e.g. manifold,points,step",
    )
    p.add_argument("--test", choices=CANDIDATE_TESTS, default=None, help="candidate test (default: the run's)")
    p.add_argument("--theta", type=_degrees, default=None, help="angle θ of the test in degrees (default: the run's)")
    p.add_argument(
        "--projection",
        default=None,
        help="R^k to the view: 'pca', 'stereo' (k >= 4), or coordinates such as '1,2,4' "
        "(default: the session's, else the first three coordinates)",
    )
    p.add_argument(
        "--camera",
        default=None,
        help="'session' (default for a session), 'reset' (the viewer's initial camera), or a direction "
        "to look from, 'x,y,z' (the data framed)",
    )
    p.add_argument(
        "--frame-steps",
        action="store_true",
        help="replay: look at each step's tau from its open side, as the viewer's Frame each step",
    )


def load(
    source: str, d: int | str | None, mode: str | None, run: dict | None = None, seed: int = 0, n: int | None = None
):
    """Reconstruct ``source`` (a built-in name or a file): returns (rec, truth, label).

    ``run`` (``test``, ``theta``, ``prune_boundary``) overrides the saved or default parameters.  ``d`` may be
    ``"auto"`` (estimated as ``reconstruct -d auto`` does); without it a mesh file's faces say it, as ``auto``.
    """
    from .core import reconstruct
    from .core.samples.manifolds import MANIFOLDS

    run = {k: v for k, v in (run or {}).items() if v is not None}
    path = Path(source)
    if not path.exists() and source in MANIFOLDS:
        m = MANIFOLDS[source]
        n = n or m.default_n
        sample = m.sample(n, seed=seed)
        rec = reconstruct(sample.points, m.d if d in (None, "auto") else d, mode=mode or "robust", **run)
        return rec, sample, f"{source} (n = {n})"
    from .io import read_mesh, read_points, read_run_parameters

    params = read_run_parameters(path)
    mesh = read_mesh(path) if params is None else None
    points = mesh.points if mesh is not None else read_points(path)
    kwargs = {}
    if params is not None:  # a saved result: its own run (test, angle, pruning, mode, normal planes)
        d = d or params["d"]
        kwargs = {"test": params["test"], "theta": params["theta"], "prune_boundary": params["prune_boundary"]}
        kwargs["normals"] = params.get("normals", "paper")
        kwargs["labelling"] = params.get("labelling", True)
        mode = mode or params["mode"]
    kwargs.update(run)
    if d == "auto" and params is not None:
        d = params["d"]
    if d == "auto" or (d is None and mesh is not None):
        from .cli_reconstruct import choose_d

        d, _ = choose_d(points, "auto", mesh)
    if d is None:
        raise InputError(f"give the intrinsic dimension with -d (a number, or auto) for '{path.name}'")
    if not 1 <= d < points.shape[1]:
        raise InputError(f"d must be between 1 and k-1 = {points.shape[1] - 1}; got d = {d}")
    return reconstruct(points, d, mode=mode or "robust", **kwargs), None, path.name


def load_session(path: str, args: argparse.Namespace):
    """Reconstruct a session's input with its run, --test, --theta and --mode on top: (rec, truth, label, s)."""
    from .session import BuiltinSource, SessionError, read_session, resolve_input

    try:
        s = read_session(path)
        src = s.source
        if isinstance(src, BuiltinSource):
            where, n, seed = src.name, src.n, src.seed
        else:
            found, _ = resolve_input(src, path)
            where, n, seed = str(found), None, 0
    except SessionError as err:
        raise InputError(str(err)) from None
    run = {"test": args.test or s.test, "theta": s.theta if args.theta is None else args.theta}
    run["prune_boundary"] = s.prune_boundary
    run["normals"] = s.normals
    mode = args.mode_given or s.mode
    rec, truth, label = load(where, args.d or s.d, mode, run, seed=seed, n=n)
    return rec, truth, label, s


def apply_session(model, s, fresh_run: bool) -> list[str]:
    """A session's layers, projection, slice and step on ``model`` (Qt-free, as the viewer restores them).

    ``fresh_run``: the run differs from the session's (another test or θ), so its step is not kept.
    """
    notes = []
    for name, style in s.layers.items():
        layer = model.layers.get(name)
        if layer is None:
            continue
        for f, v in style.items():
            if f == "colorby" and layer.colorings and v not in model.colorings(name):
                notes.append(f"colouring {v!r} of {name} does not apply here")
                continue
            setattr(layer, f, float(v) if f in ("opacity", "size", "shrink") else v)
    if s.projection is not None:
        try:
            model.projection.restore(s.projection)
        except ValueError as err:
            notes.append(str(err))
    if s.slice is not None:
        model.set_slice(s.slice["offset"], s.slice["cut"])
    if not fresh_run:
        model.player.set_step(min(s.step, model.player.n_steps))
    return notes


def set_projection(model, text: str) -> None:
    """``--projection``: 'pca', 'stereo', or coordinates '1,2,4'."""
    p, rec = model.projection, model.rec
    if text == "pca":
        p.set_pca(rec.points)
    elif text == "stereo":
        if rec.k < 4:
            raise InputError("--projection stereo needs points in R^4 or more")
        p.set_stereographic(float(model.radius))
    else:
        try:
            axes = [int(v) - 1 for v in text.split(",")]
        except ValueError:
            raise InputError(f"--projection: expected pca, stereo or coordinates like 1,2,4; got {text!r}") from None
        if not 2 <= len(axes) <= 3 or len(set(axes)) != len(axes) or not all(0 <= a < rec.k for a in axes):
            raise InputError(f"--projection: two or three different coordinates between 1 and {rec.k}; got {text!r}")
        p.set_coordinates(*axes)


def set_camera(scene, text: str | None, session) -> None:
    """``--camera``: the session's camera, the initial one ('reset'), or framed from a direction 'x,y,z'."""
    import numpy as np

    from .render.camera import set_camera_state

    view = scene.view
    if text in (None, "session"):
        if session is not None and session.camera is not None:
            set_camera_state(scene.plotter, session.camera)
        return
    view.reset_camera()
    if text == "reset":
        return
    try:
        direction = np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise InputError(f"--camera: expected session, reset or a direction x,y,z; got {text!r}") from None
    if direction.shape != (3,) or not np.isfinite(direction).all() or np.linalg.norm(direction) == 0:
        raise InputError(f"--camera: a direction needs three numbers, not all 0; got {text!r}")
    cam = scene.plotter.camera
    focus = np.asarray(cam.focal_point)
    dist = float(np.linalg.norm(np.asarray(cam.position) - focus))
    cam.position = tuple(focus + dist * direction / np.linalg.norm(direction))
    up = np.array([0.0, 0.0, 1.0]) if abs(direction[2]) < 0.99 * np.linalg.norm(direction) else np.array([0, 1.0, 0])
    cam.up = tuple(up)
    cam.SetWindowCenter(0.0, 0.0)  # the reset's shift clear of the legend was for its own direction
    scene.plotter.reset_camera()


def framed_replay(scene, plan):
    """A replay whose every frame looks at its step's tau from the open side (``--frame-steps``)."""
    from .animation import step_caption

    note = plan.note() + "; each step framed"
    model = scene.model
    for i in plan.positions:
        model.player.set_step(i)
        step = model.player.current_step
        if step is not None:
            scene.view.frame_step(step)
        yield scene.frame(step_caption(model, i) + "\n" + note)


def _check_output(source: Path, output: Path, kind: str) -> None:
    """Refuse, in one line and before the reconstruction, an output the animation could not be written to.

    The writer makes missing folders (a GIF's, or a folder of frames and its parents), so a missing folder
    is fine; the nearest folder that exists must take a file, and the output must not be the input.
    """
    from .cli_reconstruct import _probe_folder, _same_file

    out = Path(output)
    if kind != "folder" and out.is_dir():
        raise InputError(f"Cannot write '{out}': it is a folder.")
    folder = out if kind == "folder" else out.parent
    folder = folder if str(folder) else Path(".")
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise InputError(f"Cannot write '{out}': '{folder}' is not a folder.")
    _probe_folder(out, folder)
    if _same_file(out, Path(str(source).split("@", 1)[0])):
        raise InputError(f"Refusing to write over the input file '{source}' (output '{out}'): choose another name.")


def run(args: argparse.Namespace) -> int:
    """Run ``crustview render``; returns the exit status."""
    from .animation import (
        DEFAULT_BUDGET,
        OffscreenScene,
        even_size,
        output_kind,
        parse_steps,
        plan_replay,
        text_progress,
        write_frames,
    )
    from .scene.model import SceneModel

    try:
        kind = output_kind(args.output)
    except ValueError as err:
        raise InputError(str(err)) from None
    size = even_size(args.size) if kind == "mp4" else args.size
    _check_output(args.input, args.output, kind)  # before the reconstruction: not after minutes of work
    if args.replay and args.frames is not None and args.frames < 2:
        raise InputError(f"a replay needs --frames 2 or more (its first and last step), got {args.frames}")
    if args.layers:  # the layer names are the same for every result: checked before it, too
        from .scene.layers import default_layers

        names = list(default_layers())
        unknown = {s.strip() for s in args.layers.split(",") if s.strip()} - set(names)
        if unknown:
            raise InputError(f"unknown layers {sorted(unknown)}; choose from {', '.join(names)}")
    t0 = time.perf_counter()
    from .session import is_session_path

    session = None
    if is_session_path(args.input):
        rec, truth, label, session = load_session(args.input, args)
    else:
        rec, truth, label = load(args.input, args.d, args.mode_given, {"test": args.test, "theta": args.theta})
    print(
        f"reconstructed {label}: {rec.n} samples, {len(rec.manifold)} simplices, "
        f"{rec.extraction.n_steps} steps ({time.perf_counter() - t0:.1f} s)",
        file=sys.stderr,
    )
    model = SceneModel()
    model.set_reconstruction(rec, truth=truth, source=label)
    if session is not None:
        fresh = (rec.test, float(rec.theta), rec.mode) != (session.test, session.theta, session.mode)
        for note in apply_session(model, session, fresh):
            print(f"session: {note}", file=sys.stderr)
    if args.projection:
        set_projection(model, args.projection)
    if args.layers:
        wanted = {s.strip() for s in args.layers.split(",") if s.strip()}
        unknown = wanted - set(model.layers)
        if unknown:
            raise InputError(f"unknown layers {sorted(unknown)}; choose from {', '.join(model.layers)}")
        for name, layer in model.layers.items():
            layer.visible = name in wanted
    scene = OffscreenScene(model, size)
    try:
        set_camera(scene, args.camera, session)
        t1 = time.perf_counter()
        if args.replay:
            try:
                steps = parse_steps(args.steps, rec.extraction.n_steps)
            except ValueError as err:
                raise InputError(str(err)) from None
            plan = plan_replay(rec.extraction.n_steps, steps, args.frames or DEFAULT_BUDGET)
            frames = framed_replay(scene, plan) if args.frame_steps else scene.replay(plan)
            total = len(plan.positions)
            print(f"replay: {plan.note()}", file=sys.stderr)
        else:
            model.player.last()
            if not args.layers:  # the last step's highlight means nothing in a tour
                model.layers["step"].visible = False
            total = args.frames or int(round(8 * args.fps))
            frames = scene.tour(total, args.fps)
        from .cli_progress import wants_bar

        # a bar on a terminal only: piped or redirected, stderr keeps the lines that say something
        bar = text_progress(sys.stderr, "rendering") if wants_bar(sys.stderr) else None
        written = write_frames(args.output, frames, total, args.fps, bar)
    finally:
        scene.close()
    secs = time.perf_counter() - t1
    size_note = ""
    if args.output.is_file():
        size_note = f", {args.output.stat().st_size / 1e6:.2f} MB"
    print(
        f"wrote {written} frames of {size[0]}x{size[1]} to {args.output}{size_note} "
        f"({secs:.1f} s, {1000 * secs / max(written, 1):.0f} ms a frame)"
    )
    return 0
