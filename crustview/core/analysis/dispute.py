"""Where two robust answers of the same sample differ: the dispute's uncertain features.

:func:`crustview.core.robust.driver.choose` keeps one of two results (the labelled and the grown M_S); when
both are manifolds through (nearly) every sample, both closed or both with boundary, and their topology
differs (:func:`crustview.core.robust.verdict._disputed`), the sample does not decide between them, and the
kept result carries the difference as uncertain features (:attr:`crustview.core.steps.Extraction.disputed`).
"""

from __future__ import annotations

import numpy as np

from .cotree import triangle_edges
from .features import Feature
from .radii import local_spacing
from .topology import graph_components


def disagreement(
    points: np.ndarray, kept: np.ndarray, other: np.ndarray, betti_kept: tuple, betti_other: tuple
) -> list[Feature]:
    """Uncertain features where two results of the same sample differ in topology.

    Both complexes are manifolds through (nearly) every sample, both closed or both with boundary
    (:func:`crustview.core.robust.verdict._disputed`), so the sample does not decide between them.  The
    faces that only one of them has are grouped by shared vertices; the largest group is where they differ
    most.  One feature per differing count is placed there: a component when b_0 differs, a hole when the
    number of boundary loops does, a handle when twice the genus does (b_0 + b_1 - b_2 - holes, which is
    b_1 for closed surfaces).
    """
    d = kept.shape[1] - 1
    a = {tuple(sorted(r)) for r in np.asarray(kept).tolist()}
    b = {tuple(sorted(r)) for r in np.asarray(other).tolist()}
    diff = np.array(sorted(a ^ b), dtype=np.int64).reshape(-1, d + 1)
    n = len(points)
    if len(diff):
        _, label = graph_components(n, np.c_[np.repeat(diff[:, 0], d), diff[:, 1:].ravel()])
        lab = label[diff[:, 0]]
        big = np.bincount(lab).argmax()
        verts = np.unique(diff[lab == big])
    else:
        verts = np.unique(np.asarray(kept).ravel())
    loc = points[verts].mean(axis=0)
    h = local_spacing(points, kept)
    size = float(np.ptp(points[verts], axis=0).max() / np.median(h[verts])) if len(verts) > 1 else 0.0
    holes = (_boundary_loops(kept, n), _boundary_loops(other, n)) if d == 2 else (0, 0)
    if min(holes) == 0:  # not both with boundary (outside _disputed's pairs): compared by the Betti numbers
        holes = (0, 0)
    counts = [("component", "b0", betti_kept[0], betti_other[0])]
    surfaces = d == 2 and len(betti_kept) == len(betti_other) == 3
    pairs = ((betti_kept, holes[0]), (betti_other, holes[1]))
    genus2 = [bk[0] + bk[1] - bk[2] - hk for bk, hk in pairs] if surfaces else []
    if surfaces and all(g >= 0 and g % 2 == 0 for g in genus2):
        counts += [("hole", "boundary loops", *holes), ("handle", "2 g", *genus2)]
    elif len(betti_kept) > 1:
        # curves, higher dimensions, or rims that pinch (two holes touching at a vertex count as one loop, and
        # the topology report counts pinched vertices on closed complexes only): b1 as it is
        counts.append(("handle", "b1", betti_kept[1], betti_other[1]))
    both = "closed manifolds" if holes == (0, 0) else "manifolds with boundary"
    out = []
    for kind, what, mine, theirs in counts:
        if mine != theirs:
            out.append(
                Feature(
                    kind,
                    loc,
                    size,
                    True,
                    verts,
                    f"two reconstructions of this sample, both {both}, differ here ({what} = {mine} kept, "
                    f"{theirs} in the other): the sample does not decide between them",
                    disputed=True,
                )
            )
    return out


def _boundary_loops(tris: np.ndarray, n: int) -> int:
    """How many boundary loops a triangle complex has: components of its edges in one triangle."""
    if len(tris) == 0:
        return 0
    edges, tri_edges = triangle_edges(np.asarray(tris, dtype=np.int64))
    rim = edges[np.bincount(tri_edges.ravel(), minlength=len(edges)) == 1]
    if len(rim) == 0:
        return 0
    _, label = graph_components(n, rim)
    return len(np.unique(label[np.unique(rim)]))
