"""Where a handle loop comes back near itself: detours cut off, necks measured.

The loops of :func:`.loops.short_basis` are shortest in their classes only approximately (a few spread
roots), and one may run out and come back within a few spacings of itself.  At such a place the shortest
path on M_S between the two sides cuts the loop in two: where one part is null-homologous the other is a
shorter loop of the same class (the hand at half density: an extra handle measured at 17.7 and 41.3
sampling radii has loops of 8.4 and 6.4, below what an eps = 1/2 sample resolves); where both go round
handles, the part outside the span of the basis's other loops is a shorter loop for the same handle; where
the two sides are far apart on M_S, the loop passes a neck narrower than two sheets a sample resolves.
Any two places of the loop are compared (:func:`close_pairs`), not only those half the loop apart: the
camel head with noise 0.3 h (draw 23) had a false handle whose 22.8-radius loop comes back near itself a
sixth of the way on (tightened: 10.8 radii, below what an eps = 1/2 sample resolves).  Used by
:mod:`.features` for handles.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

#: How much longer than its chord the shorter arc between two loop vertices must be for the loop to
#: *come back* there, in units of the bound: on a round loop the shorter arc between two points is at
#: most pi / 2 times their chord (a half circle), so an arc of pi times the bound, twice a half
#: circle's over a chord of the bound, is no round loop's two sides, with a margin of two for the zigzag
#: of a loop through noisy samples.  A round tube of diameter D has half-circumference pi D / 2: its
#: loop has such pairs only when squashed to half its width below 2 D / pi.
ARC_FACTOR = math.pi


def close_pairs(points: np.ndarray, loop: np.ndarray, h: np.ndarray, bound: float) -> list[tuple[float, int, int]]:
    """Where a closed loop comes back near itself: (width, i, j) narrower than ``bound``, narrowest first.

    A pair of loop vertices i, j counts when their distance is below ``bound`` sampling radii seen from
    both ends (the width is the distance in the smaller of their two radii) and the shorter of the two
    arcs of the loop between them is at least :data:`ARC_FACTOR` times ``bound`` radii (in the smaller
    radius): the loop leaves the place and comes back to it, which no round loop does.  Any two vertices
    are looked at, not only those half the loop apart: a loop that runs out along a finger and back
    returns near itself a quarter of the way on.  The same vertex visited twice is a pair of width 0.
    """
    if len(loop) < 3:
        return []
    q = points[loop]
    seg = np.linalg.norm(np.roll(q, -1, axis=0) - q, axis=1)
    at = np.concatenate([[0.0], np.cumsum(seg)])
    whole = at[-1]
    hl = np.where(h[loop] > 0, h[loop], 1.0)
    found = cKDTree(q).query_pairs(bound * float(hl.max()), output_type="ndarray")
    if len(found) == 0:
        return []
    i, j = found[:, 0], found[:, 1]
    unit = np.minimum(hl[i], hl[j])
    width = np.linalg.norm(q[i] - q[j], axis=1) / unit
    arc = np.abs(at[i] - at[j])
    arc = np.minimum(arc, whole - arc) / unit
    keep = (width < bound) & (arc >= ARC_FACTOR * bound)
    i, j, width = i[keep], j[keep], width[keep]
    order = np.lexsort((j, i, width))
    return [(float(width[k]), int(i[k]), int(j[k])) for k in order]


def _reduce(x: int, echelon: dict[int, int]) -> int:
    """``x`` reduced by an echelon basis over Z/2 (pivot bit to row): 0 exactly when x is in its span."""
    while x:
        top = x.bit_length() - 1
        if top not in echelon:
            return x
        x ^= echelon[top]
    return 0


def _as_int(mask: np.ndarray) -> int:
    """A class's bit mask (uint64 words) as one Python integer."""
    return sum(int(w) << (64 * i) for i, w in enumerate(np.asarray(mask).tolist()))


