"""Stage timings of the reconstruction core, as ratios to scipy's Delaunay.

The Delaunay stage itself runs CGAL in R^3 (see ``core/delaunay_cgal.py``),
so the after-Delaunay stages are also given over that stage's own time.
Each case first times ``scipy.spatial.Delaunay`` on the same (joggled,
normalised) points in the same process: that is the floor the paper's method
cannot beat, since it needs the full Delaunay triangulation.  Then it runs
``reconstruct`` and prints every stage and the ratio of the whole pipeline,
and of the stages after the Delaunay, to that floor.  Every timing is the
fastest of :data:`REPEATS` runs.

Run: ``python benchmarks/bench_core.py [case ...]``
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _cases import case_names
from scipy.spatial import Delaunay

from crustview.core import reconstruct
from crustview.core.prepare import prepare_points
from crustview.core.samples.manifolds import get_manifold

CASES = {
    "torus-20k": ("torus", 20000),
    "clifford-torus-2k": ("clifford-torus", 2000),
    "sphere-10k": ("sphere", 10000),
    "flat-klein-1500": ("flat-klein", 1500),
    "s3-2k": ("s3", 2000),
    "trefoil-300": ("trefoil", 300),
}


#: Each timing is the minimum over this many runs (the machine has 2 cores and
#: other work on it; the minimum is the least disturbed run).
REPEATS = 3


def floor_delaunay(points: np.ndarray, d: int, repeats: int = REPEATS) -> float:
    prep = prepare_points(points, d)
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        Delaunay(prep.work)
        best = min(best, time.perf_counter() - t0)
    return best


def run(case: str) -> None:
    name, n = CASES[case]
    m = get_manifold(name)
    pts = m.sample(n, seed=0).points
    floor = floor_delaunay(pts, m.d)
    runs = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        rec = reconstruct(pts, m.d)
        runs.append((time.perf_counter() - t0, rec))
    total, rec = min(runs, key=lambda r: r[0])
    after = sum(v for k, v in rec.timings.items() if k not in ("prepare", "delaunay"))
    own = rec.timings["delaunay"]  # crustview's own Delaunay stage (CGAL in R^3, Qhull elsewhere)
    stages = "  ".join(f"{k} {v:.3f}" for k, v in rec.timings.items())
    ok = rec.topology.closed_manifold and rec.topology.betti == m.betti and rec.topology.unused_samples == 0
    print(f"{case:20s} n={n:6d} scipy-Delaunay {floor:7.3f}s | {stages}")
    print(
        f"{'':20s} total/Delaunay = {total / floor:5.2f}   after-Delaunay/Delaunay = {after / floor:5.2f}"
        f"   after/own Delaunay stage = {after / own:5.2f}   correct topology: {ok} {rec.topology.betti}",
        flush=True,
    )
    if m.cospherical:
        exact = pts / np.linalg.norm(pts, axis=1, keepdims=True) * np.linalg.norm(pts[0])
        t0 = time.perf_counter()
        Delaunay(exact[: min(n, 3000)])
        raw = time.perf_counter() - t0
        floor_small = floor_delaunay(exact[: min(n, 3000)], m.d)
        print(
            f"{'':20s} cospherical: Qhull without joggle is {raw / floor_small:5.1f}x slower ({min(n, 3000)} points)",
            flush=True,
        )


if __name__ == "__main__":
    for c in case_names(__doc__, CASES, sys.argv[1:]):
        run(c)
