"""Where a handle loop comes back near itself: detours cut off, necks measured.

The loops of :func:`.loops.short_basis` are shortest in their classes only approximately (a few spread
roots), and one may run out and come back within a few spacings of itself.  At such a place the shortest
path on M_S between the two sides cuts the loop in two: where one part is null-homologous the other is a
shorter loop of the same class (the hand at half density: an extra handle measured at 17.7 and 41.3
sampling radii has loops of 8.4 and 6.4, below what an eps = 1/2 sample resolves); where both go round
handles, or the two sides are far apart on M_S, the loop passes a neck narrower than two sheets a sample
resolves.  Used by :mod:`.features` for handles.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse.csgraph import dijkstra


def neck_pairs(points: np.ndarray, loop: np.ndarray, h: np.ndarray) -> list[tuple[float, int, int]]:
    """Where a closed loop comes close to itself half the loop on: (width, i, j) by increasing width.

    For each vertex p = loop[i], the point a half of the loop's length further along it (on an edge,
    interpolated) is found, and their distance is taken in p's sampling radii.  A neck is one place seen
    from its two sides, so it counts only as wide as the larger of p's distance and that of j, the loop
    vertex nearest the point found (whose own half-loop point is back near p): a single vertex moved by
    noise toward the other side, or an edge's interpolation, does not make a neck.  A loop around a round
    tube of radius r gives 2 r everywhere; a loop of fewer than three vertices has no pair.
    """
    if len(loop) < 3:
        return []
    q = points[loop]
    step = np.roll(q, -1, axis=0) - q
    seg = np.linalg.norm(step, axis=1)
    at = np.concatenate([[0.0], np.cumsum(seg)])
    half = (at[:-1] + at[-1] / 2) % at[-1]
    j = np.clip(np.searchsorted(at, half, side="right") - 1, 0, len(q) - 1)
    frac = (half - at[j]) / np.where(seg[j] > 0, seg[j], 1.0)
    opposite = q[j] + frac[:, None] * step[j]
    hl = h[loop]
    dist = np.linalg.norm(q - opposite, axis=1) / np.where(hl > 0, hl, 1.0)
    nearest = np.where(frac < 0.5, j, (j + 1) % len(q))  # the loop vertex nearest the point found
    width = np.maximum(dist, dist[nearest])
    order = np.argsort(width, kind="stable")
    return [(float(width[i]), int(i), int(nearest[i])) for i in order]


def walk_class(walk: list[int] | np.ndarray, cocycles: dict) -> np.ndarray:
    """The homology class (bit mask over the basis, from :func:`short_basis`'s ``cocycles``) of a closed walk."""
    w = np.asarray(walk, np.int64)
    w = w[np.r_[True, w[1:] != w[:-1]]]  # no zero-length steps
    if len(w) > 1 and w[0] == w[-1]:
        w = w[:-1]
    if len(w) < 2:
        return np.zeros(cocycles["mask"].shape[1], np.uint64)
    ids = cocycles["edge_ids"](w, np.roll(w, -1))
    return np.bitwise_xor.reduce(cocycles["mask"][ids], axis=0)


def tighten(
    points: np.ndarray, loop: np.ndarray, h: np.ndarray, cocycles: dict, bound: float, rounds: int = 4
) -> tuple[np.ndarray, float]:
    """A handle loop made shorter where it comes back near itself, and the width of its neck if it has one.

    The basis search's loops are shortest only approximately, and one may run out and come back within a
    few spacings of itself.  At each place narrower than ``bound`` (:func:`neck_pairs`, narrowest first),
    the shortest path on the surface between the two sides cuts the loop into two loops:

    * one of them null-homologous: the other has the loop's class and is shorter, and replaces it (the
      place was a detour; the search goes on on the new loop, at most ``rounds`` times, after which a
      place still narrower than ``bound`` counts as a neck);
    * both round a handle: the loop is two loops meeting at a place narrower than ``bound``: a neck;
    * the path as long as the loop's arc, or longer than the whole loop: the two sides are far apart on
      the surface and close in space, two sheets closer than ``bound``: a neck.

    Returns
    -------
    loop : ndarray of int
        The loop, shortened where it could be.
    neck : float
        The neck's width in sampling radii, or inf.
    """
    whole = walk_class(loop, cocycles)
    g = cocycles["graph"]
    for _ in range(rounds):
        pairs = [p for p in neck_pairs(points, loop, h) if p[0] < bound][:4]
        if not pairs:
            return loop, math.inf
        length = walk_length(points, loop)
        for width, i, j in pairs:
            a, b = int(loop[i]), int(loop[j])
            # a shortcut longer than the loop shortens nothing: the search stops there
            _, pred = dijkstra(g, indices=[b], return_predecessors=True, limit=length)
            back = [a]  # the shortcut, from a to b
            while back[-1] != b and pred[0][back[-1]] >= 0:
                back.append(int(pred[0][back[-1]]))
            if back[-1] != b:
                return loop, width  # farther apart on M_S than the loop is long: two sheets
            if max(back) >= len(h):
                continue  # a path through a hole's cap (its apex is no sample)
            arc1 = list(loop[i : j + 1]) if i <= j else list(loop[i:]) + list(loop[: j + 1])
            arc2 = list(loop[j:]) + list(loop[: i + 1]) if i <= j else list(loop[j : i + 1])
            half1 = arc1 + back[::-1][1:-1]  # a .. b along the loop, back to a by the shortcut
            c1 = walk_class(half1, cocycles)
            if c1.any() and (c1 ^ whole).any():
                return loop, width
            half2 = arc2 + back[1:-1]  # b .. a along the loop, back to b by the shortcut
            new = np.asarray(half1 if c1.any() else half2, np.int64)
            new = new[np.r_[True, new[1:] != new[:-1]]]
            if len(new) >= 3 and walk_length(points, new) < length * (1 - 1e-9):
                loop = new
                break
            return loop, width
        else:
            return loop, math.inf
    # the rounds ran out with the loop still shortening: a place left narrower than the bound is not
    # known to be a detour, and counts as a neck
    pairs = neck_pairs(points, loop, h)
    return loop, (pairs[0][0] if pairs and pairs[0][0] < bound else math.inf)


def walk_length(points: np.ndarray, walk: np.ndarray) -> float:
    """The length of a closed walk (its last vertex joined to its first)."""
    q = points[np.asarray(walk, np.int64)]
    return float(np.linalg.norm(np.roll(q, -1, axis=0) - q, axis=1).sum())
