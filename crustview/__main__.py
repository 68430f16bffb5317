"""Command line: ``crustview [view|reconstruct|sample|list] ...``.

Without a sub-command the viewer starts with its demo.  Errors are reported
as one line ``crustview: error: <message>`` on stderr: exit status 2 for bad
input or usage, 1 for an unexpected failure, and 1 also after ``reconstruct``
wrote a result whose verdict is failed or wrong (or, with several files or
``--out-dir``, when a file could not be reconstructed).  Only ``crustview`` and
``crustview view`` import Qt, and only when they run.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from crustview import __version__, cli_reconstruct
from crustview.cli_reconstruct import comparison_summary, extraction_summary  # noqa: F401 - their old home
from crustview.core.errors import CrustviewError

PROG = "crustview"


class _UsageError(Exception):
    """Raised instead of argparse printing the usage and exiting."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{message} (see '{self.prog} --help')")


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
    p.add_argument(
        "-d", type=cli_reconstruct.dimension_arg, default=None, help="intrinsic dimension, or 'auto' (default: ask)"
    )
    p.add_argument("--paper", action="store_true", help=_PAPER_HELP)

    cli_reconstruct.add_parser(sub, _angle_degrees)

    p = sub.add_parser("sample", help="sample a built-in manifold to a point file")
    p.add_argument("name", help="manifold name (see 'crustview list')")
    p.add_argument(
        "-n", type=cli_reconstruct.positive_int, default=None, help="number of points (default: the manifold's default)"
    )
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


#: Points above which ``crustview sample`` says first how long an even sample takes (measured here: 40,000
#: in 9.6 s, 300,000 in 124 s, about 0.4 ms a point; a minute from some 150,000).
SAMPLE_SLOW_N = 100_000


def _cmd_sample(args: argparse.Namespace) -> int:
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_points

    manifold = get_manifold(args.name)
    n = manifold.default_n if args.n is None else args.n
    if args.method == "even" and n > SAMPLE_SLOW_N:
        # the even sampler's greedy farthest-point pass is one pick at a time: about 0.4 ms a point here
        print(
            f"crustview: note: sampling {n:,} points evenly takes about {0.4e-3 * n / 60:.0f} minute(s) on a 2-core "
            "machine (one farthest point at a time); --method random draws i.i.d. points at once.",
            file=sys.stderr,
            flush=True,
        )
    sample = manifold.sample(n, seed=args.seed, noise=args.noise, density=args.density, method=args.method)
    write_points(args.output, sample.points)
    head = f"Wrote {n} points of {manifold.name} (d={manifold.d}, k={manifold.k}) to {args.output}"
    if n < manifold.k + 2:  # reconstruct refuses fewer than k + 2 samples: no command that would fail
        print(f"{head}; too few to reconstruct (points in R^{manifold.k} need at least {manifold.k + 2})")
    else:
        print(f"{head}; reconstruct with: crustview reconstruct {args.output} -d {manifold.d} -o OUTPUT")
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
        if args.d == "auto":
            from crustview.core.analysis.dimension import estimate_file_dimension

            estimate = estimate_file_dimension(points, mesh)
            print(f"{PROG}: note: {args.file.name}: -d auto chose {estimate.sentence()}", file=sys.stderr, flush=True)
            args.d = estimate.d
        if args.d is not None and not 1 <= args.d < k:
            raise _UsageError(f"d must be between 1 and k-1 = {k - 1} for points in R^{k}; got d = {args.d}")
        if mesh is not None and args.d is not None:
            mesh.simplices(args.d)
        return _run_app(str(args.file), args.d, mode="paper" if args.paper else None)
    if args.command == "reconstruct":
        return cli_reconstruct.run(args)
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
        Exit status: 0 success, 2 bad input or usage, 1 unexpected failure or a written result whose
        verdict is failed or wrong (:data:`crustview.cli_reconstruct.BAD_VERDICTS`; a batch's rule:
        :mod:`crustview.cli_batch`), 130 interrupted.
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
    except KeyboardInterrupt:  # atomic writes (crustview.atomic) leave no partial file
        print(f"{PROG}: cancelled (Ctrl-C); no partial file was written", file=sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - one line, never a traceback
        print(f"{PROG}: error: unexpected {type(err).__name__}: {_one_line(err)}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
