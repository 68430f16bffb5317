"""A curve's holes: the gaps between the ends of its open paths, and why the robust report doubts each.

A surface's hole is a boundary loop (:func:`~.features.features` measures its rim); a curve's is the gap
between two ends that face each other (:func:`curve_gaps`).  In a robust result every such gap is
uncertain (:func:`straight_gaps`): two ends always lie on a line, so the sample does not tell a gap from a
straight piece of the curve sampled only at its two ends -- the curve's version of a planar rim
(:mod:`.planar`: a cut along a plane, or a flat face sampled only on its outline).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from .features import HOLE_SUPPORTED, Feature
from .radii import local_spacing
from .topology import graph_components


def curve_gaps(points: np.ndarray, edges: np.ndarray, spacing: np.ndarray | None = None) -> list[Feature]:
    """The holes of a curve: the gaps between the ends of its open paths, each end with the nearest other end.

    A curve's hole is a gap between two ends that face each other: the ends (vertices in one edge) are
    paired nearest first, whatever path each belongs to (a circle missing two samples has two gaps of one
    sample each, not two chords across it), and an arc's two ends are its one gap.  Each is measured as a
    surface's rim is (the distance between the two ends over their local spacing, sampling radii) and
    uncertain under the same bound, :data:`HOLE_SUPPORTED` (a gap of one missing sample measures 4: at the
    bound, and uncertain).  Ends on a component with a branch point (a vertex in three or more edges) are
    left to the report's manifold check.  The robust report adds these (:mod:`crustview.core.uncertainty`);
    :func:`~.features.features` does not, so the paper mode's report and the robust driver's choices are unchanged.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    edges : ndarray of shape (e, 2)
        M_S, a curve.
    spacing : ndarray of shape (n,), optional
        Local sampling radius per sample (default: :func:`~.radii.local_spacing` of ``edges``).
    """
    edges = np.asarray(edges, np.int64).reshape(-1, 2)
    n = len(points)
    if len(edges) == 0:
        return []
    deg = np.bincount(edges.ravel(), minlength=n)
    _, label = graph_components(n, edges)
    branched = np.unique(label[deg >= 3])
    ends = np.flatnonzero((deg == 1) & ~np.isin(label, branched))
    if len(ends) < 2:
        return []
    h = local_spacing(points, edges) if spacing is None else np.asarray(spacing, dtype=float)
    pairs: list[tuple[int, int, float]] = []
    free = np.arange(len(ends))
    while len(free) >= 2:
        # candidate pairs among the ends still free: each with its nearest others (all of them up to 10), closest
        # first; the closest free pair is always among them, so every round pairs at least one
        near_d, near_i = cKDTree(points[ends[free]]).query(points[ends[free]], k=min(len(free), 10))
        other = near_i != np.arange(len(free))[:, None]  # by index: a duplicate point may come before the end itself
        a_all = np.repeat(free, near_i.shape[1])[other.ravel()]
        b_all, d_all = free[near_i[other]], near_d[other]
        taken = set()
        for i in np.argsort(d_all, kind="stable").tolist():
            a, b = int(a_all[i]), int(b_all[i])
            if a in taken or b in taken or a == b:
                continue
            taken.update((a, b))
            pairs.append((a, b, float(d_all[i])))
        if not taken:  # cannot happen (the closest free pair is a candidate); never loop forever
            break
        free = np.setdiff1d(free, np.fromiter(taken, np.int64, len(taken)))
    result = []
    for a, b, dist in pairs:
        pair = ends[[a, b]]
        size = dist / float(np.median(h[pair]))
        unc = size <= HOLE_SUPPORTED * (1 + 1e-9)  # one missing sample measures 4: at the bound, uncertain
        reason = f"gap of an open curve: two ends {size:.3g} spacings apart" + (
            " (at most 4 spacings: only a sample coarser than eps = 1/2 resolves it, so it may be a gap of the "
            "sampling)"
            if unc
            else ""
        )
        result.append(Feature("hole", points[pair].mean(axis=0), size, unc, pair, reason))
    return result


def straight_gaps(gaps: list[Feature]) -> list[Feature]:
    """The gaps, each uncertain: a gap, or a straight piece sampled only at its two ends."""
    return [
        replace(
            f,
            uncertain=True,
            reason=f"{f.reason} (a gap, or a straight piece sampled only at its two ends; the sample does not tell "
            "the two apart)",
        )
        for f in gaps
    ]
