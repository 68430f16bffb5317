"""Where two robust answers of the same sample differ: the dispute's uncertain features.

:func:`crustview.core.robust.driver.choose` keeps one of two results (the labelled and the grown M_S); when
both are manifolds through (nearly) every sample, both closed or both with boundary, and their topology
differs (:func:`crustview.core.robust.verdict._disputed`), the sample does not decide between them, and the
kept result carries the difference as uncertain features (:attr:`crustview.core.steps.Extraction.disputed`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .cotree import triangle_edges
from .features import LOOP_SUPPORTED, Feature
from .radii import local_spacing
from .topology import graph_components

#: How far, in local spacings, a dispute's marked samples reach from the middle of where the two results
#: differ: half of LOOP_SUPPORTED (4 pi), the longest loop the features call uncertain; a loop that long through
#: the middle lies within that distance of it.
REACH = LOOP_SUPPORTED / 2
#: Nearest vertices looked at for two components' closest approach (as :mod:`crustview.core.robust.join_parts`).
NEIGHBOURS = 16


def disagreement(
    points: np.ndarray, kept: np.ndarray, other: np.ndarray, betti_kept: tuple, betti_other: tuple
) -> list[Feature]:
    """Uncertain features where two results of the same sample differ in topology.

    Both complexes are manifolds through (nearly) every sample, both closed or both with boundary
    (:func:`crustview.core.robust.verdict._disputed`), so the sample does not decide between them.  The
    faces that only one of them has are grouped by shared vertices; the largest group is where they differ
    most.  One feature per differing count is placed there: a component when b_0 differs, a hole when the
    number of boundary loops does, a handle when twice the genus does (b_0 + b_1 - b_2 - holes, which is
    b_1 for closed surfaces).  A handle's or hole's samples are those of the group within :data:`REACH`
    local spacings of its middle (:func:`_core`), its size the whole group's span; a component's are the
    closest two vertices of two components of the result that has more of them which the other result has
    in one (where it joins them), its size their distance in local spacings.
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
    h = local_spacing(points, kept)
    size = float(np.ptp(points[verts], axis=0).max() / np.median(h[verts])) if len(verts) > 1 else 0.0
    verts = _core(points, verts, h)
    loc = points[verts].mean(axis=0)
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
            where, length, at = loc, size, verts
            if kind == "component":  # where the other result joins two parts of the one with more
                split, joined = (kept, other) if mine > theirs else (other, kept)
                gap = _closest_approach(points, split, local_spacing(points, split), joined)
                if gap is not None:
                    length, at = gap
                    where = points[at].mean(axis=0)
            out.append(
                Feature(
                    kind,
                    where,
                    length,
                    True,
                    at,
                    f"two reconstructions of this sample, both {both}, differ here ({what} = {mine} kept, "
                    f"{theirs} in the other): the sample does not decide between them",
                    disputed=True,
                )
            )
    return out


def _core(points: np.ndarray, verts: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The samples of ``verts`` within :data:`REACH` local spacings of the one nearest their centroid.

    Where the two results differ over a large region (two triangulations of the same parts), the differing
    faces say only roughly where the topology differs; the feature marks their middle, not all of them (a
    dispute on the foot bones selected 1,388 of 2,154 samples).  A small group is kept whole.
    """
    if len(verts) < 2:
        return verts
    p = points[verts]
    mid = int(np.argmin(np.linalg.norm(p - p.mean(axis=0), axis=1)))
    reach = REACH * float(np.median(h[verts]))
    return verts[np.linalg.norm(p - p[mid], axis=1) <= reach]


def _closest_approach(
    points: np.ndarray, tris: np.ndarray, h: np.ndarray, joined: np.ndarray | None = None
) -> tuple[float, np.ndarray] | None:
    """The closest two vertices of different components of ``tris``: (their distance in local spacings, the pair).

    With ``joined`` (a complex with fewer components), the pair is of two components that ``joined`` has in
    one (where it joins them), when there is such a pair among the nearest vertices; else the closest of all.
    """
    verts = np.unique(np.asarray(tris).ravel())
    if len(verts) < 2:
        return None
    n = len(points)
    d = tris.shape[1] - 1
    _, label = graph_components(n, np.c_[np.repeat(tris[:, 0], d), tris[:, 1:].ravel()])
    k = min(len(verts), NEIGHBOURS)
    dist, idx = cKDTree(points[verts]).query(points[verts], k=k)
    other = label[verts[idx]] != label[verts][:, None]
    if joined is not None and len(joined):
        dj = joined.shape[1] - 1
        _, together = graph_components(n, np.c_[np.repeat(joined[:, 0], dj), joined[:, 1:].ravel()])
        inside = np.zeros(n, bool)
        inside[np.asarray(joined).ravel()] = True
        same = inside[verts[idx]] & inside[verts][:, None] & (together[verts[idx]] == together[verts][:, None])
        if (other & same).any():
            other = other & same
    gap = np.where(other, dist, np.inf)
    i, j = np.unravel_index(int(np.argmin(gap)), gap.shape)
    if not np.isfinite(gap[i, j]):
        return None
    pair = np.array([verts[i], verts[idx[i, j]]], dtype=np.int64)
    return float(gap[i, j] / max(float(np.median(h[pair])), 1e-300)), pair


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
