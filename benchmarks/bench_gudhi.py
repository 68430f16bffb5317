"""crustview against GUDHI's tangential complex on manifolds of known topology.

For each built-in manifold in R^2..R^4 both libraries get the same sample.
GUDHI's result is judged by the Z/2 Betti numbers of its simplicial complex
(persistence of the simplex tree, field Z/2) and its count of inconsistent
simplices, both as computed and after its own repair step
(``fix_inconsistencies_using_perturbation``); crustview's by its topology report.  Times are given as ratios to
scipy's Delaunay on the same points, measured in the same process.

Run: ``python benchmarks/bench_gudhi.py [name ...]``  (needs ``pip install gudhi``)
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _cases import case_names
from scipy.spatial import Delaunay

from crustview.core import reconstruct
from crustview.core.samples.manifolds import MANIFOLDS

NAMES = [
    "circle",
    "ellipse",
    "trefoil",
    "hopf-link",
    "sphere",
    "ellipsoid",
    "torus",
    "clifford-torus",
    "flat-klein",
    "sphere-r4",
    "s3",
    "circle-r4",
]


def gudhi_betti(points: np.ndarray, d: int, fix: bool) -> tuple[tuple[int, ...], int, float]:
    """Betti numbers, inconsistencies and seconds of GUDHI's tangential complex.

    With ``fix`` the documented repair step runs too: perturb the points of
    inconsistent simplices (at most 0.1 sample spacing, 30 s).
    """
    import gudhi
    from scipy.spatial import cKDTree

    t0 = time.perf_counter()
    tc = gudhi.TangentialComplex(intrinsic_dim=d, points=points)
    tc.compute_tangential_complex()
    if fix:
        spacing = float(np.median(cKDTree(points).query(points, k=2)[0][:, 1]))
        tc.fix_inconsistencies_using_perturbation(0.1 * spacing, 30.0)
    st = tc.create_simplex_tree()
    dt = time.perf_counter() - t0
    st.compute_persistence(homology_coeff_field=2, persistence_dim_max=True)
    betti = tuple(st.betti_numbers()[: d + 1])
    betti = betti + (0,) * (d + 1 - len(betti))
    return betti, tc.num_inconsistent_simplices(), dt


def main(names: list[str]) -> None:
    print(
        f"{'manifold':15s} {'n':>5s} {'truth':12s} | {'crustview':28s} | {'gudhi tangential':32s} | "
        f"{'gudhi + fix_inconsistencies':32s}"
    )
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
        cols = []
        for fix in (False, True):
            gb, incons, tg = gudhi_betti(pts, m.d, fix)
            gok = gb == m.betti and incons == 0
            cols.append(f"{'OK ' if gok else 'BAD'} {str(gb):12s} incons={incons:<4d} {tg / floor:6.1f}x")
        print(
            f"{name:15s} {len(pts):5d} {str(m.betti):12s} | "
            f"{'OK ' if ok else 'BAD'} {str(top.betti):12s} {tc / floor:6.1f}x | " + " | ".join(cols),
            flush=True,
        )


if __name__ == "__main__":
    main(case_names(__doc__, NAMES, sys.argv[1:], "manifold"))
