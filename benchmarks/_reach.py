"""The reach of a built-in manifold, estimated by Federer's formula on a dense sample with its true tangents.

Federer (1959): reach(M) = inf over x != y in M of |y - x|^2 / (2 dist(y - x, T_x M)).  Nearby pairs
give the smallest radius of curvature, distant ones half the narrowest bottleneck (the Hopf link's two
circles, the trefoil's strands), taken here over the pairs of a dense sample with its own tangent spaces
(``Sample.tangents``).  Checked against the analytic values: sphere 1.000 (1), ellipse 0.250
(b^2 / a = 0.25), torus 0.450 (its tube radius), the Clifford torus 0.707 (1 / sqrt 2), S^3 1.000, the
unit circle 1.000 (1).  Pairs closer than CLOSE of the sample's size are left out: their
|v|^2 - |v along T|^2 loses its digits to cancellation (a pair 2e-7 apart gave the circle 0.989).
``bench_variants.py`` prints the values it uses.

Run: ``python benchmarks/_reach.py`` prints every built-in's estimate.
"""

from __future__ import annotations

import numpy as np

from crustview.core.samples.manifolds import MANIFOLDS, get_manifold

#: Points of the dense sample by the manifold's dimension (curves, surfaces, 3-manifolds): pairs are
#: examined all against all, in blocks.
DENSE = {1: 4000, 2: 6000, 3: 8000}
#: Pairs closer than this fraction of the sample's bounding-box size are not used (see the module docstring).
CLOSE = 1e-4


def reach(name: str, seed: int = 0) -> float:
    """Federer's estimate of the reach of built-in ``name`` (see the module docstring)."""
    m = get_manifold(name)
    s = m.sample(DENSE[m.d], seed=seed, method="random")
    p, t = s.points, s.tangents  # t: (n, k, d), orthonormal columns
    close2 = (CLOSE * float(np.ptp(p, axis=0).max())) ** 2
    best = np.inf
    for i0 in range(0, len(p), 256):
        x, tx = p[i0 : i0 + 256], t[i0 : i0 + 256]
        v = p[None, :, :] - x[:, None, :]  # (b, n, k)
        along = np.einsum("bnk,bkd->bnd", v, tx)
        normal2 = np.maximum((v * v).sum(-1) - (along * along).sum(-1), 0.0)
        length2 = (v * v).sum(-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            ok = (length2 > close2) & (normal2 > 0)
            ratio = np.where(ok, length2 / (2 * np.sqrt(normal2)), np.inf)
        best = min(best, float(ratio.min()))
    return best


if __name__ == "__main__":
    for name in MANIFOLDS:
        print(f"{name:16s} {reach(name):.3f}")
