"""Thin parts that nearly touch: a U-shaped tube whose arms carry two bumps a fraction of a spacing apart.

A review in session 38 built this shape to test a rule (withdrawn) that took a short handle loop sliding
along thin parts for a tube's meridian.  It also shows a gap in what the report measures today: where the
labelling joins the two bumps, the false handle's shortest loop is the bridge's waist (8.6 sampling radii,
uncertain), but the loop basis search (``analysis/loops.py``: 12 spread roots per component, and local
searches from the tree-cotree split's leftover edges) may miss it and report the arm's cross-section
(27 radii) instead, sure: a closed genus 1 with no flag for a genus-0 object.  With every vertex a root the
greedy basis finds the waist.  This sweep counts such results, so that a better search can be measured.

The object: two vertical capsules (radius 2.5, axis length 60) joined at the bottom by a horizontal one
(a U, genus 0), each arm with a ball of radius 1.2 at height 45 bulging 0.75 into the space between the
arms, the two balls ``gap`` apart.  Samples: the union's surface, even at spacing 0.6 (every
point of each primitive's surface outside the others, thinned so that no two are closer than the
spacing).  Gaps of 0.1, 0.15 and 0.2 (a sixth to a third of the spacing: below what any sample resolves, so
a joined result is expected and must be flagged), seeds 1-3.

Run: ``python benchmarks/bench_thin.py [--seeds N]``
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _judge import judge, seeds  # noqa: E402

#: Tube radius, arm length, sample spacing, ball radius and height, and how far each ball reaches into the
#: space between the arms (2 REACH + gap wide).
RADIUS, ARM, SPACING, BALL, HEIGHT, REACH = 2.5, 60.0, 0.6, 1.2, 45.0, 0.75
GAPS = (0.1, 0.15, 0.2)


def _capsule_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray, r: float) -> np.ndarray:
    """Signed distance to the capsule of radius r around the segment ab."""
    ab = b - a
    t = np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1) - r


def _capsule_points(a: np.ndarray, b: np.ndarray, r: float, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points uniform by area on the capsule's surface (cylinder and two half-spheres)."""
    ab = b - a
    length = float(np.linalg.norm(ab))
    axis = ab / length
    u = np.linalg.svd(axis[None, :])[2][1]
    v = np.cross(axis, u)
    cyl, ball = 2 * np.pi * r * length, 4 * np.pi * r * r
    on_cyl = rng.random(count) < cyl / (cyl + ball)
    out = np.empty((count, 3))
    k = int(on_cyl.sum())
    angle, t = rng.uniform(0, 2 * np.pi, k), rng.uniform(0, length, k)
    out[on_cyl] = a + t[:, None] * axis + r * (np.cos(angle)[:, None] * u + np.sin(angle)[:, None] * v)
    d = rng.normal(size=(count - k, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    ends = np.where(((d @ axis) > 0)[:, None], b, a)  # each half-sphere on its own end
    out[~on_cyl] = ends + r * d
    return out


def u_shape(gap: float) -> tuple[list[tuple[np.ndarray, np.ndarray]], list[np.ndarray]]:
    """The U's three capsules (axis end points, radius RADIUS) and the two balls' centres (radius BALL)."""
    x1 = 2 * RADIUS + 2 * REACH + gap  # the second arm's axis: the bumps' surfaces gap apart
    z = np.array([0.0, 0.0, 1.0])
    right = np.array([x1, 0.0, 0.0])
    caps = [(np.zeros(3), ARM * z), (right, right + ARM * z), (np.zeros(3), right)]
    balls = [np.array([RADIUS + REACH - BALL, 0, HEIGHT]), np.array([x1 - RADIUS - REACH + BALL, 0, HEIGHT])]
    return caps, balls


def u_distance(p: np.ndarray, gap: float) -> np.ndarray:
    """Signed distance to the union's surface (negative inside), exact outside the union."""
    caps, balls = u_shape(gap)
    parts = [_capsule_distance(p, a, b, RADIUS) for a, b in caps] + [
        np.linalg.norm(p - c, axis=1) - BALL for c in balls
    ]
    return np.min(parts, axis=0)


def u_with_bumps(gap: float, seed: int) -> np.ndarray:
    """The sample of the U with its two bumps ``gap`` apart (see the module docstring)."""
    rng = np.random.default_rng(seed)
    caps, balls = u_shape(gap)
    dense = 40  # candidate points per unit area before thinning: far more than one per spacing^2
    parts = [
        _capsule_points(a, b, RADIUS, int(dense * 2 * np.pi * RADIUS * (np.linalg.norm(b - a) + 2 * RADIUS)), rng)
        for a, b in caps
    ]
    for c in balls:
        d = rng.normal(size=(int(dense * 4 * np.pi * BALL**2), 3))
        parts.append(c + BALL * d / np.linalg.norm(d, axis=1)[:, None])
    pts = np.vstack(parts)
    pts = pts[u_distance(pts, gap) > -1e-9]  # on the union's surface: inside no other part
    pts = pts[rng.permutation(len(pts))]
    tree = cKDTree(pts)
    keep = np.ones(len(pts), bool)
    for i in range(len(pts)):  # greedy thinning: no two kept points closer than the spacing
        if keep[i]:
            near = tree.query_ball_point(pts[i], SPACING)
            keep[[j for j in near if j > i]] = False
    return pts[keep]


def main(argv: list[str]) -> int:
    n_seeds = seeds(__doc__, argv, 3, "seeds per gap (1, 2, ...)")
    print("| gap (spacings) | seed | samples | right | Betti | uncertain (h/holes/c) | s |")
    print("|---|---|---|---|---|---|---|")
    tally = [0, 0, 0, 0]  # right, total, quiet wrong, right flagged
    for gap in GAPS:
        for seed in range(1, n_seeds + 1):
            pts = u_with_bumps(gap, seed)
            j = judge(pts, (1, 0, 1), 0.0)
            j.add_to(tally)
            print(
                f"| {gap / SPACING:.2f} | {seed} | {len(pts):,} | {'yes' if j.right else 'no'} | {j.betti} | "
                f"{'/'.join(map(str, j.uncertain))} | {j.seconds:.1f} |",
                flush=True,
            )
    r, n, q, f = tally
    print()
    print(f"{r}/{n} right; wrong without a flag: {q}; right with a flag: {f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
