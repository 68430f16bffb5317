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

So a loop of length L *slides* when, through some sample r at a distance d
of at least :data:`SLIDE_AWAY` L = 2 L from it along M_S, there is a loop of
the same Z/2 class shorter than the lasso bound 2 d + L by a factor
:data:`SLIDE_MARGIN` = 2 (L the shortest loop of the class found, here or
through r).  Round a tunnel or a bridge no loop passes that test (the loop
itself, at d = 0, has the ratio 1); a tube's meridian keeps its length while
the bound grows with d (a pinch of half the tube's width doubles the
meridians beside it, and the test passes from about d = 3 L on: the knotted
tube of the held-out data at 0.1 h, a pinch of 8.5 radii in a tube whose
meridians measure 17.6 on the true mesh, ratio 0.17 at d = 6 L).  The
samples r are spread (farthest-point sampling) over those between SLIDE_AWAY L
and :data:`SLIDE_FAR` L from the loop: a neck about as long as it is wide is
no tube (two parts in contact over a stretch look like one, and so does a
short real handle: both stay undecided).  A loop that slides is the sample's
own evidence of a tube, not of a gap of a few cells: its handle is supported
(:func:`.features._handles`), and ``cut-handle`` leaves it (a tunnel through
a wall several times thicker than its width slides too; it is a real bore,
not noise).  Below LOOP_MIN nothing changes: no eps < 1 sample resolves such
a loop at all.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import dijkstra

from .loops import _path_masks, _spread
from .necks import walk_class, walk_length

#: How much shorter than the lasso bound 2 d + L a loop through a sample d away must be for the loop to
#: slide: a factor 2 (a tunnel's or a bridge's loops reach the bound at best, the loop itself at d = 0).
SLIDE_MARGIN = 2.0
#: The samples tried lie at least this many loop lengths from the loop along M_S: a tube is told from a neck
#: by its length, and a contact between two parts can stretch over a loop length or so (the decimated
#: knight's arm on its body, where a loop of its class 0.8 L away measures 1.1 L; a cup's short handle
#: looks the same and stays undecided); two meridians on one side is a tube.
SLIDE_AWAY = 2.0
#: The samples tried lie within this many loop lengths of the loop along M_S: far enough for a pinched
#: tube's meridians (up to a few L) to be under half the bound (2 d + L) / 2 at d = SLIDE_FAR L = 6.5 L.
SLIDE_FAR = 6.0
#: Samples tried (spread by farthest-point sampling over those within SLIDE_FAR L): a tube leaves the
#: loop on two sides, and the spread roots lie along it.
SLIDE_ROOTS = 12


def slides(points: np.ndarray, edges: np.ndarray, cocycles: dict, loop: np.ndarray) -> tuple[bool, float]:
    """Whether a loop of ``loop``'s class through a sample d away is SLIDE_MARGIN times shorter than 2 d + L.

    Parameters
    ----------
    points : ndarray of shape (m, 3)
        The (capped) surface's points.
    edges : ndarray of shape (e, 2)
        Its edges (sorted rows), in the order of ``cocycles["mask"]``.
    cocycles : dict
        :func:`.loops.short_basis`'s ``cocycles`` (``mask``, ``edge_ids``, ``graph``).
    loop : ndarray of int
        The handle's loop, a closed walk on the surface's edges.

    Returns
    -------
    (bool, float)
        Whether it slides, and the smallest ratio of a loop found through a sample d away to the lasso
        bound 2 d + L (inf where none was found).
    """
    loop = np.asarray(loop, np.int64)
    target = walk_class(loop, cocycles)
    if len(loop) < 3 or not target.any():
        return False, float("inf")
    g = cocycles["graph"]
    mask = cocycles["mask"]
    length = walk_length(points, loop)
    away = dijkstra(g, indices=np.unique(loop), min_only=True, limit=SLIDE_FAR * length)
    near = np.flatnonzero(np.isfinite(away) & (away >= SLIDE_AWAY * length))
    if len(near) == 0:
        return False, float("inf")
    hot = np.flatnonzero(mask.any(axis=1))
    marked, marked_mask = edges[hot], mask[hot]
    elen = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    found = []
    for r in _spread(points, near, SLIDE_ROOTS):
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
        pm = _path_masks(pred, marked, marked_mask)
        same = (pm[a] ^ pm[b] ^ mask[sel] == target).all(axis=1)
        if same.any():
            found.append((d, float((dist[a[same]] + elen[sel[same]] + dist[b[same]]).min())))
    if not found:
        return False, float("inf")
    shortest = min([length] + [ell for _, ell in found])  # the bound with the shortest loop of the class seen
    ratio = min(ell / (2 * d + shortest) for d, ell in found)
    return ratio * SLIDE_MARGIN <= 1.0, ratio
