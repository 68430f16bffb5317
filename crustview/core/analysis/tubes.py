"""Whether a short handle loop is the meridian of a tube: it slides along the tube; a tunnel's or bridge's rim does not.

Why
---
A handle loop shorter than :data:`~.features.LOOP_SUPPORTED` = 4 pi sampling
radii is resolved only by a sample coarser than eps = 1/2, so by its length
alone the sample cannot tell it from a gap, and ``cut-handle`` removes it
between :data:`~.features.LOOP_MIN` and that bound.  Three shapes give such a
loop, and its length does not tell them apart; where the loop can go does:

* a **tunnel** through a thin wall (outside cells across a part, where noise
  left a few of them): the loop is the tunnel's rim.  A loop of the same
  class through a point t away from the rim, on the wall, has to go round the
  tunnel: about 2 t + L at the least (out to the rim, round it and back; a
  circle round it, 2 pi (rho + t), is longer where the wall is flat).
* a **bridge** between two parts that nearly touch (inside cells across the
  gap): the loop goes round the bridge, and away from it, on either part, a
  loop of its class has to go round the bridge's foot: again 2 t + L.
* a **tube**, a thin real part (a knotted tube): the loop is a meridian, and
  the meridian through a point along the tube is about as long, however far
  from the first; where the labelling pinched the tube (noise), the loop is
  the pinch's and the meridians beside it are up to a few times longer, then
  stay so.

So a loop of length L *slides* when, on each of its two sides, through some
sample r at a distance d of at least :data:`SLIDE_AWAY` L = 4 L from it along
M_S, there is a loop of the same Z/2 class shorter than the lasso bound
2 d + L by a factor :data:`SLIDE_MARGIN` = 2 (L the shortest loop of the class
found, here or through r).  Round a tunnel or a bridge no loop passes that
test on the side of the wall or of the part (the loop itself, at d = 0, has
the ratio 1); a tube's meridian keeps its length while the bound grows with
d (a pinch of half the tube's width doubles the meridians beside it: the
knotted tube of the held-out data at 0.1 h, a pinch of 8.5 radii in a tube
whose meridians measure 17.6 on the true mesh, slides at ratio 0.12).  The
sides are the two strips of triangles along the loop, and a sample belongs to
the side it is nearer along M_S without crossing the loop; the samples r are
spread (farthest-point sampling) over those between SLIDE_AWAY L and
:data:`SLIDE_FAR` L from it.  What this leaves undecided, as before:

* a limb touching a body at its tip makes the limb a handle whose meridian
  slides along the limb, but not on the body's side;
* on an object only a few loop lengths across, loops of any class are short
  and the lasso bound does not hold: the decimated knight (502 samples, its
  arm touching its body) has loops of the bridge's class 2.2 L long 2 L away,
  but no sample 4 L away on both sides;
* a short real handle (a cup's, about three meridians long) looks like a
  neck.

A loop that slides is the sample's own evidence of a long tube through it, not
of a gap of a few cells: its handle is supported (:func:`.features._handles`),
and ``cut-handle`` leaves it.  Below LOOP_MIN nothing changes: no eps < 1
sample resolves such a loop at all.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import diags
from scipy.sparse.csgraph import dijkstra

from .loops import _path_masks, _spread
from .necks import walk_class, walk_length
from .topology import graph_components

#: How much shorter than the lasso bound 2 d + L a loop through a sample d away must be for the loop to
#: slide: a factor 2 (a tunnel's or a bridge's loops reach the bound at best, the loop itself at d = 0).
SLIDE_MARGIN = 2.0
#: The samples tried lie at least this many loop lengths from the loop along M_S, on each side: a tube is
#: told from a neck by its length, and the lasso bound needs walls wider than 2 d around a gap, which a small
#: object does not have (the decimated knight, 3.5 loop lengths across: loops of its bridge's class 0.43 of
#: the bound 2 L away on both sides, so 2 L let a false handle stand, noise draw 50 at 0.1 h).
SLIDE_AWAY = 4.0
#: The samples tried lie within this many loop lengths of the loop along M_S: a band of 2 L beyond SLIDE_AWAY
#: for the spread roots, where the bound is 9-13 L and a pinched tube's meridians (2-3 L) are under half of it.
SLIDE_FAR = 6.0
#: Samples tried (spread by farthest-point sampling over those within SLIDE_FAR L): a tube leaves the
#: loop on two sides, and the spread roots lie along it.
SLIDE_ROOTS = 12


def slides(
    points: np.ndarray, tris: np.ndarray, edges: np.ndarray, cocycles: dict, loop: np.ndarray
) -> tuple[bool, float]:
    """Whether ``loop`` slides on both of its sides: a loop of its class SLIDE_MARGIN times shorter than 2 d + L.

    Parameters
    ----------
    points : ndarray of shape (m, 3)
        The (capped) surface's points.
    tris : ndarray of shape (t, 3)
        Its triangles.
    edges : ndarray of shape (e, 2)
        Its edges (sorted rows), in the order of ``cocycles["mask"]``.
    cocycles : dict
        :func:`.loops.short_basis`'s ``cocycles`` (``mask``, ``edge_ids``, ``graph``).
    loop : ndarray of int
        The handle's loop, a closed walk on the surface's edges.

    Returns
    -------
    (bool, float)
        Whether it slides on both sides, and the ratio of the loop found through a sample d away to the
        lasso bound 2 d + L on the side where it is larger (inf where a side has none).
    """
    loop = np.asarray(loop, np.int64)
    target = walk_class(loop, cocycles)
    sides = _sides(tris, loop, len(points))
    if len(loop) < 3 or not target.any() or sides is None:
        return False, float("inf")
    g = cocycles["graph"]
    length = walk_length(points, loop)
    # distances from either side of the loop, not across it
    keep = np.ones(len(points))
    keep[loop] = 0.0
    cut = diags(keep) @ g @ diags(keep)
    far = [dijkstra(cut, indices=seeds, min_only=True, limit=SLIDE_FAR * length) for seeds in sides]
    ratios = []
    for mine, other in (far, far[::-1]):
        near = np.flatnonzero(np.isfinite(mine) & (mine <= other) & (mine >= SLIDE_AWAY * length))
        if len(near) == 0:
            return False, float("inf")
        found = _class_loops(points, edges, cocycles, target, length, mine, _spread(points, near, SLIDE_ROOTS))
        if not found:
            return False, float("inf")
        shortest = min([length] + [ell for _, ell in found])  # the bound with the shortest loop of the class seen
        ratios.append(min(ell / (2 * d + shortest) for d, ell in found))
    ratio = max(ratios)
    return ratio * SLIDE_MARGIN <= 1.0, ratio


def _sides(tris: np.ndarray, loop: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The vertices beside the loop on each of its two sides; None unless the loop has exactly two.

    The triangles with a loop vertex, joined across their edges that are not the loop's, fall into two strips
    along a loop that has two sides (a loop through a vertex twice, or a one-sided one, gives another count).
    """
    on = np.zeros(n, bool)
    on[loop] = True
    strip = np.flatnonzero(on[tris].any(axis=1))
    t = np.sort(tris[strip], axis=1)
    keys = np.stack([t[:, 0] * n + t[:, 1], t[:, 1] * n + t[:, 2], t[:, 0] * n + t[:, 2]], axis=1).ravel()
    lo, hi = np.minimum(loop, np.roll(loop, -1)), np.maximum(loop, np.roll(loop, -1))
    across = ~np.isin(keys, lo * n + hi)
    owner = np.repeat(np.arange(len(t)), 3)[across]
    k = keys[across]
    order = np.argsort(k, kind="stable")
    same = np.flatnonzero(k[order][1:] == k[order][:-1])
    pairs = np.stack([owner[order][same], owner[order][same + 1]], axis=1)
    count, label = graph_components(len(t), pairs)
    if count != 2:
        return None
    seeds = [np.setdiff1d(t[label == c].ravel(), loop) for c in range(2)]
    if not all(len(s) for s in seeds) or np.intersect1d(*seeds).size:
        return None
    return seeds[0], seeds[1]


