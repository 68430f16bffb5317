"""The sample's own loops in any dimension: the 1-dimensional persistence (Z/2) of its alpha complex.

Why
---
The union of balls of radius r around a sample of a manifold M has M's homology for r between the
sampling density and the reach (Niyogi, Smale and Weinberger 2008); the alpha complex (Edelsbrunner 1995),
a subcomplex of the Delaunay triangulation, has the union's homotopy type at every r.  A loop of M is
therefore a 1-cycle of the alpha complex that is born when the balls close around it and lives until they
fill it: from about eps * lfs to about lfs, a ratio 1 / eps.  Noise and the sample's own gaps make cycles
too, born at the spacing and gone within a few spacings.

:mod:`.alpha` reads the plane's loops by duality; in R^3 and beyond a loop is no region of the
complement, and the pairs come from the standard reduction of the boundary matrix of the triangles
(Edelsbrunner, Letscher and Zomorodian 2002; Z/2 coefficients, as the Betti numbers the report gives):
the edges enter in order of their alpha value, each joining two components (no cycle) or closing a cycle;
the triangles enter in order, and each reduced column's lowest edge is the cycle the triangle ends.

What the report does with it
----------------------------
Where the robust extension grew M_S in codimension 2 or more (surfaces in R^4 and R^5, curves in space:
the growing path, which has no inside and outside to label), a closed M_S with fewer independent loops
(b_1) than the sample holds for sure has lost some: :func:`missing_loops` names each as an uncertain
feature.  *For sure* is :data:`PERSISTENT_SURE`: a cycle living from r to at least 4 r, which an
eps = 1/4 sample keeps (the margin of two in eps that ``resample-check``'s LOOP_CHECKED = 8 pi also
uses over the resolution bound).  Measured with GUDHI's alpha complex on every variant of
``bench_variants.py`` of the flat Klein bottle and the Clifford torus in R^4 (draws 0 and 10): the two
loops of each live 4.7-11 times their birth, the noise's and the gaps' at most 2.6 times.  A flat Klein
bottle with noise of 1 % of its size (``bench_variants.py --draw 10``) was grown into a closed sphere
with two crosscaps, both cut as below the sample's resolution (3.0 and 3.1 sampling radii): a sphere for
a Klein bottle, with nothing said; its sample holds both loops (7.5 and 5.7 times their birth).

Cost: the alpha values of every face down to the edges, and one pass of the reduction over the
triangles; a few seconds at a few thousand samples in R^4, so the check runs only where the growing
path ran (the paper's own results, such as the 10,000-sample Klein bottle of the speed benchmark, keep
the paper's guarantees and are not checked).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import check_cancel
from .alpha import PERSISTENT, alpha_levels
from .features import Feature

#: A loop of the sample is one it holds for sure when its cycle lives from radius r to at least this many
#: times r: an eps = 1/4 sample keeps its loops from eps * lfs to about lfs (twice the curve rule's
#: PERSISTENT = 2, eps = 1/2: the margin of two in eps ``resample-check`` takes over the resolution bound).
PERSISTENT_SURE = 2 * PERSISTENT


def loop_pairs(points: np.ndarray, top: np.ndarray, cancel: object | None = None) -> np.ndarray:
    """The persistence pairs of the 1-cycles of the alpha complex (Z/2): rows (birth, death, u, v).

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    top : ndarray of shape (m, r + 1), r >= 2
        Their Delaunay r-simplices (r the dimension of their affine hull).
    cancel : object with ``is_set()``, optional
        Checked every few thousand edges (:class:`~crustview.core.errors.Cancelled`).

    Returns
    -------
    ndarray of shape (p, 4)
        Birth and death radius of every cycle that lives a positive time, and the edge (u, v) whose
        arrival makes it.  Cycles still alive when every triangle is in (none, for a triangulation of a
        convex hull) get death ``inf``.
    """
    top = np.sort(np.asarray(top, dtype=np.int64), axis=1)
    n = len(points)
    if len(top) == 0 or top.shape[1] < 3:
        return np.zeros((0, 4))
    faces, levels, _ = alpha_levels(points, top)
    edges, e_val = faces[1], levels[1]
    tris, t_val = faces[2], levels[2]
    # the edges in filtration order; an edge that joins two components makes no cycle (H_0's pairs)
    e_order = np.argsort(e_val, kind="stable")
    rank = np.empty(len(edges), np.int64)
    rank[e_order] = np.arange(len(edges))
    closes = _closing_edges(n, edges[e_order])  # per rank: True where the edge closes a cycle
    # each triangle's three edges as ranks (faces are sorted rows, so its edges are pairs of its columns)
    keys = edges[:, 0] * np.int64(n) + edges[:, 1]
    key_order = np.argsort(keys)
    sorted_keys = keys[key_order]

    def edge_rank(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return rank[key_order[np.searchsorted(sorted_keys, a * np.int64(n) + b)]]

    cols = np.stack(
        [edge_rank(tris[:, 0], tris[:, 1]), edge_rank(tris[:, 0], tris[:, 2]), edge_rank(tris[:, 1], tris[:, 2])], 1
    )
    # faces before their cofaces at equal values: an edge's value never exceeds its triangles'
    t_order = np.lexsort((np.arange(len(tris)), t_val))
    death = _cohomology_deaths(cols, t_order, t_val, closes, cancel)
    born = np.flatnonzero(closes)
    b2, d2 = e_val[e_order][born], death[born]
    live = d2 > b2
    uv = edges[e_order][born][live]
    return np.c_[np.sqrt(b2[live]), np.sqrt(d2[live]), uv].reshape(-1, 4)


def _cohomology_deaths(
    cols: np.ndarray, t_order: np.ndarray, t_val: np.ndarray, closes: np.ndarray, cancel: object | None
) -> np.ndarray:
    """Per edge rank, the squared radius at which the cycle it closes dies (inf: never, or no cycle).

    The same pairs as reducing the triangles' boundaries (Z/2), read from the coboundaries instead
    (de Silva, Morozov and Vejdemo-Johansson 2011, "Dualities in persistent (co)homology"; Ripser's
    choice): the cycle-closing edges, latest first, each a column of the triangles that contain it, the
    earliest triangle lowest; an edge that joins two components has a column that reduces to zero and is
    skipped (clearing).  Most columns are their own pivot at once, where the triangles' reduction spent
    most of its time cancelling the triangles that close 2-cycles (5.6 million column additions for a
    1,000-sample torus in R^5).  A column is a Python int used as a bit set: XOR and the lowest bit run in C.
    """
    t_count = len(t_order)
    bit = np.empty(t_count, np.int64)
    bit[t_order] = t_count - 1 - np.arange(t_count)  # the earliest triangle has the highest bit
    edge_of = cols.ravel()
    order = np.argsort(edge_of, kind="stable")
    tri_bits = np.repeat(bit, 3)[order].tolist()
    starts = np.searchsorted(edge_of[order], np.arange(len(closes) + 1)).tolist()
    death = np.full(len(closes), np.inf)
    pivot: dict[int, int] = {}
    for step, e in enumerate(np.flatnonzero(closes)[::-1].tolist()):
        if step % 4096 == 0:
            check_cancel(cancel)
        col = 0
        for b in tri_bits[starts[e] : starts[e + 1]]:
            col ^= 1 << b
        while col:
            low = col.bit_length() - 1
            other = pivot.get(low)
            if other is None:
                pivot[low] = col
                death[e] = t_val[t_order[t_count - 1 - low]]
                break
            col ^= other
    return death


def _closing_edges(n: int, ordered: np.ndarray) -> np.ndarray:
    """Per edge in the given order, whether both its ends are already joined by the earlier edges."""
    parent = np.arange(n)

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    out = np.zeros(len(ordered), bool)
    for i, (a, b) in enumerate(ordered.tolist()):
        ra, rb = root(a), root(b)
        if ra == rb:
            out[i] = True
        else:
            parent[max(ra, rb)] = min(ra, rb)
    return out


def persistent_loops(points: np.ndarray, top: np.ndarray, cancel: object | None = None) -> np.ndarray:
    """The rows of :func:`loop_pairs` that live from r to at least :data:`PERSISTENT_SURE` r, longest-lived first."""
    pairs = loop_pairs(points, top, cancel)
    keep = pairs[pairs[:, 1] >= PERSISTENT_SURE * pairs[:, 0]]
    return keep[np.argsort(-keep[:, 1] / keep[:, 0], kind="stable")]


def missing_loops(
    points: np.ndarray, top: np.ndarray, b1: int, d: int, spacing: float, cancel: object | None = None
) -> list[Feature]:
    """Uncertain features for loops the sample holds for sure and a closed M_S with first Betti number ``b1`` lacks.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    top : ndarray
        Their Delaunay simplices (only rows among the samples are used).
    b1 : int
        M_S's first Betti number (Z/2).
    d : int
        M_S's dimension: a missing loop is a handle of a surface (d >= 2) or a closed curve (d = 1, a
        ``component``).
    spacing : float
        The samples' median nearest-neighbour distance (the unit of the sizes).
    cancel : object with ``is_set()``, optional

    Returns
    -------
    list of Feature
        One disputed, uncertain feature per loop missing, placed at the edge that closes the cycle (the
        most persistent cycles beyond the first ``b1`` are named); its size is the death radius over the
        spacing times 2 pi, the length of a circle the balls fill at that radius.
    """
    top = np.asarray(top, dtype=np.int64)
    top = top[(top < len(points)).all(axis=1)]
    sure = persistent_loops(points, top, cancel)
    if len(sure) <= b1:
        return []
    kind = "handle" if d >= 2 else "component"
    out = []
    for birth, death, u, v in sure[b1:].tolist():
        pair = np.array([int(u), int(v)])
        size = 2 * math.pi * death / spacing if spacing > 0 else math.inf
        reason = (
            f"the sample holds {len(sure)} loops for sure (cycles of its union of balls living from r to "
            f"{PERSISTENT_SURE:g} r or more) and M_S has {b1}: this one lives from {birth / spacing:.3g} to "
            f"{death / spacing:.3g} spacings ({death / birth:.3g} times its birth), and M_S may lack it"
        )
        out.append(Feature(kind, points[pair].mean(axis=0), size, True, pair, reason, disputed=True))
    return out


__all__ = ["PERSISTENT_SURE", "loop_pairs", "missing_loops", "persistent_loops"]
