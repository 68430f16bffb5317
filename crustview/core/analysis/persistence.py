"""The sample's own loops in any dimension: the 1-dimensional persistence (Z/2) of its alpha complex.

Why
---
The union of balls of radius r around a sample of a manifold M has M's homology for r between the
sampling density and the reach (Niyogi, Smale and Weinberger 2008); the alpha complex (Edelsbrunner 1995),
a subcomplex of the Delaunay triangulation, has the union's homotopy type at every r.  A loop of M is
therefore a 1-cycle of the alpha complex that is born when the balls close around it and lives until they
fill it: from about eps * lfs to about lfs, a ratio 1 / eps.  Noise and the sample's own gaps make cycles
too, born at the spacing and gone within a few spacings.  Beyond the reach the union gains loops M lacks:
where two parts of M come close (a curve passing near itself, a bent surface whose tips nearly meet) the
balls close a loop across the gap.

:mod:`.alpha` reads the plane's loops by duality; in R^3 and beyond a loop is no region of the
complement.  The pairs (Z/2 coefficients, as the Betti numbers the report gives) come from the
coboundary reduction with clearing (de Silva, Morozov and Vejdemo-Johansson 2011; Ripser's choice), which
gives the same pairs as reducing the triangles' boundaries (Edelsbrunner, Letscher and Zomorodian 2002):
the edges enter in order of their alpha value, each joining two components (no cycle) or closing one;
each cycle-closing edge, latest first, is a column of the triangles that contain it, and its reduced
column's earliest triangle is the one that ends its cycle.

What the report does with it
----------------------------
Where the robust extension built a closed M_S in codimension 2 or more (surfaces in R^4 and R^5, curves in
space: the growing path, which has no inside and outside to label), :func:`missing_loops` names as an
uncertain feature each loop the sample holds *for sure* beyond M_S's first Betti number.  For sure is two
conditions on a cycle born at radius b by the edge (u, v):

* it lives to at least :data:`PERSISTENT_SURE` b = 4 b.  The curve rule calls a cycle the sample's at 2 b
  (eps = 1/2, :data:`~.alpha.PERSISTENT`); twice that is the margin of two in eps that ``resample-check``
  (LOOP_CHECKED = 8 pi over 4 pi) also takes, an analogy, not a theorem.  Measured with GUDHI's alpha
  complex on every variant of ``bench_variants.py`` of the flat Klein bottle and the Clifford torus in R^4
  (draws 0 and 10): their loops live 4.7-11 times their birth, the noise's and the gaps' at most 2.6;
* it is born below the local unit at its edge (the larger of the nearest-neighbour distance and M_S's
  sampling radius at u or v, as the features measure a gap between components): a loop of M closes across
  an edge between neighbours along M, at most twice the sampling radius long; a loop born later closes
  across a gap of 2 b >= GAP_MIN units, which the sample resolves as a gap, so the loop is the ambient
  space's (the near approaches above, born at 1.1-3.3 spacings where the manifolds' loops are born at
  0.7-0.8: a review's figure eight in R^3 and bent capsule in R^4, each right and flagged before this
  condition).  Where the gap is below GAP_MIN the sample does not tell whether the parts touch, and a loop
  across it is counted: that doubt is the report's to give.

A flat Klein bottle with noise of 1 % of its size (``bench_variants.py --draw 10``) was grown into a closed
sphere with two crosscaps, both cut as below the sample's resolution (3.0 and 3.1 sampling radii): a sphere
for a Klein bottle, with nothing said; its sample holds both loops (7.5 and 5.7 times their birth).

The values are those of the run's own Delaunay cells, bounding points included, in the coordinates the
cells were built in (the joggled working coordinates, :func:`crustview.core.prepare.prepare_points`):
without the joggle a grid's cells are flat and their values wrong (a 48 x 24 torus grid in R^4 had 731
false loops), and without the cells at the bounding points the rest is no alpha complex (loops die late or
never).  Cycles closed by an edge at a bounding point are left out.  The reduction stops at the radius
where every cycle born below the largest unit has lived 4 times its birth.

Cost: the alpha values of every face down to the edges, then the reduction over the cycle-closing edges;
under a second at 1,500 samples in R^4, a few seconds at 1,000 in R^5, so the check runs only where the
extension ran (the paper's own results, such as the 10,000-sample Klein bottle of the speed benchmark, keep
the paper's guarantees and are not checked).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import minimum_spanning_tree

from ..errors import check_cancel
from .alpha import PERSISTENT, alpha_levels
from .features import Feature

#: A loop of the sample is one it holds for sure when its cycle lives from radius r to at least this many
#: times r: an eps = 1/4 sample keeps its loops from eps * lfs to about lfs (twice the curve rule's
#: PERSISTENT = 2, eps = 1/2: the margin of two in eps ``resample-check`` takes over the resolution bound).
PERSISTENT_SURE = 2 * PERSISTENT


def loop_pairs(points: np.ndarray, top: np.ndarray, cancel: object | None = None, upto: float = math.inf) -> np.ndarray:
    """The persistence pairs of the 1-cycles of the alpha complex (Z/2): rows (birth, death, u, v).

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The points the Delaunay cells were built on.
    top : ndarray of shape (m, r + 1), r >= 2
        Their Delaunay r-simplices (r the dimension of their affine hull), all of them: the alpha values of
        a subset are not the alpha complex's.
    cancel : object with ``is_set()``, optional
        Checked between the stages and every few thousand edges (:class:`~crustview.core.errors.Cancelled`).
    upto : float
        Only the filtration up to this radius: a cycle still alive there gets death ``inf``.

    Returns
    -------
    ndarray of shape (p, 4)
        Birth and death radius of every cycle that lives a positive time, and the edge (u, v) whose
        arrival makes it.  Over a whole triangulation of a convex hull every cycle dies; ``inf`` marks one
        still alive at ``upto``.
    """
    top = np.asarray(top, dtype=np.int64)
    n = len(points)
    if top.ndim != 2 or len(top) == 0 or top.shape[1] < 3:
        return np.zeros((0, 4))
    top = np.sort(top, axis=1)
    faces, levels, _ = alpha_levels(points, top, upto)
    check_cancel(cancel)
    edges, e_sq = faces[1], levels[1]
    tris, t_sq = faces[2], levels[2]
    cut = upto * upto
    e_in, t_in = np.flatnonzero(e_sq <= cut), np.flatnonzero(t_sq <= cut)
    edges, e_sq, tris, t_sq = edges[e_in], e_sq[e_in], tris[t_in], t_sq[t_in]
    # the edges in filtration order; an edge that joins two components makes no cycle (H_0's pairs)
    e_order = np.argsort(e_sq, kind="stable")
    rank = np.empty(len(edges), np.int64)
    rank[e_order] = np.arange(len(edges))
    closes = _closing_edges(n, edges[e_order])  # per rank: True where the edge closes a cycle
    # each triangle's three edges as ranks (faces are sorted rows, so its edges are pairs of its columns;
    # a triangle in the filtration has its edges in it: an edge's value never exceeds its triangles')
    keys = edges[:, 0] * np.int64(n) + edges[:, 1]
    key_order = np.argsort(keys)
    sorted_keys = keys[key_order]

    def edge_rank(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return rank[key_order[np.searchsorted(sorted_keys, a * np.int64(n) + b)]]

    cols = np.stack(
        [edge_rank(tris[:, 0], tris[:, 1]), edge_rank(tris[:, 0], tris[:, 2]), edge_rank(tris[:, 1], tris[:, 2])],
        axis=1,
    )
    t_order = np.lexsort((np.arange(len(tris)), t_sq))
    death_sq = _cohomology_deaths(cols, t_order, t_sq, closes, cancel)
    born = np.flatnonzero(closes)
    b_sq, d_sq = e_sq[e_order][born], death_sq[born]
    live = d_sq > b_sq
    uv = edges[e_order][born][live]
    return np.c_[np.sqrt(b_sq[live]), np.sqrt(d_sq[live]), uv].reshape(-1, 4)


def _cohomology_deaths(
    cols: np.ndarray, t_order: np.ndarray, t_sq: np.ndarray, closes: np.ndarray, cancel: object | None
) -> np.ndarray:
    """Per edge rank, the squared radius at which the cycle it closes dies (inf: not in the filtration).

    The cycle-closing edges, latest first, each a column of the triangles that contain it (by their rank in
    the filtration); a column's pivot is its earliest triangle.  An edge that joins two components has a
    column that reduces to zero and is skipped (clearing).  Most columns are their own pivot at once, where
    reducing the triangles' boundaries spent most of its time cancelling the triangles that close 2-cycles
    (5.6 million column additions for a 1,000-sample torus in R^5).  Columns are Python sets: their size is
    their triangles' count, where a bit set over the triangles' ranks held up to (triangles / 8) bytes per
    pivot (2.6 GB for a noise-free torus in R^5, a review found).
    """
    t_count = len(t_order)
    t_rank = np.empty(t_count, np.int64)
    t_rank[t_order] = np.arange(t_count)
    edge_of = cols.ravel()
    order = np.argsort(edge_of, kind="stable")
    tri_ranks = np.repeat(t_rank, 3)[order].tolist()
    starts = np.searchsorted(edge_of[order], np.arange(len(closes) + 1)).tolist()
    death = np.full(len(closes), np.inf)
    pivot: dict[int, set[int]] = {}
    for step, e in enumerate(np.flatnonzero(closes)[::-1].tolist()):
        if step % 4096 == 0:
            check_cancel(cancel)
        col = set(tri_ranks[starts[e] : starts[e + 1]])
        while col:
            low = min(col)
            other = pivot.get(low)
            if other is None:
                pivot[low] = col
                death[e] = t_sq[t_order[low]]
                break
            col ^= other
    return death


def _closing_edges(n: int, ordered: np.ndarray) -> np.ndarray:
    """Per edge in the given order, whether both its ends are already joined by the earlier edges.

    Those are the edges outside the minimum spanning forest of the order (Kruskal's greedy forest is the
    union-find over the edges in order, and with distinct weights the forest is unique): scipy's.
    """
    rank = np.arange(1, len(ordered) + 1, dtype=float)  # distinct positive weights: the order itself
    graph = coo_matrix((rank, (ordered[:, 0], ordered[:, 1])), shape=(n, n)).tocsr()
    forest = minimum_spanning_tree(graph).tocoo()
    out = np.ones(len(ordered), bool)
    out[forest.data.astype(np.int64) - 1] = False
    return out


def persistent_loops(points: np.ndarray, top: np.ndarray, cancel: object | None = None) -> np.ndarray:
    """The rows of :func:`loop_pairs` that live from r to at least :data:`PERSISTENT_SURE` r, longest-lived first."""
    pairs = loop_pairs(points, top, cancel)
    keep = pairs[pairs[:, 1] >= PERSISTENT_SURE * pairs[:, 0]]
    return keep[np.argsort(-keep[:, 1] / keep[:, 0], kind="stable")]


def sure_loops(points: np.ndarray, top: np.ndarray, unit: np.ndarray, cancel: object | None = None) -> np.ndarray:
    """The loops a sample holds for sure: rows of :func:`loop_pairs` among the samples (module text).

    Parameters
    ----------
    points : ndarray of shape (n + b, k)
        The samples (first ``len(unit)`` rows) and any bounding points, as the Delaunay cells were built.
    top : ndarray
        The Delaunay cells over ``points``, all of them.
    unit : ndarray of shape (n,)
        Each sample's local unit in the coordinates of ``points``.
    cancel : object with ``is_set()``, optional

    Returns
    -------
    ndarray of shape (p, 4)
        (birth, death, u, v) of every cycle closed by an edge between two samples, born below the larger
        unit of u and v, that lives at least :data:`PERSISTENT_SURE` times its birth; longest-lived first.
    """
    n = len(unit)
    if n == 0:
        return np.zeros((0, 4))
    pairs = loop_pairs(points, top, cancel, upto=PERSISTENT_SURE * float(np.max(unit)))
    uv = pairs[:, 2:].astype(np.int64)
    ours = (uv < n).all(axis=1)
    pairs, uv = pairs[ours], uv[ours]
    local = np.maximum(unit[uv[:, 0]], unit[uv[:, 1]])
    keep = (pairs[:, 0] < local) & (pairs[:, 1] >= PERSISTENT_SURE * pairs[:, 0])
    keep = pairs[keep]
    return keep[np.argsort(-keep[:, 1] / keep[:, 0], kind="stable")]


def missing_loops(
    points: np.ndarray,
    top: np.ndarray,
    unit: np.ndarray,
    b1: int,
    d: int,
    scale: float = 1.0,
    cancel: object | None = None,
) -> tuple[list[Feature], int]:
    """Uncertain features for loops the sample holds for sure and a closed M_S with first Betti number ``b1`` lacks.

    Parameters
    ----------
    points, top, unit, cancel
        As in :func:`sure_loops`.
    b1 : int
        M_S's first Betti number (Z/2).
    d : int
        M_S's dimension: a missing loop is a handle of a surface (d >= 2) or a closed curve (d = 1, a
        ``component``).
    scale : float
        What a length in ``points`` is in the samples' own coordinates (the features' locations are there).

    Returns
    -------
    features : list of Feature
        One disputed, uncertain feature per loop missing, placed at the edge that closes the cycle (the
        cycles beyond the ``b1`` longest-lived are named); its size is the death radius (or the radius where
        the reduction stopped, for a cycle alive there) over the local unit times 2 pi, the length of a
        circle the balls fill at that radius.  The location is in ``points``'
        coordinates.
    sure : int
        How many loops the sample holds for sure.
    """
    sure = sure_loops(points, top, unit, cancel)
    out = []
    kind = "handle" if d >= 2 else "component"
    for birth, death, u, v in sure[b1:].tolist():
        pair = np.array([int(u), int(v)])
        local = float(max(unit[pair[0]], unit[pair[1]]))
        # a cycle alive where the reduction stopped (4 times the largest unit) lives at least that long
        last = min(death, PERSISTENT_SURE * float(np.max(unit)))
        size = 2 * math.pi * last / local if local > 0 else math.inf
        span = f"to {last * scale:.3g}" if math.isfinite(death) else f"past {last * scale:.3g}"
        reason = (
            f"the sample holds {len(sure)} loops for sure (cycles of its union of balls born within a "
            f"sampling radius and living {PERSISTENT_SURE:g} times their birth or more) and M_S has {b1}: this "
            f"one lives from radius {birth * scale:.3g} {span} ({last / birth:.3g} times its birth"
            + ("" if math.isfinite(death) else " or more")
            + "), and M_S may lack it"
        )
        out.append(Feature(kind, points[pair].mean(axis=0), size, True, pair, reason, disputed=True))
    return out, len(sure)


__all__ = ["PERSISTENT_SURE", "loop_pairs", "missing_loops", "persistent_loops", "sure_loops"]
