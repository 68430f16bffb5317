"""3-manifolds with a tunnel (S^2 x S^1 in R^4, and in a turned 4-flat of R^5): right or not, and what is uncertain.

S^2 x S^1 is sampled as the points at distance ``tube`` from a unit 2-sphere in the hyperplane w = 0 of R^4,
uniformly by volume (i.i.d., ``samples.manifolds.s2_times_s1_points``), with Gaussian noise of ``noise`` times
the tube radius; its Z/2 Betti numbers
are (1, 1, 1, 1) and its one tunnel is the tube's circle, 2 pi ``tube`` long.  Each case runs
``reconstruct(points, 3)`` with its defaults and prints: right or not (closed, through every sample, those
Betti numbers), the Betti numbers, and every uncertain feature (kind and size in sampling radii; a
``dispute`` is resample-check's).  The closing line counts the wrong results that do not say so (no uncertain
feature while claiming a closed manifold: "NOT a closed manifold" is a warning of its own) and the right ones
with an uncertain feature.  The rows are those of session 37's table (docs/history.md); ``--r5`` runs each
case again turned into R^5 (a hypersurface of a 4-flat: labelled in the flat's coordinates since session 37).

Run: ``python benchmarks/bench_tunnels.py [--r5]`` (about 2 minutes; with ``--r5`` twice that).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from crustview.core import reconstruct
from crustview.core.samples.manifolds import s2_times_s1_points

#: (samples, tube radius, noise over the tube radius, draws): session 37's rows
CASES = [
    (1500, 0.4, 0.0, (1, 2)),
    (1500, 0.25, 0.0, (1, 2)),
    (3000, 0.25, 0.05, (1, 2)),
    (8000, 0.4, 0.03, (1, 2)),
    (3000, 0.15, 0.0, (1, 2)),
    (800, 0.4, 0.03, (1, 2)),
]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").strip().splitlines()[0])
    ap.add_argument("--r5", action="store_true", help="also each case turned into a 4-flat of R^5")
    a = ap.parse_args(argv)
    turn = np.linalg.qr(np.random.default_rng(1).normal(size=(5, 5)))[0]
    print("| samples | tube | noise | draw | in | right | Betti | closed | uncertain (kind: radii) | s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    right = quiet = flagged = runs = 0
    for n, tube, noise, draws in CASES:
        for seed in draws:
            pts = s2_times_s1_points(n, tube, noise, seed)
            where = [("R^4", pts)] + ([("R^5", np.c_[pts, np.zeros(n)] @ turn - 2.0)] if a.r5 else [])
            for name, p in where:
                t0 = time.perf_counter()
                rec = reconstruct(p, 3)
                top = rec.topology
                ok = top.closed_manifold and top.unused_samples == 0 and tuple(top.betti) == (1, 1, 1, 1)
                unc = rec.uncertain_features
                words = ", ".join(f"{'dispute' if f.disputed else f.kind}: {f.size_spacings:.1f}" for f in unc[:6]) + (
                    f", ... ({len(unc)})" if len(unc) > 6 else ""
                )
                runs += 1
                right += ok
                quiet += not ok and not unc and top.closed_manifold  # "NOT a closed manifold" warns on its own
                flagged += ok and bool(unc)
                print(
                    f"| {n} | {tube} | {noise} | {seed} | {name} | {'yes' if ok else 'no'} | {tuple(top.betti)} | "
                    f"{'yes' if top.closed_manifold else 'no'} | "
                    f"{words or '-'} | {time.perf_counter() - t0:.1f} |",
                    flush=True,
                )
    print(f"\n{right}/{runs} right; wrong without an uncertain feature: {quiet}; right with one: {flagged}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