def _class_loops(
    points: np.ndarray,
    edges: np.ndarray,
    cocycles: dict,
    target: np.ndarray,
    length: float,
    away: np.ndarray,
    roots: list[int],
) -> list[tuple[float, float]]:
    """(d, shortest loop of class ``target`` through the root) per root that has one under SLIDE_MARGIN's bound."""
    g, mask = cocycles["graph"], cocycles["mask"]
    hot = np.flatnonzero(mask.any(axis=1))
    elen = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    found = []
    for r in roots:
        d = float(away[r])
        # a loop under the bound through r keeps within half its length of r
        dist, pred = dijkstra(g, indices=[r], return_predecessors=True, limit=(2 * d + length) / SLIDE_MARGIN / 2)
        dist, pred = dist[0], pred[0]
        reached = np.isfinite(dist)
        sel = np.flatnonzero(reached[edges[:, 0]] & reached[edges[:, 1]])
        a, b = edges[sel, 0], edges[sel, 1]
        tree = (pred[a] == b) | (pred[b] == a)
        sel, a, b = sel[~tree], a[~tree], b[~tree]
        if len(sel) == 0:
            continue
        pm = _path_masks(pred, edges[hot], mask[hot])
        same = (pm[a] ^ pm[b] ^ mask[sel] == target).all(axis=1)
        if same.any():
            found.append((d, float((dist[a[same]] + elen[sel[same]] + dist[b[same]]).min())))
    return found
