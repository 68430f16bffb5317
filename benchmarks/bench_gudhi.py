"""crustview against GUDHI's tangential complex on manifolds of known topology.

For each built-in manifold in R^2..R^4 both libraries get the same sample.
GUDHI's result is judged by the Z/2 Betti numbers of its simplicial complex
(persistence of the simplex tree, field Z/2) and its count of inconsistent
simplices; crustview's by its topology report.  Times are given as ratios to
scipy's Delaunay on the same points, measured in the same process.

Run: ``python benchmarks/bench_gudhi.py [name ...]``  (needs ``pip install gudhi``)
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.spatial import Delaunay

from crustview.core import reconstruct
from crustview.core.sampling import MANIFOLDS

NAMES = ["circle", "ellipse", "trefoil", "hopf-link", "sphere", "ellipsoid", "torus",
         "clifford-torus", "flat-klein", "sphere-r4", "s3", "circle-r4"]


def gudhi_betti(points: np.ndarray, d: int) -> tuple[tuple[int, ...], int, float]:
    import gudhi

    t0 = time.perf_counter()
    tc = gudhi.TangentialComplex(intrinsic_dim=d, points=points)
    tc.compute_tangential_complex()
    st = tc.create_simplex_tree()
    dt = time.perf_counter() - t0
    st.compute_persistence(homology_coeff_field=2, persistence_dim_max=True)
    betti = tuple(st.betti_numbers()[: d + 1])
    betti = betti + (0,) * (d + 1 - len(betti))
    return betti, tc.num_inconsistent_simplices(), dt


def main(names: list[str]) -> None:
    print(f"{'manifold':15s} {'n':>5s} {'truth':12s} | {'crustview':28s} | {'gudhi tangential':30s}")
    for name in names:
        m = MANIFOLDS[name]
        pts = m.sample(m.default_n, seed=0).points
        t0 = time.perf_counter()
        Delaunay(pts + np.random.default_rng(0).normal(scale=1e-9, size=pts.shape))
        floor = time.perf_counter() - t0
        t0 = time.perf_counter()
        rec = reconstruct(pts, m.d)
        tc = time.perf_counter() - t0
        top = rec.topology
        ok = top.closed_manifold and top.betti == m.betti and top.unused_samples == 0
        gb, incons, tg = gudhi_betti(pts, m.d)
        gok = gb == m.betti and incons == 0
        print(
            f"{name:15s} {len(pts):5d} {str(m.betti):12s} | "
            f"{'OK ' if ok else 'BAD'} {str(top.betti):12s} {tc / floor:6.1f}x | "
            f"{'OK ' if gok else 'BAD'} {str(gb):12s} incons={incons:<4d} {tg / floor:6.1f}x",
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:] or NAMES)
