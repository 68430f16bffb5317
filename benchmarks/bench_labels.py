"""Sweep of the labelling path's one constant, BIG_BALL, on the public closed scans and their noisy copies.

``crustview.core.robust.labelling.BIG_BALL`` sets how big (radius over the
local spacing) a Delaunay ball must be before its ties are trusted.  For each
value this runs the labelling path alone (:func:`~crustview.core.robust.cells.extract_by_labels`,
no growing path, no second opinion) on every closed single- or multi-object
file of ``../shared/data/scans`` and ``scans2`` and on their noisy copies at
0.1 h and 0.3 h, and counts the results that are right (closed, the true Z/2
Betti numbers, every sample a vertex; 99 % at 0.3 h).

Run: ``python benchmarks/bench_labels.py [--values 1 2 4] [--clean-only]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scans import cases  # noqa: E402

from crustview.core import reconstruct  # noqa: E402
from crustview.core.analysis.topology import analyse  # noqa: E402
from crustview.core.robust import labelling  # noqa: E402
from crustview.core.robust.cells import extract_by_labels  # noqa: E402


def right(top, case) -> bool:
    t = case.truth
    c, g = int(t["components"]), int(t["genus"])
    need = 0.99 if case.noise >= 0.3 else 1.0
    return (
        top.closed_manifold
        and tuple(top.betti) == (c, 2 * g, c)
        and top.unused_samples <= (1 - need) * len(case.points)
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--values", type=float, nargs="+", default=[1.0, 2.0, 4.0])
    ap.add_argument("--clean-only", action="store_true")
    ap.add_argument("--noisy-dir", type=Path, default=Path(__file__).resolve().parent / ".noisy")
    a = ap.parse_args(argv)
    closed = [c for c in cases(not a.clean_only, None, a.noisy_dir) if c.truth["closed"]]
    print("| file | " + " | ".join(f"BIG_BALL = {v:g}" for v in a.values) + " |")
    print("|---|" + "---|" * len(a.values))
    wins = {v: 0 for v in a.values}
    for case in closed:
        rec = reconstruct(case.points, 2, mode="paper")
        m = len(rec.delaunay_simplices)
        cells = (rec.delaunay_points, rec.delaunay_simplices, rec.voronoi_vertices[:m])
        ts = np.sort(rec.candidates.select(rec.test), axis=1)
        row = []
        for v in a.values:
            labelling.BIG_BALL = v
            t0 = time.perf_counter()
            ext = extract_by_labels(rec.points, *cells, rec.candidates.faces, ts, rec.spacing)
            top = analyse(ext.complex_at(ext.n_steps), rec.n, 2)
            ok = right(top, case)
            wins[v] += ok
            row.append(f"{'yes' if ok else 'no'} {tuple(top.betti)} {time.perf_counter() - t0:.1f}s")
        print(f"| {case.name} | " + " | ".join(row) + " |", flush=True)
    print("\nright: " + ", ".join(f"BIG_BALL = {v:g}: {wins[v]}/{len(closed)}" for v in a.values))
    return 0


if __name__ == "__main__":
    sys.exit(main())
