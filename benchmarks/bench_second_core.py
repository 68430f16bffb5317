"""The robust extraction with its growing path begun in a second process, against the same run in one.

:func:`crustview.core.robust.choose.choose` begins the growing path in a helper process
(:mod:`crustview.core.util.second_core`) while the labelling runs, and stops it when the labelling's result
is kept.  This benchmark measures, on ``bench_scans.py``'s cases (the public scans and their noisy copies
by default; ``--folder`` for others):

* the first helper's start (it imports crustview);
* per case, the robust extraction's time with the second process and without (``CRUSTVIEW_PROCESSES=1``),
  their ratio, whether the growing path ran, and whether the two results are the same (M_S and the step
  log; they must be);
* where the growing path ran: its own time per sample, and how much longer the same job takes in the helper
  (sending arguments and result), so the number of samples below which the path costs less than that:
  the reasoning behind ``SPECULATE_MIN_N``.

Both runs of a case start from the same paper-mode run (same Delaunay, same candidates), in this process.

Run: ``python benchmarks/bench_second_core.py [--only NAME] [--clean-only] [--folder DIR]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from bench_scans import cases

from crustview.core import reconstruct
from crustview.core.reconstruct import reextract
from crustview.core.robust.choose import SPECULATE_MIN_N
from crustview.core.robust.grown_path import grown_path
from crustview.core.util import second_core
from crustview.core.util.memory import gc_paused


def helper_start() -> float:
    """Seconds from asking for the first helper of this process to its answer to a trivial job."""
    t0 = time.perf_counter()
    second_core.Speculation(len, ((),)).result(wait_for_start=True)
    return time.perf_counter() - t0


def robust(paper, processes: bool):
    """The robust extraction on ``paper``'s run, with or without the second process; (result, seconds)."""
    if processes:
        os.environ.pop(second_core.PROCESSES_ENV, None)
    else:
        os.environ[second_core.PROCESSES_ENV] = "1"
    t0 = time.perf_counter()
    rec = reextract(paper, paper.test, paper.theta, mode="robust")
    return rec, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", action="append", help="only this file (repeatable, stem or name)")
    ap.add_argument("--clean-only", action="store_true", help="no noisy copies")
    ap.add_argument("--folder", action="append", type=Path, help="meshes in DIR instead of the shared data")
    ap.add_argument("--noisy-dir", type=Path, default=Path(__file__).parent / ".noisy")
    args = ap.parse_args(argv)
    if (os.cpu_count() or 1) < 2:
        print("one core: the second process is never used here", file=sys.stderr)
        return 1
    os.environ.pop(second_core.PROCESSES_ENV, None)
    print(f"the first helper answers after {helper_start():.3f} s (it imports crustview)")
    todo = cases(not args.clean_only, set(args.only) if args.only else None, args.noisy_dir, folders=args.folder)
    print("| case | points | grown | one process s | two processes s | ratio | same |")
    print("|---|---|---|---|---|---|---|")
    one_total = two_total = 0.0
    per_sample, overhead = [], []
    for case in todo:
        paper = reconstruct(case.points, 2, mode="paper")
        one, t_one = robust(paper, processes=False)
        two, t_two = robust(paper, processes=True)
        grew = "grew M_S" in one.extraction.notes[0]
        same = np.array_equal(one.manifold, two.manifold) and [s.reason for s in one.extraction.steps] == [
            s.reason for s in two.extraction.steps
        ]
        one_total += t_one
        two_total += t_two
        if grew:
            c = paper.candidates
            t0 = time.perf_counter()
            args = (paper.points, c.faces, c.angles[paper.test], c.angles[paper.test] < paper.theta, paper.spacing)
            with gc_paused():  # as in the run
                grown_path(*args)
            here = time.perf_counter() - t0
            t0 = time.perf_counter()
            # the same job in the helper: sending, computing, sending back
            second_core.Speculation(grown_path, args).result(wait_for_start=True)
            overhead.append(time.perf_counter() - t0 - here)
            per_sample.append(here / len(paper.points))
        print(
            f"| {case.name} | {len(case.points)} | {'yes' if grew else 'no'} | {t_one:.2f} | {t_two:.2f} | "
            f"{t_two / t_one:.2f} | {'yes' if same else '**no**'} |",
            flush=True,
        )
    ratio = two_total / one_total if one_total else float("nan")
    print(f"\nall cases: {one_total:.1f} s in one process, {two_total:.1f} s with the second ({ratio:.2f})")
    if per_sample:
        rate, cost = statistics.median(per_sample), statistics.median(overhead)
        print(
            f"the growing path: median {rate * 1e6:.0f} us per sample over {len(per_sample)} cases; in the helper it "
            f"took a median {cost:.3f} s longer (range {min(overhead):.3f}-{max(overhead):.3f} s: sending the "
            f"arguments and the result), which buys about {cost / rate:.0f} samples of it "
            f"(SPECULATE_MIN_N = {SPECULATE_MIN_N})"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
