"""Command line: ``crustview [view|reconstruct|sample|list] ...``.

Without a sub-command the viewer starts with its demo.  Errors are reported
as one line ``crustview: error: <message>`` on stderr: exit status 2 for bad
input or usage, 1 for an unexpected failure.  Only ``crustview`` and
``crustview view`` import Qt, and only when they run.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from crustview import __version__
from crustview.core.analysis.features import summary_suffix
from crustview.core.errors import CrustviewError
from crustview.core.result import CANDIDATE_TESTS

PROG = "crustview"


class _UsageError(Exception):
    """Raised instead of argparse printing the usage and exiting."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{message} (see '{self.prog} --help')")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def _nonnegative_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"expected a finite number >= 0, got {text}")
    return value


def _angle_degrees(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an angle in degrees, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite angle in degrees, got {text}")
    return value  # the core checks the range (and says so in degrees)


_PAPER_HELP = (
    "extract with the paper's Algorithm 3 exactly as printed (default: the robust extension, "
    "which returns the paper's result whenever that is a closed manifold through every sample)"
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (sub-commands view, reconstruct, sample, list)."""
    parser = _Parser(
        prog=PROG,
        description="Reconstruct a closed d-manifold in R^k from a point sample "
        "(generalized crust) and view every stage.  Run without arguments to "
        "start the viewer.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    p = sub.add_parser("view", help="open a point file or a saved session in the viewer")
    p.add_argument("file", type=Path, help="point file (.npy .npz .csv .txt .xyz .ply ...) or SESSION.crustview.json")
    p.add_argument("-d", type=_positive_int, default=None, help="intrinsic dimension")
    p.add_argument("--paper", action="store_true", help=_PAPER_HELP)

    p = sub.add_parser("reconstruct", help="reconstruct a manifold and write the result")
    p.add_argument("input", type=Path, help="point file")
    p.add_argument("-d", type=_positive_int, required=True, help="intrinsic dimension")
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        help="result file: .npz, or .ply .obj .off .vtk .stl for d <= 2, k <= 3",
    )
    p.add_argument("--report", type=Path, default=None, help="also write a JSON report")
    p.add_argument(
        "--test", choices=CANDIDATE_TESTS, default="cocone", help="candidate test of Algorithm 2 (default: cocone)"
    )
    p.add_argument(
        "--theta", type=_angle_degrees, default=22.5, help="angle threshold in degrees (default: 22.5 = pi/8)"
    )
    p.add_argument("--paper", action="store_true", help=_PAPER_HELP)
    p.add_argument(
        "--keep-boundary",
        action="store_true",
        help="paper mode only (implies --paper): do not prune (d-1)-faces with a single "
        "d-simplex (the paper prunes them); for looking at scans with holes, which "
        "cannot give a closed manifold",
    )

    p = sub.add_parser("sample", help="sample a built-in manifold to a point file")
    p.add_argument("name", help="manifold name (see 'crustview list')")
    p.add_argument("-n", type=_positive_int, default=None, help="number of points (default: the manifold's default)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument(
        "--noise",
        type=_nonnegative_float,
        default=0.0,
        help="Gaussian noise in units of the point spacing (default: 0)",
    )
    p.add_argument("--density", choices=("uniform", "nonuniform"), default="uniform")
    p.add_argument(
        "--method", choices=("even", "random"), default="even", help="even spacing (default) or i.i.d. points"
    )
    p.add_argument("-o", "--output", type=Path, required=True, help="point file (.npy .npz .csv .txt .xyz .ply .vtk)")

    sub.add_parser("list", help="list the built-in manifolds")
    _add_demo_commands(sub)
    return parser


def _add_demo_commands(sub) -> None:
    """Sub-commands kept in their own modules (render, compare)."""
    from crustview import cli_compare, cli_render

    cli_render.add_parser(sub)
    cli_compare.add_parser(sub)


def _check_display() -> None:
    """Fail with one line when no screen is reachable (Qt would abort the process)."""
    if not sys.platform.startswith("linux") or os.environ.get("QT_QPA_PLATFORM") or os.environ.get("WAYLAND_DISPLAY"):
        return
    hint = "run it on a desktop, under 'xvfb-run', or use 'crustview reconstruct' for headless work"
    display = os.environ.get("DISPLAY")
    if not display:
        raise _UsageError(f"no display: DISPLAY is not set ({hint})")
    if not _x_display_opens(display):
        raise _UsageError(f"no display: cannot connect to the X display '{display}' ({hint})")


def _x_display_opens(display: str) -> bool:
    """Whether Xlib can open ``display``; True when Xlib itself is not found (let Qt try)."""
    import ctypes
    import ctypes.util

    name = ctypes.util.find_library("X11")
    if name is None:
        return True
    try:
        xlib = ctypes.CDLL(name)
    except OSError:
        return True
    xlib.XOpenDisplay.restype = ctypes.c_void_p
    xlib.XOpenDisplay.argtypes = [ctypes.c_char_p]
    xlib.XCloseDisplay.argtypes = [ctypes.c_void_p]
    handle = xlib.XOpenDisplay(display.encode())
    if not handle:
        return False
    xlib.XCloseDisplay(handle)
    return True


def _run_app(*args: object, **kwargs: object) -> int:
    _check_display()
    try:
        from crustview.qt.app import run_app
    except ImportError as err:
        print(f"{PROG}: error: the viewer cannot start ({_one_line(err)})", file=sys.stderr)
        return 1
    return int(run_app(*args, **kwargs) or 0)


def _summary(rec, seconds: float, output: Path) -> str:
    top = rec.topology
    word = {1: "curve", 2: "surface"}.get(rec.d, f"{rec.d}-manifold")
    merged = len(rec.input_points) - rec.n
    dup = f" ({merged} duplicates merged)" if merged else ""
    closed = "a closed manifold" if top.closed_manifold else "NOT a closed manifold"
    parts = [
        f"Reconstructed a {word} in R^{rec.k} from {rec.n} points{dup}: {top.n_simplices} {rec.d}-simplices, {closed}",
        f"Betti numbers (Z/2) {tuple(int(b) for b in top.betti)}, Euler characteristic {top.euler}",
    ]
    if top.orientable is not None:
        parts.append("orientable" if top.orientable else "non-orientable")
    if not top.closed_manifold:
        parts.append(
            f"{top.boundary_faces} boundary and {top.nonmanifold_faces} non-manifold faces, "
            f"{top.unused_samples} unused samples"
        )
    text = "; ".join(parts) + f"; {seconds:.2f} s; wrote {output}."
    notes = set(rec.extraction.notes)  # said on the extraction line
    messages = [m for m in top.messages if m not in notes and not m.startswith("the sample does not support")]
    if messages:
        text += " Note: " + "; ".join(str(m).rstrip(".") for m in messages) + "."
    suffix = summary_suffix(rec.features)
    return text + (f" {suffix}" if suffix else "")


def extraction_summary(rec) -> str:
    """One sentence: which extraction ran, why, and how many steps of each rule.

    Parameters
    ----------
    rec : Reconstruction

    Returns
    -------
    str
        E.g. ``"extraction: robust (the paper's Algorithm 3 was abandoned after
        127 steps, ...); 2160 steps: seed 1, grow 2068, ..."`` or
        ``"extraction: paper's Algorithm 3; 12 steps: prune-sharp 0,
        resolve-nonmanifold 12."``.  A robust run lists only the rules it
        used; a paper run lists both of the paper's rules.
    """
    ext = rec.extraction
    if rec.mode == "paper":
        head = "extraction: paper's Algorithm 3"
        if not rec.prune_boundary:
            head += " with boundary faces kept (--keep-boundary)"
    else:
        why = "; ".join(str(n).rstrip(".") for n in ext.notes)
        head = "extraction: robust" + (f" ({why})" if why else "")
    counts = ext.counts_by_rule()
    shown = [f"{rule} {c['steps']}" for rule, c in counts.items() if c["steps"] or rec.mode == "paper"]
    return f"{head}; {ext.n_steps} steps" + (": " + ", ".join(shown) if shown else "") + "."


def _cmd_reconstruct(args: argparse.Namespace) -> int:
    from crustview.core import cost_warning, reconstruct
    from crustview.io import read_mesh, read_points, write_report, write_result

    mesh = read_mesh(args.input)  # a mesh with faces: its vertices are the sample, its faces the truth
    read_notes: list[str] = []  # e.g. a text file's header line of column names
    points = mesh.points if mesh is not None else read_points(args.input, read_notes)
    for line in read_notes:
        print(f"{PROG}: note: {line}", file=sys.stderr, flush=True)
    truth = mesh.simplices(args.d) if mesh is not None and 1 <= args.d < points.shape[1] else None
    note = cost_warning(points.shape[1], args.d) if 1 <= args.d < points.shape[1] else None
    if note:
        print(f"{PROG}: warning: {note}", file=sys.stderr, flush=True)
    if args.keep_boundary and not args.paper:
        print(
            f"{PROG}: note: --keep-boundary belongs to the paper's Algorithm 3 (the robust extension "
            "never prunes); running it as with --paper",
            file=sys.stderr,
            flush=True,
        )
    mode = "paper" if args.paper or args.keep_boundary else "robust"
    start = time.perf_counter()
    rec = reconstruct(
        points, args.d, test=args.test, theta=math.radians(args.theta), prune_boundary=not args.keep_boundary, mode=mode
    )
    seconds = time.perf_counter() - start
    comparison = None
    if truth is not None:
        from crustview.core.analysis.compare import compare_to_mesh

        comparison = compare_to_mesh(rec, truth)
    write_result(args.output, rec)
    if args.report is not None:
        write_report(args.report, rec, comparison)
    print(_summary(rec, seconds, args.output))
    print(extraction_summary(rec))
    if comparison is not None:
        print(comparison_summary(comparison, args.input.name))
    return 0


def comparison_summary(c, name: str) -> str:
    """One sentence: M_S against the mesh's faces."""
    from crustview.core.analysis.compare import MeshComparison

    def top(t) -> str:
        g = MeshComparison.genus(t)
        shape = f"closed, genus {g}" if g is not None else ("closed" if t.closed_manifold else "not closed")
        return f"{shape}, Betti {tuple(int(b) for b in t.betti)}"

    h = c.hausdorff
    collapsed = f" ({c.collapsed_faces} collapsed by duplicate merging)" if c.collapsed_faces else ""
    return (
        f"Against the faces of {name}: {c.recovered} of {c.mesh_faces} mesh faces recovered "
        f"({100 * c.recovered_share:.1f}%){collapsed}, {c.extra} extra; mesh {top(c.mesh_topology)}; "
        f"M_S {top(c.result_topology)}; Hausdorff distance {h.distance:.4g} "
        f"(sampled, within {h.error_bound:.2g})."
    )


def _cmd_sample(args: argparse.Namespace) -> int:
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_points

    manifold = get_manifold(args.name)
    n = manifold.default_n if args.n is None else args.n
    sample = manifold.sample(n, seed=args.seed, noise=args.noise, density=args.density, method=args.method)
    write_points(args.output, sample.points)
    print(
        f"Wrote {n} points of {manifold.name} (d={manifold.d}, k={manifold.k}) to {args.output}; "
        f"reconstruct with: crustview reconstruct {args.output} -d {manifold.d} -o OUTPUT"
    )
    return 0


def _cmd_list() -> int:
    from crustview.core.samples.manifolds import MANIFOLDS

    print(f"{'name':<15} {'k':>2} {'d':>2}  {'betti (Z/2)':<13} {'euler':>5}  "
          f"{'orient.':<7} {'cosph.':<6} {'n':>5}  description")  # fmt: skip
    for m in MANIFOLDS.values():
        betti = "(" + ",".join(str(b) for b in m.betti) + ")"
        print(
            f"{m.name:<15} {m.k:>2} {m.d:>2}  {betti:<13} {m.euler:>5}  "
            f"{'yes' if m.orientable else 'no':<7} {'yes' if m.cospherical else 'no':<6} "
            f"{m.default_n:>5}  {m.description}"
        )
    return 0


def _dispatch(argv: Sequence[str]) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:  # --help and --version
        return int(stop.code or 0)
    if args.command is None:
        return _run_app()
    if args.command == "view":
        from crustview.io import read_mesh, read_points
        from crustview.session import FileSource, is_session_path, read_session, resolve_input

        if is_session_path(args.file):  # a session holds its own input, d and mode
            if args.d is not None or args.paper:
                raise _UsageError("a session holds its own d and extraction mode: give no -d or --paper with it")
            s = read_session(args.file)
            if isinstance(s.source, FileSource):
                resolve_input(s.source, args.file)  # moved or changed: one line here, not in a window
            return _run_app(str(args.file))
        mesh = read_mesh(args.file)  # report a bad file (or bad faces) here, before a window opens
        points = mesh.points if mesh is not None else read_points(args.file)
        k = points.shape[1]
        if args.d is not None and not 1 <= args.d < k:
            raise _UsageError(f"d must be between 1 and k-1 = {k - 1} for points in R^{k}; got d = {args.d}")
        if mesh is not None and args.d is not None:
            mesh.simplices(args.d)
        return _run_app(str(args.file), args.d, mode="paper" if args.paper else None)
    if args.command == "reconstruct":
        return _cmd_reconstruct(args)
    if args.command == "sample":
        return _cmd_sample(args)
    if args.command == "render":
        from crustview import cli_render

        return cli_render.run(args)
    if args.command == "compare":
        from crustview import cli_compare

        return cli_compare.run(args)
    return _cmd_list()


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 success, 2 bad input or usage, 1 unexpected failure,
        130 interrupted.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        return _dispatch(argv)
    except (_UsageError, CrustviewError) as err:
        print(f"{PROG}: error: {_one_line(err)}", file=sys.stderr)
        return 2
    except OSError as err:
        name = f" '{err.filename}'" if err.filename else ""
        print(f"{PROG}: error:{name} {_one_line(err.strerror or err)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{PROG}: error: interrupted", file=sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - one line, never a traceback
        print(f"{PROG}: error: unexpected {type(err).__name__}: {_one_line(err)}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
