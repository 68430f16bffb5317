"""Plane curves under noise of the order of the spacing: rule tour-curve and the sweep behind PERSISTENT.

Two parts, each judged like ``bench_objects.py`` (right: a closed curve per
true curve, the right Betti numbers, every sample a vertex, 99 % at 0.3 h or
more; flagged: an uncertain feature, issue 18's definition):

* **Noisy ellipses**: the built-in ellipse (200 samples) with Gaussian noise of
  0.5, 1 and 1.5 % of its size (``bench_variants.py``'s model; 1 % is about
  one spacing), sample seeds 0 to N - 1.  Each row also gives the persistence
  of the sample's 1-cycles (``AlphaLadder.loops``, death over birth radius):
  the curve's, and the longest-lived other one.  ``tour_curve.PERSISTENT`` = 2
  must lie between the two columns' ranges.
* **Pairs of circles**: two unit circles of 200 samples, nested (the outer one
  gap h farther out, with as many more samples) or side by side, gaps of 1 to
  6 spacings, noise of 0 to 1 spacing, three seeds.  What the rule must not do
  is join two curves without saying so.

Run: ``python benchmarks/bench_curves.py [--seeds N]``
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _judge import judge, seeds  # noqa: E402

from crustview.core.analysis.alpha import AlphaLadder  # noqa: E402
from crustview.core.samples.manifolds import get_manifold  # noqa: E402

#: Noise of the ellipses, as a share of their size (bench_variants' model).
ELLIPSE_NOISE = (0.005, 0.01, 0.015)
#: Gaps between the two circles, and noise, in spacings h = 2 pi / 200.
GAPS = (1, 2, 3, 4, 6)
NOISE = (0.0, 0.3, 0.6, 1.0)


def noisy_ellipse(frac: float, seed: int) -> np.ndarray:
    m = get_manifold("ellipse")
    base = m.sample(m.default_n, seed=seed).points
    size = float(np.ptp(base, axis=0).max())
    return base + np.random.default_rng(seed + 1).normal(scale=frac * size, size=base.shape)


def circle_pair(kind: str, gap: float, noise: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n, h = 200, 2 * np.pi / 200

    def circle(m: int, r: float, cx: float) -> np.ndarray:
        t = np.linspace(0, 2 * np.pi, m, endpoint=False) + rng.uniform(0, 2 * np.pi / m)
        return np.c_[cx + r * np.cos(t), r * np.sin(t)]

    a = circle(n, 1.0, 0.0)
    if kind == "nested":
        r2 = 1 + gap * h
        b = circle(int(n * r2), r2, 0.0)
    else:
        b = circle(n, 1.0, 2 + gap * h)
    pts = np.vstack([a, b])
    return pts + rng.normal(scale=noise * h, size=pts.shape)


def main(argv: list[str]) -> int:
    n_seeds = seeds(__doc__, argv, 12, "sample seeds of the noisy ellipses")
    print("| ellipse noise | seed | right | Betti | uncertain (h/holes/c) | curve's cycle | longest other |")
    print("|---|---|---|---|---|---|---|")
    tally = {"ellipses": [0, 0, 0, 0], "pairs": [0, 0, 0, 0]}  # right, total, quiet wrong, right flagged
    curve, other = [], []
    for frac in ELLIPSE_NOISE:
        for seed in range(n_seeds):
            pts = noisy_ellipse(frac, seed)
            loops = AlphaLadder(pts).loops()
            ratio = np.sort(loops[:, 1] / loops[:, 0])[::-1]
            curve.append(ratio[0])
            other.append(ratio[1] if len(ratio) > 1 else 1.0)
            j = judge(pts, (1, 1), 0.0, d=1)
            j.add_to(tally["ellipses"])
            print(
                f"| {100 * frac:g} % | {seed} | {'yes' if j.right else 'no'} | {j.betti} | "
                f"{'/'.join(map(str, j.uncertain))} | {curve[-1]:.2f} | {other[-1]:.2f} |",
                flush=True,
            )
    print()
    print(f"cycle persistence: the curve's {min(curve):.2f}-{max(curve):.2f}, others at most {max(other):.2f}")
    print()
    print("| circles | gap (h) | noise (h) | seed | right | Betti | uncertain (h/holes/c) |")
    print("|---|---|---|---|---|---|---|")
    for kind in ("nested", "side by side"):
        for gap in GAPS:
            for noise in NOISE:
                for seed in range(3):
                    j = judge(circle_pair(kind, gap, noise, seed), (2, 2), noise, d=1)
                    j.add_to(tally["pairs"])
                    print(
                        f"| {kind} | {gap:g} | {noise:g} | {seed} | {'yes' if j.right else 'no'} | {j.betti} | "
                        f"{'/'.join(map(str, j.uncertain))} |",
                        flush=True,
                    )
    print()
    for key in ("ellipses", "pairs"):
        r, n, q, f = tally[key]
        print(f"{key}: {r}/{n} right; wrong without a flag: {q}; right with a flag: {f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
