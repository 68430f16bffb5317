"""``crustview reconstruct A B C ... --out-dir DIR [-j N]``: many files, N processes, one summary.

For every input ``NAME.ext`` it writes ``DIR/NAME.npz`` and
``DIR/NAME.report.json`` (a number is added to names that two inputs
share), prints one row per file as it finishes, and writes
``DIR/summary.csv`` and ``DIR/summary.json`` (in the order of the inputs):
file, status ("ok", or "error" for a file that could not be reconstructed), verdict (sure, uncertain, wrong or
failed; empty for an error), points, k, d, closed, Betti numbers, uncertain handles,
holes and components, seconds, outputs and the error of a file that could not be reconstructed.
The exit status is 1 when a file could not be reconstructed or its verdict is failed or wrong
(:data:`~crustview.cli_reconstruct.BAD_VERDICTS`, as for one file), 0 otherwise.  Ctrl-C
stops the workers; every file is written atomically, so nothing partial
is left, and where some files were done the summaries list them, the others
as cancelled.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import sys
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any

from crustview.atomic import write_text
from crustview.cli_reconstruct import BAD_VERDICTS
from crustview.core.errors import CrustviewError, InputError

#: The verdicts of a written result, in the closing line's order (:func:`crustview.report.result_verdict`).
VERDICTS = ("sure", "uncertain", "wrong", "failed")

#: Columns of summary.csv.
COLUMNS = (
    "file",
    "status",
    "verdict",
    "points",
    "k",
    "d",
    "d_auto_confidence",
    "d_estimate_contradicts",
    "closed",
    "betti",
    "uncertain_handles",
    "uncertain_holes",
    "uncertain_components",
    "seconds",
    "output",
    "report",
    "error",
)


def output_names(inputs: list[Path], out_dir: Path) -> list[tuple[Path, Path]]:
    """The result and report path of each input (names made unique)."""
    used: set[str] = set()
    out = []
    for path in inputs:
        stem, i = path.stem, 1
        while stem in used:
            i += 1
            stem = f"{path.stem}-{i}"
        used.add(stem)
        out.append((out_dir / f"{stem}.npz", out_dir / f"{stem}.report.json"))
    return out


def _job(path: Path, output: Path, report: Path, args: argparse.Namespace) -> tuple[dict[str, Any], list[str]]:
    """One file in a worker: its row and the lines it would print."""
    from crustview.cli_reconstruct import reconstruct_file

    lines: list[str] = []
    start = time.perf_counter()
    try:
        row = reconstruct_file(path, output, report, args, None, lambda kind, text: lines.append(f"{kind}: {text}"))
    except CrustviewError as err:
        row = _failed(path, " ".join(str(err).split()), start)
    except Exception as err:  # noqa: BLE001 - one file's failure is its row, not the batch's end
        row = _failed(path, f"unexpected {type(err).__name__}: {' '.join(str(err).split())}", start)
    return row, lines


def _worker_ignores_ctrl_c(own_process_only: bool) -> None:
    """Workers leave Ctrl-C to the parent, which stops them (no traceback from each worker).

    With ``own_process_only`` (two workers or more) they also keep each run in their own process: every
    core already runs a file, so the robust extraction's helper process
    (:mod:`crustview.core.util.second_core`) would only compete.
    """
    import os
    import signal

    from .core.util.second_core import PROCESSES_ENV

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if own_process_only:
        os.environ[PROCESSES_ENV] = "1"


def _failed(path: Path, error: str, start: float) -> dict[str, Any]:
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    row.update(file=str(path), status="error", verdict=None, error=error, seconds=round(time.perf_counter() - start, 3))
    return row


def _show(show, row: dict[str, Any], lines: list[str]) -> None:
    """A file's row, and for a failed one the notes read before it failed.

    Why a file's z = 0 made d = 2 impossible says the note, not the error.
    """
    show(row_line(row))
    if row["status"] != "ok":
        for line in lines:
            show(f"  {line}")


def _contradicted(row: dict[str, Any]) -> str:
    """What a row adds after a given d that local PCA contradicts, e.g. ``(given; the sample looks like d = 2)``."""
    other = row.get("d_estimate_contradicts")
    return "" if other is None else f" (given; the sample looks like d = {other})"


def row_line(row: dict[str, Any]) -> str:
    """One printed row."""
    name = Path(row["file"]).name
    if row["status"] != "ok":
        error = str(row["error"])
        error = error[len(name) + 2 :] if error.startswith(f"{name}: ") else error  # named once
        return f"{name}: not reconstructed: {error}"
    closed = "closed" if row["closed"] else "not closed"
    unc = row["uncertain_handles"] + row["uncertain_holes"] + row["uncertain_components"]
    return (
        f"{name}: {row['verdict']}: {row['points']} points, d = {row['d']}{_contradicted(row)}, {closed}, "
        f"Betti {tuple(row['betti'])}, "
        f"{unc} uncertain feature(s) ({row['uncertain_handles']} handles, {row['uncertain_holes']} holes, "
        f"{row['uncertain_components']} components), {row['seconds']:.1f} s"
    )


def summary_csv(rows: list[dict[str, Any]]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        shown = dict(row)
        if isinstance(shown.get("betti"), list):
            shown["betti"] = " ".join(map(str, shown["betti"]))
        writer.writerow({k: "" if shown.get(k) is None else shown[k] for k in COLUMNS})
    return buf.getvalue()


def run(args: argparse.Namespace) -> int:
    """The batch form of ``reconstruct``."""
    from crustview.cli_reconstruct import check_outputs

    if args.out_dir is None:
        raise InputError("several input files need --out-dir DIR (one result and report per file are written there)")
    if args.output is not None or args.report is not None:
        raise InputError("with --out-dir give no -o or --report: each file's result and report are named after it")
    if args.jobs < 1:
        raise InputError(f"-j needs a positive number of processes, got {args.jobs}")
    try:
        args.out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        reason = err.strerror or type(err).__name__
        raise InputError(f"Cannot make the folder '{args.out_dir}' for the results ({reason}).") from None
    names = output_names(list(args.input), args.out_dir)
    summary = [args.out_dir / "summary.csv", args.out_dir / "summary.json"]
    check_outputs(list(args.input), [p for pair in names for p in pair] + summary, args.force)
    rows: list[dict[str, Any] | None] = [None] * len(names)
    start = time.perf_counter()
    try:
        _run_all(args, names, rows)
    except KeyboardInterrupt:
        # Ctrl-C: the results already written stay, and so does a summary of them (nothing is lost); the
        # files not reached are listed as cancelled.  With none finished, nothing is written.
        if any(r is not None for r in rows):
            done = [
                r if r is not None else {"file": str(path), "status": "cancelled", "verdict": None}
                for r, path in zip(rows, args.input, strict=True)
            ]
            _write_summaries(summary, done, {"cancelled": sum(r is None for r in rows), "jobs": args.jobs})
        raise
    return _close(args, rows, summary, start)


def _run_all(args: argparse.Namespace, names: list, rows: list) -> None:
    """Reconstruct every input into ``rows`` (in input order), one process or ``args.jobs``."""
    from crustview.cli_progress import CountProgress, wants_bar

    with CountProgress(len(names), wants_bar(sys.stderr, args.quiet)) as bar:
        show = (lambda line: None) if args.quiet else bar.print
        if args.jobs == 1:
            for i, (path, (out, rep)) in enumerate(zip(args.input, names)):
                rows[i], lines = _job(path, out, rep, args)
                _show(show, rows[i], lines)
                bar.advance(path.name)
        else:
            workers = min(args.jobs, len(names))
            pool = ProcessPoolExecutor(
                max_workers=workers, initializer=_worker_ignores_ctrl_c, initargs=(workers >= 2,)
            )
            with pool:
                pending = {
                    pool.submit(_job, path, out, rep, args): i
                    for i, (path, (out, rep)) in enumerate(zip(args.input, names))
                }
                try:
                    while pending:
                        done, _ = wait(pending, return_when=FIRST_COMPLETED)
                        for fut in done:
                            i = pending.pop(fut)
                            rows[i], lines = fut.result()
                            _show(show, rows[i], lines)
                            bar.advance(Path(rows[i]["file"]).name)
                except BaseException:  # Ctrl-C: stop the workers now (their unnamed temporary files vanish)
                    for process in list(getattr(pool, "_processes", {}).values()):
                        process.terminate()
                    pool.shutdown(wait=False, cancel_futures=True)
                    raise


def _write_summaries(summary: list[Path], rows: list[dict[str, Any]], meta: dict[str, Any]) -> None:
    """summary.csv and summary.json (``meta`` first, with the count of files, then the rows)."""
    write_text(summary[0], summary_csv(rows))
    write_text(summary[1], json.dumps({"files": len(rows), **meta, "rows": rows}, indent=2) + "\n")


def _close(args: argparse.Namespace, rows: list, summary: list[Path], start: float) -> int:
    """Write the summaries, print the closing line; the exit status."""
    final = [r for r in rows if r is not None]
    errors = sum(r["status"] != "ok" for r in final)
    verdicts = {v: sum(r["status"] == "ok" and r["verdict"] == v for r in final) for v in VERDICTS}
    meta = {"errors": errors, "verdicts": verdicts, "seconds": round(time.perf_counter() - start, 3), "jobs": args.jobs}
    _write_summaries(summary, final, meta)
    if not args.quiet:
        said = ", ".join(f"{n} {v}" for v, n in verdicts.items() if n)
        print(
            f"{len(final) - errors} of {len(final)} file{'' if len(final) == 1 else 's'} reconstructed "
            f"({errors} could not be); verdicts: {said or 'none'}; {meta['seconds']:.1f} s with {args.jobs} "
            f"process{'' if args.jobs == 1 else 'es'}; "
            f"wrote {summary[0]} and {summary[1]}.",
            flush=True,
        )
    bad = errors + sum(verdicts[v] for v in BAD_VERDICTS)
    return 1 if bad else 0
