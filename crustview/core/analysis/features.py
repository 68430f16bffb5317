"""Topological features of a result, and whether the sample supports each one.

A reconstruction can be a closed manifold through every sample and still have
the wrong topology: two parts that nearly touch joined by a bridge (a false
handle), a thin part cut through (a missing piece), a gap taken for a hole.
This module names every handle, hole and component of M_S, measures it in
local sample spacings, and calls it *uncertain* when the sampling cannot tell
it from a gap.

The measure and its bound
-------------------------
All sizes are in units of the local sampling radius h (:func:`local_spacing`:
about how far a point of M_S gets from every sample).  The paper's guarantees need an epsilon-sample,
h <= eps * LFS.  Voronoi-based reasoning (poles near the medial axis, Amenta
and Bern) needs at least eps < 1, so a feature whose local feature size is
below one spacing is below the resolution of *any* sampling condition:

* **Handle** (a generator of H_1 of a closed surface): a loop of length L
  around a tube of radius r has L = 2 pi r, and the tube's LFS is at most r.
  eps < 1 needs h < r, so a loop shorter than :data:`LOOP_MIN` = 2 pi
  spacings is below resolution: fewer than about six samples around it.
  Both a false bridge between parts that nearly touch and a tunnel punched
  through a thin part leave such a short loop.
  A loop below :data:`LOOP_SUPPORTED` = 4 pi is resolved only if eps > 1/2,
  beyond where reconstruction works in practice: such a handle is uncertain
  too.  The rule ``cut-handle`` removes both kinds where it can; a removed
  handle stays uncertain only if its loop was at least LOOP_MIN.
* **Component**: two sheets at distance g have LFS <= g / 2 between them,
  so eps < 1 needs h < g / 2.  A component closer than :data:`GAP_MIN` = 2
  spacings to another one may be one object with the other.  The spacing
  here is the larger of the sample's nearest-neighbour distance and h: on
  an anisotropic sample (rings dense along, sparse across) the nearest
  neighbour sees only the dense direction, and two walls closer than the
  sparse one are not resolved.
* **Hole** (a boundary loop of an open result): a hole whose span is below
  :data:`LOOP_MIN` / pi = 2 spacings (diameter of a circle of circumference
  LOOP_MIN) is as wide as one missing sample: it may be an undersampling
  gap rather than a real opening.  Its rim is a loop like a handle's, so the
  handles' second bound applies too: a span below :data:`HOLE_SUPPORTED` =
  LOOP_SUPPORTED / pi = 4 is resolved only by a sample coarser than
  eps = 1/2, and such a hole is uncertain.  Two holes closer than GAP_MIN spacings
  (the components' bound, in the same unit) are uncertain too: the strip of
  M_S between them is narrower than the sample resolves, one opening with a
  ribbon left across it (a cap the labelling split in two) or a real strip.
  A hole whose rim lies where M_S has two sheets facing opposite ways closer
  than GAP_MIN (a thin part, or a fold of one noisy sheet: :mod:`.sheets`) is
  uncertain too: the components' bound across one surface.

Handles are the loops of a short basis of H_1 (Z/2), found by :mod:`.loops` (a surface) or :mod:`.tunnels`
(d >= 3: the same bounds, a tunnel being a tube's S^1 factor as a surface handle is).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from .cotree import triangle_edges
from .loops import capped, no_loops, short_basis
from .necks import tighten, walk_class, walk_length
from .radii import circumradii, enclosing_cover, enclosing_radii, local_spacing

__all__ = [
    "GAP_MIN",
    "HOLE_SUPPORTED",
    "LOOP_MIN",
    "LOOP_SUPPORTED",
    "Feature",
    "circumradii",
    "enclosing_cover",
    "enclosing_radii",
    "features",
    "handles_decided",
    "local_spacing",
    "summary_suffix",
    "surface_handles",
    "uncertain",
]

#: Shortest loop (in local spacings) that an eps < 1 sample can resolve: 2 pi (see the module text).
LOOP_MIN = 2 * math.pi
#: Shortest loop (in local spacings) that an eps = 1/2 sample resolves: 2 pi / eps.  A handle whose loop
#: lies between LOOP_MIN and this is resolved only by a sample coarser than eps = 1/2, where the
#: reconstruction theory no longer holds in practice (noise tunnels of the public scans' 0.3 h copies
#: and their other draws measure 6.9-11 radii, the scans' real handles 12.7 and more): uncertain too.
LOOP_SUPPORTED = 4 * math.pi
#: Closest distance (in local spacings) between two components that an eps < 1 sample can resolve.
GAP_MIN = 2.0
#: Smallest span (in local spacings) of a hole that an eps = 1/2 sample resolves: the diameter of a
#: circle of circumference LOOP_SUPPORTED.  A hole's rim is a loop like a handle's, and the same two
#: bounds apply: below LOOP_MIN / pi = 2 no eps < 1 sample shows the hole, below this only a sample
#: coarser than eps = 1/2 does, and a hole in that band is uncertain like a handle in its band.  (A noise
#: draw of the lion at 0.1 h, seed 21, held out of the public copies: a cap the labelling put over a
#: closed part, 19.5 times its ring, opened and mostly refilled, left a hole 3.7 spacings across 57
#: spacings from the scan's real opening, reported as sure.)
HOLE_SUPPORTED = LOOP_SUPPORTED / math.pi


@dataclass(frozen=True)
class Feature:
    """One handle, hole or component of M_S.

    Attributes
    ----------
    kind : {"handle", "hole", "component"}
    location : ndarray of shape (k,)
        A point of the feature in R^k (the middle of a handle's loop, a hole's
        rim, a component's closest approach to another one).
    size_spacings : float
        The loop length (handle), the span of the rim (hole) or the gap to the
        nearest other component (component), in local spacings.
    uncertain : bool
        The sample cannot tell the feature from a gap (size below its bound).
    vertices : ndarray of int
        Sample indices along the loop, rim or closest approach (for drawing).
    reason : str
        One sentence.
    removed : bool
        The extraction removed this feature as below the sample's resolution
        (rule ``cut-handle``; ``join-parts``): it was in M_S before and is
        not in the result; or a possible opening ``open-cap`` kept closed
        (always uncertain: a hole that is not in M_S, at the cap's samples).
        A removed handle stays *uncertain* when its loop was at least
        :data:`LOOP_MIN` (a sample coarser than eps = 1/2 resolves it: the
        sample did not decide it); below LOOP_MIN no eps < 1 sample resolves it.
    disputed : bool
        Where two robust answers of the same sample differ (:mod:`.dispute`): one handle, hole or
        component more or fewer than M_S has there, always uncertain.  It marks a place, not a feature of
        M_S of its own, so counts of M_S's holes and handles leave it out.
    """

    kind: str
    location: np.ndarray
    size_spacings: float
    uncertain: bool
    vertices: np.ndarray
    reason: str
    removed: bool = False
    disputed: bool = False

    def as_dict(self) -> dict:
        """The JSON form (``uncertain_features`` entries)."""
        return {
            "kind": self.kind,
            "location": [float(x) for x in self.location],
            "size_spacings": round(float(self.size_spacings), 3),
            "uncertain": bool(self.uncertain),
            "removed": bool(self.removed),
            "disputed": bool(self.disputed),
            "reason": self.reason,
        }


def features(
    points: np.ndarray,
    simplices: np.ndarray,
    d: int,
    spacing: np.ndarray | None = None,
    *,
    tighten_loops: bool = True,
    handles_only: bool = False,
    b1: int | None = None,
) -> list[Feature]:
    """Every handle, hole and component of a complex, with its support.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    simplices : ndarray of shape (s, d + 1)
        M_S.
    d : int
        Its dimension.  Handles are found for d >= 2 (:func:`.tunnels.tunnels` for d >= 3), holes for
        d >= 2 (:func:`.solidholes.holes_of_solids` for d >= 3), components in every dimension (a curve's
        gaps: :func:`.gaps.curve_gaps`).
    spacing : ndarray of shape (n,), optional
        Local spacing per sample (default: nearest-neighbour distances).
    tighten_loops : bool
        Shorten a handle loop where it comes back near itself, and look for necks
        (:func:`.necks.tighten`).  ``cut-handle`` measures the loops of the basis search as they come
        (its cuts are decided as before); the report, and the robust driver's choice between the
        labelled and the grown result (below 5,000 samples), measure them tightened.
    handles_only : bool
        Only the handles (what ``cut-handle`` looks at): the components, the samples M_S does not
        reach and the holes are not measured.  A surface's handles are the same either way (a d >= 3
        complex's tunnels are measured only with the rest).
    b1 : int, optional
        The complex's first Betti number when the caller knows it (:func:`.topology.analyse`): at 0 a
        d >= 3 complex's classes (:func:`.tunnels.edge_classes`) are not computed.  The result is the same.

    Returns
    -------
    list of Feature
        Components first (with the clusters of samples M_S does not reach,
        :mod:`.missing`), then holes, then handles.
    """
    from .missing import left_out  # it builds on this module's Feature and GAP_MIN

    simplices = np.asarray(simplices, dtype=np.int64).reshape(-1, d + 1)
    n = len(points)
    if len(simplices) == 0:
        return []  # an empty M_S lacks everything, which no feature is (missing.left_out)
    h = local_spacing(points, simplices) if spacing is None else np.asarray(spacing, dtype=float)
    out = [] if handles_only else _components(points, simplices, h) + left_out(points, simplices, d)
    if d == 2:
        edges, tri_edges = triangle_edges(simplices)
        count = np.bincount(tri_edges.ravel(), minlength=len(edges))
        if not handles_only:
            from .surfaceholes import holes_of_surface  # it builds on this module's Feature and bounds

            out += holes_of_surface(points, edges, count, h, simplices)
        if not no_loops(simplices, edges, tri_edges, count, n):
            out += _measured(points, _basis(points, simplices, edges, tri_edges, count, h, n), h, n, tighten_loops)
    elif d >= 3 and not handles_only:
        from .solidholes import holes_of_solids  # they build on this module's Feature and bounds
        from .tunnels import tunnels

        out += holes_of_solids(points, simplices, h) + ([] if b1 == 0 else tunnels(points, simplices, h))
    return out


def _components(points: np.ndarray, simplices: np.ndarray, h: np.ndarray) -> list[Feature]:
    """Components of the complex and their gap to the nearest other one."""
    n = len(points)
    w = simplices.shape[1]
    rows = np.repeat(simplices[:, 0], w - 1)
    cols = simplices[:, 1:].ravel()
    g = coo_matrix((np.ones(len(rows), np.int8), (rows, cols)), shape=(n, n))
    _, label = connected_components(g, directed=False)
    used = np.zeros(n, bool)
    used[simplices.ravel()] = True
    verts = np.nonzero(used)[0]
    comps = np.unique(label[verts])
    result = []
    if len(comps) == 1:
        return result
    tree = cKDTree(points[verts])
    kk = min(len(verts), 16)
    dist, idx = tree.query(points[verts], k=kk)
    other = label[verts[idx]] != label[verts][:, None]
    gap = np.where(other, dist, np.inf).min(axis=1)
    own = np.where(~other & (dist > 0), dist, np.inf).min(axis=1)
    # the unit: the larger of the nearest-neighbour distance and the sampling radius h, so a gap counts
    # as resolved only if it beats both (h is the larger one where the sampling is anisotropic: thin
    # triangles across rings, whose nearest neighbours lie along the dense direction)
    own = np.maximum(np.where(np.isfinite(own), own, h[verts]), h[verts])
    where = np.where(other, idx, -1)
    # each component's closest approach: its first vertex (in vertex order) of least relative gap
    lab_v = label[verts]
    rel_all = gap / own
    order = np.lexsort((rel_all, lab_v))
    starts = np.searchsorted(lab_v[order], comps)
    sizes = np.bincount(np.searchsorted(comps, lab_v), minlength=len(comps))
    for c, start, n_c in zip(comps.tolist(), starts.tolist(), sizes.tolist(), strict=True):
        row = int(order[start])
        size = float(rel_all[row])
        v = int(verts[row])
        if not np.isfinite(size):
            size = float("inf")
            loc = points[verts[lab_v == c]].mean(axis=0)
            pair = np.array([v])
        else:
            u = int(verts[where[row][where[row] >= 0][0]]) if (where[row] >= 0).any() else v
            loc = (points[v] + points[u]) / 2
            pair = np.array([v, u])
        unc = size < GAP_MIN
        reason = (
            f"component of {n_c} samples, {size:.2g} spacings from the next one"
            + (" (closer than the sample can separate)" if unc else "")
            if np.isfinite(size)
            else f"component of {n_c} samples"
        )
        result.append(Feature("component", loc, size, unc, pair, reason))
    return result


def _basis(
    points: np.ndarray,
    tris: np.ndarray,
    edges: np.ndarray,
    tri_edges: np.ndarray,
    count: np.ndarray,
    h: np.ndarray,
    n: int,
) -> tuple[list | int, dict, np.ndarray]:
    """The short homology basis (:func:`.loops.short_basis`) of the capped surface, its cocycles, the capped edges.

    An open surface is first capped: every hole gets a cone over its rim from a vertex of its own, far
    away, so the complex is closed and its loops are exactly the handles (2g of them: a loop around a
    hole bounds the cone, and no handle loop needs to pass a cone's far apex).  Without the caps the
    tree-cotree split, which cuts the boundary edges, loses a handle whenever the shortest-path tree
    leaves out more than one rim edge per hole: a noisy plastic vase came out with b1 = 3 and two holes,
    a handle, and no loop listed.  :func:`_measured` makes one feature per loop.
    """
    pts, tris, edges, tri_edges, count, m = capped(points, tris, edges, tri_edges, count)
    local = np.r_[LOOP_MIN * h, np.zeros(m - n)]
    # local searches reach as far as a loop below the bound can go from its root
    cocycles: dict = {}
    basis = short_basis(pts, tris, edges, tri_edges, count, m, local=local, surface=n, cocycles=cocycles)
    return basis, cocycles, edges


def _measured(
    points: np.ndarray, found: tuple[list | int, dict, np.ndarray], h: np.ndarray, n: int, tighten_loops: bool
) -> list[Feature]:
    """The handle features of a basis (:func:`_basis`), its loops as found or tightened (read only)."""
    basis, cocycles, edges = found
    if isinstance(basis, int):
        return [too_many_loops(points, np.unique(edges[edges < n]), basis)]
    result = []
    classes = [walk_class(loop, cocycles) for loop, _ in basis] if tighten_loops else []
    for k, (loop, length) in enumerate(basis):
        # a loop through a cone's apex is longer than any on the surface, and every class has one there;
        # the search is approximate, and where it found none the handle is not measured on the surface
        if not (loop < n).all():
            on = loop[loop < n]  # an apex's loop neighbours are rim vertices: two at least
            size = walk_length(points, on) / float(np.median(h[on]))
            why = "the loop basis found this handle only through a hole (its cap, not the surface): not measured "
            why += "on M_S, so not supported (the size is that of the loop's part on M_S)"
            result.append(Feature("handle", points[on].mean(axis=0), size, True, on, why))
            continue
        neck = math.inf
        if tighten_loops:
            others = classes[:k] + classes[k + 1 :]
            loop, neck = tighten(points, loop, h, cocycles, GAP_MIN, others=others)
            classes[k] = walk_class(loop, cocycles)  # still a basis: the new loop is outside the others' span
            length = walk_length(points, loop)
        size = length / float(np.median(h[loop]))
        unc = size < LOOP_SUPPORTED or neck < GAP_MIN
        reason = f"loop of {len(loop)} samples, {size:.3g} sampling radii long" + (
            " (fewer samples around it than a sample can resolve: may be a bridge across a gap)"
            if size < LOOP_MIN
            else " (only a sample coarser than eps = 1/2 resolves it: may be a tunnel of noise or a bridge)"
            if size < LOOP_SUPPORTED
            else f", through a neck {neck:.3g} sampling radii across (two of its points far apart along it are "
            "closer than two sheets a sample resolves: may be two parts that touch, joined)"
            if unc
            else ""
        )
        result.append(Feature("handle", points[loop].mean(axis=0), size, unc, loop, reason))
    return result


def surface_handles(points: np.ndarray, triangles: np.ndarray) -> Callable[[bool], list[Feature]]:
    """A surface's handles, ``features(..., tighten_loops=t, handles_only=True)`` for either ``t``, one search.

    ``cut-handle`` measures the loops as the search finds them and, where none is short, tightened
    (:mod:`~crustview.core.robust.cut_handle`): the basis is the same both times (the search does not depend on
    the tightening, which only reads it), so it is searched once.  Returns ``measure(tighten_loops)``.
    """
    simplices = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    n = len(points)
    if len(simplices) == 0:
        return lambda tighten_loops: []
    h = local_spacing(points, simplices)
    edges, tri_edges = triangle_edges(simplices)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    if no_loops(simplices, edges, tri_edges, count, n):
        return lambda tighten_loops: []
    found = _basis(points, simplices, edges, tri_edges, count, h, n)
    return lambda tighten_loops: _measured(points, found, h, n, tighten_loops)


def too_many_loops(points: np.ndarray, used: np.ndarray, count: int) -> Feature:
    """The one feature that stands for a loop basis too large to search (above :data:`.loops.MAX_LOOPS`).

    Placed at the mean of the complex's vertices ``used``, of size 0 and uncertain: none of ``count`` loops is
    measured, so none is supported.
    """
    return Feature(
        "handle",
        points[used].mean(axis=0),
        0.0,
        True,
        np.array([], np.int64),
        f"{count} independent loops: too many handles to list, none of them supported",
    )


def uncertain(feats: list[Feature]) -> list[Feature]:
    """The features the sample does not support."""
    return [f for f in feats if f.uncertain]


def summary_suffix(feats: list[Feature]) -> str:
    """The summary's "(uncertain: N handles, M holes, C components)", or "" when none is uncertain."""
    u = uncertain(feats)
    if not u:
        return ""
    c = {k: sum(f.kind == k for f in u) for k in ("handle", "hole", "component")}
    return f"(uncertain: {c['handle']} handles, {c['hole']} holes, {c['component']} components)"


def handles_decided(kept: list[Feature], b1_kept: int, b1_other: int) -> bool:
    """Whether the sampling bound decides for the kept result over another closed one with another b_1.

    The kept result is decided when it has the larger b_1 and every loop of its
    short basis is at least :data:`LOOP_SUPPORTED` long: an eps = 1/2 sample
    resolves each of its handles, so the other result has spanned tunnels the
    sample shows (the choice :func:`~crustview.core.robust.verdict._tie` makes
    on a tie).  The converse is not claimed: when the kept result has fewer
    handles, the other's extra handles would all have to be below the
    resolution of any eps < 1 sample (loops under :data:`LOOP_MIN`), a bound
    that measured loops straddle (the seahorse's tail in its 0.1 h copy: 6.27
    radii against 2 pi = 6.28), so that case stays a dispute.

    Parameters
    ----------
    kept : list of Feature
        The features of the kept result (:func:`features`); the other
        result's own loops do not decide (see above).
    b1_kept, b1_other : int
        The first Betti numbers of the two.

    Returns
    -------
    bool
        True when the kept result is decided over the other.  A basis
        too large to list (one feature of size 0) counts as unresolved.
    """
    if b1_kept <= b1_other:
        return False
    loops = [f.size_spacings for f in kept if f.kind == "handle"]
    return len(loops) == b1_kept and min(loops) >= LOOP_SUPPORTED
