"""Every built-in manifold in the variants issue 18 judges: right or not, and how sure the result says it is.

For each built-in (seed 0 unless said): its default sample; a third of that many
points; i.i.d. points instead of the even sampler; a 4x density variation
(``density="nonuniform"``); Gaussian noise of 0.5 % and 1 % of the sample's
bounding-box size; and noise of 2 % and 3 % of the manifold's reach, seeds 1 and 2
(the reach by Federer's formula on a dense sample, ``_reach.py``: the torus's tube
radius 0.45, the sphere's radius 1, S^3's 1, the trefoil's 0.42, ...).  ``--draw D`` adds D to every
seed (samples, noise): the same variants drawn again, as a judge with other draws sees them (draw 0, the
default, is the table docs/history.md reports, session 39).  The
default extraction (robust) runs on each.  A result is right when M_S is a
closed manifold through every sample with the manifold's Z/2 Betti numbers.
The closing line counts the wrong results without an uncertain feature (the
issue's target: none) and the right ones with one.

Run: ``python benchmarks/bench_variants.py [--draw D] [manifold ...]``
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _cases import case_names
from _reach import reach

from crustview.core import reconstruct
from crustview.core.samples.manifolds import MANIFOLDS, get_manifold


def variants(name: str, draw: int = 0) -> list[tuple[str, np.ndarray]]:
    """The variants of one built-in: (label, points); ``draw`` is added to every seed."""
    m = get_manifold(name)
    n = m.default_n
    out = [
        ("default", m.sample(n, seed=draw).points),
        ("1/3 density", m.sample(max(n // 3, 10), seed=draw).points),
        ("i.i.d.", m.sample(n, seed=draw, method="random").points),
        ("4x density variation", m.sample(n, seed=draw, density="nonuniform").points),
    ]
    base = m.sample(n, seed=draw).points
    size = float(np.ptp(base, axis=0).max())
    for frac in (0.005, 0.01):
        rng = np.random.default_rng(1 + draw)
        out.append((f"noise {100 * frac:g} % of size", base + rng.normal(scale=frac * size, size=base.shape)))
    r = reach(name)
    for frac in (0.02, 0.03):
        for seed in (1 + draw, 2 + draw):
            s = m.sample(n, seed=seed).points
            rng = np.random.default_rng(seed + 100)
            out.append(
                (
                    f"noise {100 * frac:g} % of reach {r:.3g}, seed {seed}",
                    s + rng.normal(scale=frac * r, size=s.shape),
                )
            )
    return out


def main(argv: list[str]) -> int:
    draw = 0
    if "--draw" in argv:  # the manifolds' names are the positional arguments (_cases.case_names)
        at = argv.index("--draw")
        try:
            draw = int(argv[at + 1])
        except (IndexError, ValueError):
            print("bench_variants.py: error: --draw needs an integer", file=sys.stderr)
            return 2
        argv = argv[:at] + argv[at + 2 :]
    names = case_names(__doc__, MANIFOLDS, argv, what="manifold")
    print("| manifold | variant | n | right | Betti | uncertain | s |")
    print("|---|---|---|---|---|---|---|")
    right = quiet = flagged = total = 0
    for name in names:
        m = get_manifold(name)
        for label, pts in variants(name, draw):
            t0 = time.perf_counter()
            rec = reconstruct(pts, m.d)
            dt = time.perf_counter() - t0
            t = rec.topology
            ok = t.closed_manifold and t.unused_samples == 0 and tuple(t.betti) == tuple(m.betti)
            unc = len(rec.uncertain_features)
            total += 1
            right += ok
            quiet += (not ok) and unc == 0 and t.closed_manifold
            flagged += ok and unc > 0
            print(
                f"| {name} | {label} | {len(pts)} | {'yes' if ok else 'no'} | {tuple(t.betti)} | {unc} | {dt:.1f} |",
                flush=True,
            )
    print(f"\n{right}/{total} right; wrong without an uncertain feature: {quiet}; right with one: {flagged}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
