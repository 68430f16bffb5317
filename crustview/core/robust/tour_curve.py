"""Rule ``tour-curve``: a curve the growing path left broken is closed by a short tour of its samples.

Why
---
For a curve (d = 1) the paper's loop and the growing path work edge by edge
from the candidate test.  Under noise of the order of the spacing the normal
lines of Algorithm 1 turn so far that a sample's two neighbours along the
curve are no longer its candidates: the ellipse with noise of 1 % of its size
(sigma = 0.95-1.05 h) came out right for 5 of 12 sample seeds (session 22;
the others open, in several pieces, or with samples left out).

For curves there is a global answer with a theorem behind it: the shortest
closed polygon through the samples of one closed curve (the travelling
salesman tour) follows the curve once the sample is dense for its local
feature size (Giesen 1999, *Curve reconstruction, the traveling salesman
problem and Menger's theorem on length*; Althaus and Mehlhorn 2000).  Noise
across the curve moves samples sideways, not along it, so a short tour still
visits them in their order along the curve where the noise is small against
the feature size.

A tour is one curve, so the samples must first be split into their curves: a
tour through two curves that pass within two spacings of each other (the Hopf
link's circles at 1 % noise) would be one closed curve for two, with nothing
to flag it.  The split comes from the samples' own homology
(:class:`~crustview.core.analysis.alpha.AlphaLadder`): each closed curve is one
1-cycle of the union of balls around its samples, for radii between the
sampling density and the reach.

The rule
--------
Only for curves in the plane (where duality gives the cycles' persistence
from a union-find), only in robust mode, and only where the growing path's
complex is not already a closed 1-manifold through every sample: every curve
that was right is unchanged.  Curves in R^3 and beyond keep the growing
path's result.

1. The persistence pairs (birth radius, death radius) of the 1-cycles of the
   alpha filtration are computed (:meth:`AlphaLadder.loops`).  A cycle that
   lives from r to at least :data:`~crustview.core.analysis.alpha.PERSISTENT` r is one of the sample's curves;
   the others are gaps of the noise.  Their number is c.
2. From the radius where the last persistent cycle is born, in steps of a
   quarter octave while every persistent cycle is still there, the first
   radius where the union has c components, each carrying one persistent
   cycle, splits the samples into c curves.  Without such a radius the curves
   touch at every scale where they exist; the split is not decided and the
   rule does nothing (the growing path's result stays, open or flagged).
3. Each curve's samples get a short closed tour: the greedy-edge tour,
   improved by 2-opt and Or-opt moves among each sample's :data:`NEIGHBOURS`
   nearest until no such move shortens it (each move shortens it by more than
   :data:`SHORTER` of the lengths compared, so the moves end; a crossing of
   two tour edges among near samples is undone by a 2-opt move).  The tours replace the complex in one step of the log
   (the edges removed, and the tours' edges added, oriented along the tour).
4. The result is always *uncertain*: one ``component`` feature at the tours'
   longest step (its size that step in median spacings).  The rule runs where
   the noise is of the order of the spacing, and there two curves within the
   noise of each other look like one noisy curve: a nested pair of circles two
   to six spacings apart under noise of 0.3-1 spacing has persistent cycles
   as short-lived as the noise's (death over birth 1.4-2.2 against the single
   noisy ellipse's 1.1-1.5), so its tour can run through both.  Only the
   longest-lived cycles are told apart with confidence, not the count.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
from scipy.spatial import cKDTree

from ..analysis.alpha import PERSISTENT, AlphaLadder
from ..analysis.features import Feature
from ..errors import Cancelled
from ..steps import RULE_TOUR
from ..util.nearest import nearest_distances
from .patcher import Patcher

#: Candidate partners of a 2-opt move: each sample's nearest samples (the move joins a sample to one of
#: them).  Along a curve the tour's neighbours of a sample are among its few nearest; eight covers noise
#: of the order of the spacing, where the two along-curve neighbours can be the fifth or sixth nearest.
NEIGHBOURS = 8
#: A move is taken only when it shortens the tour by more than this share of the lengths it compares:
#: well above their rounding (1e-16 relative), so that a move and its undoing cannot both look shorter
#: (the removal gain of Or-opt can be negative; a tolerance that changed sign with it looped forever).
SHORTER = 1e-12
#: Radii tried for the split, from the last persistent cycle's birth on: a quarter octave apart.
STEP = 2.0**0.25


def curve_groups(points: np.ndarray) -> list[np.ndarray] | None:
    """The samples of each closed curve the sample stands for (steps 1 and 2), or None when undecided.

    Parameters
    ----------
    points : ndarray of shape (n, 2)

    Returns
    -------
    list of ndarray or None
        One index array per curve (every sample in exactly one), or None when the sample holds no
        persistent cycle or no radius where each component of the union carries exactly one.
    """
    n = len(points)
    if n < 4 or points.shape[1] != 2:
        return None
    ladder = AlphaLadder(points)
    pairs = ladder.loops()
    keep = pairs[:, 1] >= PERSISTENT * pairs[:, 0]
    loops = pairs[keep]
    c = len(loops)
    if c == 0:
        return None
    lo, hi = float(loops[:, 0].max()), float(loops[:, 1].min())
    # radii where every persistent cycle is there: from the last birth, a quarter octave at a time
    radii = [lo * STEP**i for i in range(int(math.log(hi / lo, STEP)) + 1)] if hi > lo else []
    for r in radii:
        labels = ladder.components(r)
        if labels.max() + 1 != c:
            continue
        carriers = labels[loops[:, 2].astype(np.int64)]
        if len(np.unique(carriers)) == c:  # one persistent cycle in each component
            return [np.flatnonzero(labels == g) for g in range(c)]
    return None


def _closed_curve_through_all(pt: Patcher, n: int, left: list[int]) -> bool:
    """Whether the complex is a closed 1-manifold through every sample (each sample in exactly two edges)."""
    if left:
        return False
    degree = np.zeros(n, np.int64)
    for s, a in zip(pt.simp, pt.alive, strict=True):
        if a:
            degree[list(s)] += 1
    return bool((degree == 2).all())


def tour_curve(
    pt: Patcher, points: np.ndarray, edges: np.ndarray, left: list[int], cancel: object | None = None
) -> tuple[Patcher, list[int], list[Feature]]:
    """Apply ``tour-curve`` to a grown curve (see the module docstring).

    Returns the complex, the samples left out, and the uncertain feature of step 4 (none when the rule
    did not apply).

    Parameters
    ----------
    pt : Patcher
        The grown complex after its last phase (d = 1).
    points : ndarray of shape (n, k)
    edges : ndarray of shape (e, 2)
        Every Delaunay edge among the samples (the greedy start's candidates, with the nearest samples).
    left : list of int
        The samples ``pt`` leaves out.
    cancel : threading.Event, optional
        Checked between the tours' moves; when set, :class:`~crustview.core.errors.Cancelled` is raised.
    """
    n, k = points.shape
    if k != 2 or n < 4 or _closed_curve_through_all(pt, n, left):
        return pt, left, []
    groups = curve_groups(points)
    if groups is None or any(len(g) < 3 for g in groups):
        return pt, left, []
    edges = np.asarray(edges, np.int64)
    want: dict[tuple[int, ...], int] = {}
    longest = (-1.0, 0, 0)  # the tours' longest step and its ends
    for g in groups:
        inside = np.zeros(n, bool)
        inside[g] = True
        local = np.full(n, -1, np.int64)
        local[g] = np.arange(len(g))
        own = edges[inside[edges].all(axis=1)]
        tour = g[short_tour(points[g], local[own], cancel)]
        nxt = np.roll(tour, -1)
        step = np.linalg.norm(points[tour] - points[nxt], axis=1)
        at = int(np.argmax(step))
        longest = max(longest, (float(step[at]), int(tour[at]), int(nxt[at])))
        want.update({tuple(sorted((int(a), int(b)))): (1 if a < b else -1) for a, b in zip(tour, nxt, strict=True)})
    removed = [i for i, (s, alive) in enumerate(zip(pt.simp, pt.alive, strict=True)) if alive and s not in want]
    for i in removed:
        pt._delete(i)
    added = []
    for s, o in want.items():
        i = pt.index.get(s)
        if i is not None and pt.alive[i]:
            continue
        added.append(pt._insert(s, o))
    sizes = ", ".join(str(len(g)) for g in groups)
    pt.log.append(
        (
            RULE_TOUR,
            (int(groups[0][0]),),
            tuple(added),
            tuple(removed),
            float("nan"),
            f"the grown curve was not closed through every sample; the union of balls around the samples "
            f"holds {len(groups)} persistent loop{'s' if len(groups) > 1 else ''} (samples {sizes}), each "
            f"replaced by a short closed tour of its samples (greedy edges, then 2-opt and Or-opt among the "
            f"{NEIGHBOURS} nearest): {len(removed)} edges out, {len(added)} in",
        )
    )
    h = float(np.median(nearest_distances(points)))
    length, a, b = longest
    size = length / h if h > 0 else math.inf
    doubt = Feature(
        "component",
        (points[a] + points[b]) / 2,
        size,
        True,
        np.array([a, b], np.int64),
        f"closed by rule tour-curve: the samples are as noisy as they are dense, where two curves within the "
        f"noise of each other look like one; the tours' longest step ({size:.2f} spacings) is here",
    )
    return pt, [], [doubt]


def short_tour(points: np.ndarray, edges: np.ndarray, cancel: object | None = None) -> np.ndarray:
    """A short closed tour of all the samples: greedy edges, then 2-opt and Or-opt moves to a local optimum.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    edges : ndarray of shape (e, 2)
        Edges among the samples that connect them (the Delaunay edges); the greedy start takes the shortest
        of them and of each sample's nearest ones, and joins the paths it leaves by their nearest ends.
    cancel : threading.Event, optional
        Checked every 256 moves (the moves are pure Python: about 5 s for 4,000 samples).

    Returns
    -------
    ndarray of shape (n,)
        The samples in tour order (each once); empty when fewer than three.
    """
    n = len(points)
    if n < 3:
        return np.zeros(0, np.int64)
    k = min(NEIGHBOURS + 1, n)
    tree = cKDTree(points)
    near = tree.query(points, k=k)[1][:, 1:]
    tour = np.asarray(_greedy_start(points, np.asarray(edges, np.int64), near), np.int64)
    pos = np.empty(n, np.int64)
    pos[tour] = np.arange(n)

    def dist(a: int, b: int) -> float:
        return float(np.sqrt(((points[a] - points[b]) ** 2).sum()))

    def reverse(lo: int, hi: int) -> None:
        """Reverse the tour between positions lo and hi (inclusive, cyclically, lo first)."""
        idx = np.arange(lo, hi + 1 if hi >= lo else hi + n + 1) % n
        tour[idx] = tour[idx[::-1]]
        pos[tour[idx]] = idx

    def two_opt(a: int) -> list[int]:
        for side in (1, -1):  # the tour edge after a, then the one before it
            i = int(pos[a])
            b = int(tour[(i + side) % n])
            ab = dist(a, b)
            for c in near[a].tolist():
                j = int(pos[c])
                d = int(tour[(j + side) % n])
                if c == b or d == a:
                    continue
                if dist(a, c) + dist(b, d) < ab + dist(c, d) - SHORTER * ab:
                    # a-b and c-d become a-c and b-d: reverse the stretch from b to c
                    if side == 1:
                        reverse((i + 1) % n, j)
                    else:
                        reverse(j, (i - 1) % n)
                    return [a, b, c, d]
        return []

    todo = deque(range(n))
    queued = np.ones(n, bool)
    visits = 0
    while todo:
        visits += 1
        if cancel is not None and visits % 256 == 0 and cancel.is_set():  # type: ignore[attr-defined]
            raise Cancelled("reconstruction cancelled")
        a = todo.popleft()
        queued[a] = False
        touched = two_opt(a) or _or_move(tour, pos, a, near, dist)
        for v in touched:
            i = int(pos[v])
            for w in (v, int(tour[(i - 1) % n]), int(tour[(i + 1) % n])):
                if not queued[w]:
                    queued[w] = True
                    todo.append(w)
    return tour


def _greedy_start(points: np.ndarray, edges: np.ndarray, near: np.ndarray) -> list[int]:
    """The greedy-edge start, a tour of the samples in order.

    Shortest edges first while every sample has at most two and no cycle closes early; the paths left are
    joined end to end, each time to the nearest free end of another path.
    """
    n = len(points)
    cand = np.concatenate([edges, np.stack([np.repeat(np.arange(n), near.shape[1]), near.ravel()], axis=1)])
    cand = np.unique(np.sort(cand, axis=1), axis=0)
    cand = cand[cand[:, 0] != cand[:, 1]]
    length = np.linalg.norm(points[cand[:, 0]] - points[cand[:, 1]], axis=1)
    parent = list(range(n))

    def find(v: int) -> int:
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    degree = [0] * n
    adj: list[list[int]] = [[] for _ in range(n)]
    taken = 0
    for e in np.argsort(length, kind="stable").tolist():
        a, b = int(cand[e, 0]), int(cand[e, 1])
        if degree[a] > 1 or degree[b] > 1:
            continue
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        parent[ra] = rb
        degree[a] += 1
        degree[b] += 1
        adj[a].append(b)
        adj[b].append(a)
        taken += 1
        if taken == n - 1:
            break
    # walk the paths; join each path's end to the nearest free end of a path not yet walked
    done = np.zeros(n, bool)
    ends = [v for v in range(n) if degree[v] < 2]
    tree = cKDTree(points[ends]) if ends else None
    order: list[int] = []
    start = ends[0] if ends else 0
    while True:
        prev, v = -1, start
        while True:
            order.append(v)
            done[v] = True
            nxt = [w for w in adj[v] if w != prev and not done[w]]
            if not nxt:
                break
            prev, v = v, nxt[0]
        if len(order) == n:
            return order
        free = [j for j in range(len(ends)) if not done[ends[j]]]
        if tree is None or not free:
            rest = np.flatnonzero(~done)
            start = int(rest[0])
            continue
        _, idx = tree.query(points[v], k=len(ends))
        start = next(ends[j] for j in np.atleast_1d(idx).tolist() if not done[ends[j]])


def _or_move(tour: np.ndarray, pos: np.ndarray, a: int, near: np.ndarray, dist) -> list[int]:  # noqa: ANN001
    """One Or-opt move at ``a``, if one shortens the tour; the samples whose tour edges changed, or none.

    The stretch of 1-3 samples from ``a`` on goes between two tour neighbours c, e with c among the
    nearest samples of either end (either way round).  Edits ``tour`` and ``pos`` in place.
    """
    n = len(tour)
    i = int(pos[a])
    for size in (1, 2, 3):
        if n - size < 3:
            break
        seg = [int(tour[(i + t) % n]) for t in range(size)]
        p, q = int(tour[(i - 1) % n]), int(tour[(i + size) % n])
        gain = dist(p, seg[0]) + dist(seg[-1], q) - dist(p, q)
        inside = set(seg)
        for end in (seg[0], seg[-1]):
            for c in near[end].tolist():
                if c in inside:
                    continue
                j = int(pos[c])
                for e in (int(tour[(j + 1) % n]), int(tour[(j - 1) % n])):
                    if e in inside or {c, e} == {p, q}:
                        continue
                    ahead = dist(c, seg[0]) + dist(seg[-1], e)
                    back = dist(c, seg[-1]) + dist(seg[0], e)
                    cost = min(ahead, back) - dist(c, e)
                    if cost < gain - SHORTER * (abs(gain) + abs(cost)):
                        rest = [int(x) for x in np.roll(tour, -((i + size) % n))[: n - size]]  # q ... p
                        k = rest.index(c)
                        piece = seg if ahead <= back else seg[::-1]
                        if rest[(k + 1) % len(rest)] == e:  # c then e along the rest: the stretch between them
                            new = rest[: k + 1] + piece + rest[k + 1 :]
                        else:  # e then c
                            new = rest[:k] + piece[::-1] + rest[k:]
                        tour[:] = new
                        pos[tour] = np.arange(n)
                        return [p, q, c, e, *seg]
    return []