def _echelon(classes: list[np.ndarray]) -> dict[int, int]:
    """An echelon basis (pivot bit to row) of the span of some classes over Z/2."""
    out: dict[int, int] = {}
    for c in classes:
        r = _reduce(_as_int(c), out)
        if r:
            out[r.bit_length() - 1] = r
    return out


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
    points: np.ndarray,
    loop: np.ndarray,
    h: np.ndarray,
    cocycles: dict,
    bound: float,
    rounds: int = 4,
    others: list[np.ndarray] | None = None,
) -> tuple[np.ndarray, float]:
    """A handle loop made shorter where it comes back near itself, and the width of its neck if it has one.

    The basis search's loops are shortest only approximately, and one may run out and come back within a
    few spacings of itself.  At each place narrower than ``bound`` (:func:`close_pairs`, narrowest first),
    the shortest path on the surface between the two sides cuts the loop into two loops:

    * one of them null-homologous: the other has the loop's class and is shorter, and replaces it (the
      place was a detour; the search goes on on the new loop, at most ``rounds`` times, after which a
      place still narrower than ``bound`` counts as a neck);
    * both round a handle: with ``others``, the classes of the basis's other loops, exactly one of the two
      parts is outside their span (the two add up to the loop's class, which is), and it replaces the
      loop if shorter: the basis stays a basis, with a shorter loop for this handle (the greedy shortest
      basis would have taken it; a loop that crosses itself as it goes round two handles).  Without
      ``others``, or when that part is not shorter, the loop is two loops meeting at a place narrower
      than ``bound``: a neck;
    * the path longer than the arc it would replace, or than the whole loop: the two sides are far apart
      on the surface and close in space, two sheets closer than ``bound``: a neck.

    Returns
    -------
    loop : ndarray of int
        The loop, shortened where it could be.
    neck : float
        The neck's width in sampling radii, or inf.
    """
    loop = reduced(loop)
    whole = walk_class(loop, cocycles)
    g = cocycles["graph"]
    span: dict[int, int] | None = None  # the others' echelon basis, made when first needed
    for _ in range(rounds):
        pairs = close_pairs(points, loop, h, bound)[:4]
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
                if others is None:
                    return loop, width
                span = _echelon(others) if span is None else span
                keep_first = _reduce(_as_int(c1), span) != 0  # the part outside the others' span
            else:
                keep_first = bool(c1.any())
            half2 = arc2 + back[1:-1]  # b .. a along the loop, back to b by the shortcut
            new = reduced(np.asarray(half1 if keep_first else half2, np.int64))
            if len(new) >= 3 and walk_length(points, new) < length * (1 - 1e-9):
                loop = new
                whole = walk_class(loop, cocycles)
                break
            return loop, width
        else:
            return loop, math.inf
    # the rounds ran out with the loop still shortening: a place left narrower than the bound is not
    # known to be a detour, and counts as a neck
    pairs = close_pairs(points, loop, h, bound)
    return loop, (pairs[0][0] if pairs else math.inf)


def reduced(walk: np.ndarray) -> np.ndarray:
    """A closed walk without its spurs: every step straight back (u, v, u) taken out, cyclically too.

    The basis search closes a loop by two tree paths from its root, which share their first edges: the
    walk runs out along them and back.  An edge walked twice adds nothing to the class over Z/2 and only
    length, and a spur's vertices, each visited twice, would be taken one by one for places where the loop
    comes back to itself.
    """
    stack: list[int] = []
    for v in np.asarray(walk, np.int64).tolist():
        if stack and stack[-1] == v:
            continue
        if len(stack) >= 2 and stack[-2] == v:
            stack.pop()
        else:
            stack.append(v)
    while len(stack) >= 3:
        if stack[0] == stack[-1]:  # the walk's last step is back to its first vertex: once is enough
            stack.pop()
        elif stack[1] == stack[-1]:  # a spur at the first vertex: ... y, x, y ...
            stack = stack[1:-1]
        elif stack[-2] == stack[0]:  # a spur at the last vertex: ... x, y, x ...
            stack.pop()
        else:
            break
    return np.asarray(stack, np.int64)


def walk_length(points: np.ndarray, walk: np.ndarray) -> float:
    """The length of a closed walk (its last vertex joined to its first)."""
    q = points[np.asarray(walk, np.int64)]
    return float(np.linalg.norm(np.roll(q, -1, axis=0) - q, axis=1).sum())
