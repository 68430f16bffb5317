"""``crustview reconstruct``: one file to a result (and a report), or many files to a folder.

One input: ``crustview reconstruct IN -d D -o OUT [--report R.json]``.
Many (or ``--out-dir``): :mod:`crustview.cli_batch`.  ``-d auto`` estimates
d (:mod:`crustview.core.analysis.dimension`) and says what it chose and
why.  On a terminal a progress bar runs on stderr (:mod:`crustview.cli_progress`);
``-q`` prints nothing but errors.  Outputs are written atomically
(:mod:`crustview.atomic`); an output that is the input file is refused
unless ``--force``, and every output's folder is checked before the run,
so a failed command writes nothing.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

from crustview.cli_summaries import (  # noqa: F401 - also imported from here
    comparison_summary,
    extraction_summary,
    result_summary,
    verdict_line,
)
from crustview.core.errors import InputError
from crustview.core.result import CANDIDATE_TESTS

PROG = "crustview"
_PAPER_HELP = (
    "extract with the paper's Algorithm 3 exactly as printed (default: the robust extension, "
    "which returns the paper's result whenever that is a closed manifold through every sample)"
)


def dimension_arg(text: str) -> int | str:
    """``-d``: a positive integer or ``auto``."""
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return positive_int(text)
    except argparse.ArgumentTypeError as err:
        raise argparse.ArgumentTypeError(f"{err} (or 'auto')") from None


def add_parser(sub, angle_type) -> None:
    """The ``reconstruct`` sub-command's arguments."""
    p = sub.add_parser("reconstruct", help="reconstruct a manifold and write the result (one file, or many)")
    p.add_argument("input", type=Path, nargs="+", help="point file(s); several need --out-dir")
    p.add_argument(
        "-d",
        type=dimension_arg,
        required=True,
        help="intrinsic dimension, or 'auto' to estimate it from the sample (a d given that most of the local "
        "estimate's votes contradict is used, and named after the run)",
    )
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        default=None,
        help="result file: .npz, .ply, .off or .noff (any d and k), or .obj .vtk .stl (d <= 2, k <= 3)",
    )
    p.add_argument("--report", type=Path, default=None, help="also write a JSON report")
    p.add_argument(
        "--out-dir",
        type=Path,
        default=None,
        help="batch mode: write NAME.npz and NAME.report.json per input and summary.csv/summary.json here",
    )
    p.add_argument(
        "-j", "--jobs", type=positive_int, default=1, help="batch mode: files reconstructed at once (processes, >= 1)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors (no progress, no summary)")
    p.add_argument("--force", action="store_true", help="allow writing over the input file")
    p.add_argument(
        "--test", choices=CANDIDATE_TESTS, default="cocone", help="candidate test of Algorithm 2 (default: cocone)"
    )
    p.add_argument("--theta", type=angle_type, default=22.5, help="angle threshold in degrees (default: 22.5 = pi/8)")
    p.add_argument("--paper", action="store_true", help=_PAPER_HELP)
    p.add_argument(
        "--normals",
        choices=("paper", "smoothed"),
        default="paper",
        help="normal planes: 'paper' (Algorithm 1 as printed, the default) or 'smoothed' (averaged over the "
        "samples within 2 spacings: steadier under scanner noise, blurs a sparse sample's thin parts)",
    )
    p.add_argument(
        "--keep-boundary",
        action="store_true",
        help="paper mode only (implies --paper): do not prune (d-1)-faces with a single "
        "d-simplex (the paper prunes them); for looking at scans with holes, which "
        "cannot give a closed manifold",
    )


