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

from .core.errors import InputError

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


def add_parser(sub) -> None:
    """Register ``render`` on the sub-parsers action ``sub``."""
    p = sub.add_parser("render", help="render a replay or a grand tour to .gif, .mp4 or a folder of PNGs (headless)")
    p.add_argument("input", help="point file, saved result .npz, or a built-in manifold name (see 'crustview list')")
    p.add_argument("-d", type=int, default=None, help="intrinsic dimension (default: the built-in's, or the result's)")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--replay", action="store_true", help="replay the steps of Algorithm 3")
    what.add_argument("--tour", action="store_true", help="a grand tour of R^k around the final M_S")
    p.add_argument("-o", "--output", type=Path, required=True, help="OUT.gif, OUT.mp4 or a folder for PNG frames")
    p.add_argument("--size", type=_size, default=DEFAULT_SIZE, help="frame size WxH (default 640x480)")
    p.add_argument("--fps", type=_fps, default=12.0, help="frames per second (default 12)")
    p.add_argument("--steps", default=None, help="replay only steps A:B (default: all)")
    p.add_argument(
        "--frames",
        type=int,
        default=None,
        help="frame budget: a longer replay is subsampled (default 90); tour length (default 8 s)",
    )
    p.add_argument("--mode", choices=("robust", "paper"), default="robust", help="extraction mode (default robust)")
    p.add_argument(
        "--layers",
        default=None,
        help="comma-separated layers to show instead of the defaults, e.g. manifold,points,step",
    )


def load(source: str, d: int | None, mode: str):
    """Reconstruct ``source`` (a built-in name or a file): returns (rec, truth, label)."""
    from .core import reconstruct
    from .core.samples.manifolds import MANIFOLDS

    path = Path(source)
    if not path.exists() and source in MANIFOLDS:
        m = MANIFOLDS[source]
        sample = m.sample(m.default_n, seed=0)
        rec = reconstruct(sample.points, d or m.d, mode=mode)
        return rec, sample, f"{source} (n = {m.default_n})"
    from .io import read_mesh, read_points, read_run_parameters

    params = read_run_parameters(path)
    mesh = read_mesh(path) if params is None else None
    points = mesh.points if mesh is not None else read_points(path)
    kwargs = {}
    if params is not None:
        d = d or params["d"]
        kwargs = {"test": params["test"], "theta": params["theta"], "prune_boundary": params["prune_boundary"]}
    if d is None:
        raise InputError(f"give the intrinsic dimension with -d for '{path.name}'")
    if not 1 <= d < points.shape[1]:
        raise InputError(f"d must be between 1 and k-1 = {points.shape[1] - 1}; got d = {d}")
    return reconstruct(points, d, mode=mode, **kwargs), None, path.name


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
    t0 = time.perf_counter()
    rec, truth, label = load(args.input, args.d, args.mode)
    print(
        f"reconstructed {label}: {rec.n} samples, {len(rec.manifold)} simplices, "
        f"{rec.extraction.n_steps} steps ({time.perf_counter() - t0:.1f} s)",
        file=sys.stderr,
    )
    model = SceneModel()
    model.set_reconstruction(rec, truth=truth, source=label)
    if args.layers:
        wanted = {s.strip() for s in args.layers.split(",") if s.strip()}
        unknown = wanted - set(model.layers)
        if unknown:
            raise InputError(f"unknown layers {sorted(unknown)}; choose from {', '.join(model.layers)}")
        for name, layer in model.layers.items():
            layer.visible = name in wanted
    scene = OffscreenScene(model, size)
    try:
        t1 = time.perf_counter()
        if args.replay:
            try:
                steps = parse_steps(args.steps, rec.extraction.n_steps)
            except ValueError as err:
                raise InputError(str(err)) from None
            plan = plan_replay(rec.extraction.n_steps, steps, args.frames or DEFAULT_BUDGET)
            frames, total = scene.replay(plan), len(plan.positions)
            print(f"replay: {plan.note()}", file=sys.stderr)
        else:
            model.player.last()
            if not args.layers:  # the last step's highlight means nothing in a tour
                model.layers["step"].visible = False
            total = args.frames or int(round(8 * args.fps))
            frames = scene.tour(total, args.fps)
        written = write_frames(args.output, frames, total, args.fps, text_progress(sys.stderr, "rendering"))
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
