"""Every built-in manifold with every candidate test: right or not, and stage timings.

For each built-in manifold (default sample size, seed 0) the pipeline runs once
with the default test; the other tests re-run only Algorithm 3 on the stored
angles (as the viewer does).  A test "reconstructs" the manifold when M_S is a
closed manifold through every sample with the true Z/2 Betti numbers and
orientability.  Timings are per stage, with the whole pipeline also given as a
multiple of scipy's Delaunay on the same prepared points (the floor).

Run: ``python benchmarks/bench_builtins.py [name ...]``
"""

from __future__ import annotations

import sys
import time

from _cases import case_names
from scipy.spatial import Delaunay

from crustview.core import CANDIDATE_TESTS, reconstruct, reextract
from crustview.core.prepare import prepare_points
from crustview.core.samples.manifolds import MANIFOLDS


def verdict(rec, m) -> str:
    t = rec.topology
    if t.closed_manifold and t.unused_samples == 0 and t.betti == m.betti and t.orientable == m.orientable:
        return "yes"
    if not len(rec.manifold):
        return "no (empty)"
    if t.closed_manifold:
        return f"no (Betti {t.betti}, {t.unused_samples} unused)"
    return f"no ({rec.extraction.stopped}, {t.boundary_faces} boundary faces)"


def main(names: list[str]) -> None:
    names = names or list(MANIFOLDS)
    head = f"{'manifold':15s} {'k':>2s} {'d':>2s} {'n':>5s} | " + " | ".join(f"{t:28s}" for t in CANDIDATE_TESTS)
    print(head + " | stage seconds (prepare delaunay normals candidates extraction topology) | total/Delaunay")
    for name in names:
        m = MANIFOLDS[name]
        pts = m.sample(m.default_n, seed=0).points
        prep = prepare_points(pts, m.d)
        t0 = time.perf_counter()
        Delaunay(prep.work)
        floor = time.perf_counter() - t0
        rec = reconstruct(pts, m.d)
        verdicts = []
        for test in CANDIDATE_TESTS:
            other = rec if test == rec.test else reextract(rec, test, rec.theta)
            verdicts.append(verdict(other, m))
        stages = " ".join(f"{v:.3f}" for v in rec.timings.values())
        total = sum(rec.timings.values())
        print(
            f"{name:15s} {m.k:2d} {m.d:2d} {m.default_n:5d} | "
            + " | ".join(f"{v:28s}" for v in verdicts)
            + f" | {stages} | {total / floor:.1f}",
            flush=True,
        )


if __name__ == "__main__":
    main(case_names(__doc__, MANIFOLDS, sys.argv[1:], "manifold"))