# ---------------------------------------------------------------- outputs
def _same_file(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        return False
    return a.resolve() == b.resolve()


def check_outputs(inputs: list[Path], outputs: list[Path], force: bool, hint: bool = True) -> None:
    """Refuse outputs in missing folders, outputs that are folders, and (without ``force``) the input itself.

    Raises
    ------
    InputError
        One sentence naming the output.
    """
    probed: set[Path] = set()
    for out in outputs:
        parent = out.parent if str(out.parent) else Path(".")
        if not parent.is_dir():
            raise InputError(f"Cannot write '{out}': the folder '{parent}' does not exist.")
        if out.is_dir():
            raise InputError(f"Cannot write '{out}': it is a folder.")
        if parent.resolve() not in probed:
            _probe_folder(out, parent)
            probed.add(parent.resolve())
        for inp in inputs:
            if not force and _same_file(out, inp):
                raise InputError(
                    f"Refusing to write over the input file '{inp}' (output '{out}'): "
                    "choose another output name" + (", or give --force." if hint else ".")
                )
    seen: dict[Path, Path] = {}
    for out in outputs:
        key = out.resolve()
        if key in seen:
            raise InputError(f"Cannot write '{out}' twice: the result and the report need different names.")
        seen[key] = out


def positive_int(text: str) -> int:
    """An argparse type: a whole number of at least 1 (``-j``, and ``crustview sample -n``)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def _probe_folder(out: Path, parent: Path) -> None:
    """Create and drop a file in ``parent``: a folder that cannot be written to fails here, before the run.

    A permission test (``os.access``) says yes to root on a read-only file system; creating a file does not.
    """
    import tempfile

    try:
        with tempfile.TemporaryFile(dir=parent):
            pass
    except OSError as err:
        reason = err.strerror or type(err).__name__
        raise InputError(
            f"Cannot write '{out}': the folder '{parent}' cannot be written to (creating a file there: {reason})."
        ) from None


def _previous(path: Path) -> bytes | None:
    """The bytes of an existing file (to put back if a later output fails), None if there is none."""
    try:
        return path.read_bytes() if path.is_file() else None
    except OSError:
        return None


def _put_back(path: Path, old: bytes | None) -> None:
    """Undo a new output: the previous content again (atomically), or no file where there was none."""
    from crustview.atomic import write_bytes

    try:
        if old is None:
            path.unlink(missing_ok=True)
        else:
            write_bytes(path, old)
    except OSError:
        pass  # the error being raised says what failed; this file is then the new one


# ---------------------------------------------------------------- one file
def read_input(path: Path, notes: list[str]) -> tuple[Any, Any, dict]:
    """The mesh (or None), the points and the per-point attributes of an input file."""
    from crustview.io import read_attributes, read_mesh, read_points

    mesh = read_mesh(path, notes)  # a mesh with faces: its vertices are the sample, its faces the truth
    if mesh is not None:
        return mesh, mesh.points, read_attributes(path)
    attributes: dict = {}
    points = read_points(path, notes, attributes)
    return mesh, points, attributes


def choose_d(points, d: int | str, mesh=None) -> tuple[int, Any]:
    """``d`` itself, or the estimate for ``auto`` (with its :class:`DimensionEstimate`).

    A mesh file's faces decide where local PCA chose a d they cannot have (:func:`with_faces`).
    """
    if d != "auto":
        return int(d), None
    from crustview.core.analysis.dimension import estimate_file_dimension

    est = estimate_file_dimension(points, mesh)
    return est.d, est


def reconstruct_file(
    path: Path,
    output: Path,
    report: Path | None,
    args: argparse.Namespace,
    progress=None,
    say=None,
) -> dict[str, Any]:
    """Read, reconstruct and write one file; returns its summary row (see :mod:`crustview.cli_batch`).

    ``say(kind, text)`` receives the notes and warnings (``kind`` "note" or
    "warning") and the summary lines (``kind`` "summary").
    """
    from crustview.core import cost_warning, reconstruct
    from crustview.io import write_report, write_result

    say = say or (lambda kind, text: None)
    progress = progress or (lambda stage, fraction: None)
    start = time.perf_counter()
    progress("read", 0.0)
    notes: list[str] = []
    mesh, points, attributes = read_input(path, notes)
    for line in notes:
        say("note", line)
    progress("estimate d" if args.d == "auto" else "read", 1.0)
    d, estimate = choose_d(points, args.d, mesh)
    if estimate is not None:
        say("note", f"{path.name}: -d auto chose {estimate.sentence()}")
    k = points.shape[1]
    truth = mesh.simplices(d) if mesh is not None and 1 <= d < k else None
    truth_name = path.name
    if mesh is None and 1 <= d < k:  # a result written with its mesh's faces is judged against them again
        stored = _stored_mesh(path, d)
        if stored is not None:
            truth_name, truth = stored
            say("note", f"{path.name}: judged against the faces of {truth_name} stored with it")
    note = cost_warning(k, d) if 1 <= d < k else None
    if note:
        say("warning", note)
    mode = "paper" if args.paper or args.keep_boundary else "robust"
    try:
        rec = reconstruct(
            points,
            d,
            test=args.test,
            theta=math.radians(args.theta),
            prune_boundary=not args.keep_boundary,
            mode=mode,
            progress=progress,
            normals=getattr(args, "normals", "paper"),
        )
    except InputError as err:  # the points of this file cannot be used: say which file
        if path.name in str(err):
            raise
        raise InputError(f"{path.name}: {err}") from None
    seconds = time.perf_counter() - start
    comparison = None
    if truth is not None:
        from crustview.core.analysis.compare import compare_to_mesh

        progress("compare", 0.0)
        comparison = compare_to_mesh(rec, truth)
    # a -d given by hand that the sample contradicts: estimated after the run, on its distinct samples (a file
    # the run refuses gets its one error line and nothing else), said once both outputs are written
    doubt = None if estimate is not None else _doubted(rec, d, mesh)
    extra = _report_extra(rec, attributes, estimate or doubt)
    if doubt is not None:
        extra["dimension_estimate"]["given_d"] = d
    progress("write", 0.0)
    kept = None if truth is None else (truth_name, truth)  # stored with the result: reopened, it is judged again
    if report is None:
        write_result(output, rec, mesh=kept)
    else:
        # the small report first: if either write fails, neither output changes (a failed command writes nothing)
        old = _previous(report)
        write_report(report, rec, comparison, extra=extra)
        try:
            write_result(output, rec, mesh=kept)
        except BaseException:
            _put_back(report, old)
            raise
    progress("write", 1.0)
    if doubt is not None:
        say("note", f"{path.name}: -d {d} was given, but the sample looks like {doubt.sentence()}")
    from crustview.report import result_verdict

    level, sentence = result_verdict(rec, comparison)
    say("summary", result_summary(rec, seconds, output))
    say("summary", extraction_summary(rec))
    if comparison is not None:
        say("summary", comparison_summary(comparison, truth_name))
    for line in _attribute_lines(extra):
        say("summary", line)
    say("summary", verdict_line(level, sentence, bool(rec.uncertain_features)))
    return summary_row(path, rec, seconds, output, report, estimate, level, doubt)


def _stored_mesh(path: Path, d: int) -> tuple[str, Any] | None:
    """The mesh truth stored in a result ``.npz`` (:mod:`crustview.resulttruth`) when it is for this ``d``."""
    from crustview.io import read_run_parameters

    saved = read_run_parameters(path)
    stored = None if saved is None else saved.get("mesh")
    return stored if stored is not None and stored[1].shape[1] == d + 1 else None


def _doubted(rec, d: int, mesh) -> Any:
    """The estimate where it contradicts an explicit ``-d`` (:func:`.dimension.contradiction`), on the run's samples."""
    from crustview.core.analysis.dimension import contradiction

    return contradiction(rec.points, d, mesh, distinct=True)


def _report_extra(rec, attributes: dict, estimate) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if estimate is not None:
        out["dimension_estimate"] = estimate.as_dict()
    if attributes:
        from crustview.attributes import report_section

        out["input_attributes"] = report_section(rec, attributes)
    return out


def _attribute_lines(extra: dict[str, Any]) -> list[str]:
    section = extra.get("input_attributes") or {}
    angles = section.get("normal_angles")
    if not angles:
        return []
    return [
        f"File normals against AN_s: median angle {angles['median_degrees']:.1f} deg, "
        f"90th percentile {angles['p90_degrees']:.1f} deg, {angles['over_30_degrees']} of {angles['n']} over 30 deg."
    ]


def summary_row(
    path: Path, rec, seconds: float, output: Path, report: Path | None, estimate, verdict: str, doubt=None
) -> dict[str, Any]:
    """One row of the batch summary.

    ``verdict``: :func:`crustview.report.result_verdict`'s word; ``doubt``: the estimate that contradicts a
    ``-d`` given by hand, if any.
    """
    top = rec.topology
    kinds = {kind: sum(f.kind == kind for f in rec.uncertain_features) for kind in ("handle", "hole", "component")}
    return {
        "file": str(path),
        "status": "ok",
        "verdict": verdict,
        "points": int(len(rec.input_points)),
        "k": int(rec.k),
        "d": int(rec.d),
        "d_auto_confidence": None if estimate is None else round(float(estimate.confidence), 3),
        "d_estimate_contradicts": None if doubt is None else int(doubt.d),
        "closed": bool(top.closed_manifold),
        "betti": [int(b) for b in top.betti],
        "uncertain_handles": kinds["handle"],
        "uncertain_holes": kinds["hole"],
        "uncertain_components": kinds["component"],
        "seconds": round(float(seconds), 3),
        "output": str(output),
        "report": None if report is None else str(report),
        "error": None,
    }


def run(args: argparse.Namespace) -> int:
    """The ``reconstruct`` sub-command."""
    from crustview.cli_progress import StageProgress, wants_bar

    if args.out_dir is not None or len(args.input) > 1:
        from crustview import cli_batch

        return cli_batch.run(args)
    if args.output is None:
        raise InputError("give -o OUTPUT for the result (or --out-dir DIR to reconstruct many files)")
    if args.keep_boundary and not args.paper:
        _say(args)(
            "note",
            "--keep-boundary belongs to the paper's Algorithm 3 (the robust extension never prunes); "
            "running it as with --paper",
        )
    path = args.input[0]
    outputs = [args.output] + ([args.report] if args.report is not None else [])
    check_outputs([path], outputs, args.force)
    summary: list[str] = []  # printed when the bar is gone
    with StageProgress(path.name, wants_bar(sys.stderr, args.quiet)) as bar:
        row = reconstruct_file(path, args.output, args.report, args, bar, _say(args, bar, summary))
    for line in summary:
        print(line, flush=True)
    return verdict_status(row["verdict"])


#: Verdicts after which ``reconstruct`` exits with status 1: the result was written, but it is no closed manifold
#: where one was asked for ("failed"), or the input mesh's own faces contradict it ("wrong").  A script that
#: runs with ``-q`` tells them from "sure" and "uncertain" (status 0) without reading the report.
BAD_VERDICTS = ("failed", "wrong")


def verdict_status(verdict: str) -> int:
    """The exit status of a written result: 1 for :data:`BAD_VERDICTS`, else 0."""
    return 1 if verdict in BAD_VERDICTS else 0


def _say(args: argparse.Namespace, bar=None, summary: list[str] | None = None):
    def say(kind: str, text: str) -> None:
        if args.quiet:
            return
        if kind == "summary":
            if summary is None:
                print(text, flush=True)
            else:
                summary.append(text)
        elif bar is not None:
            bar.note(f"{PROG}: {kind}: {text}")
        else:
            print(f"{PROG}: {kind}: {text}", file=sys.stderr, flush=True)

    return say
