"""Rule ``join-parts``: two parts of the labelled surface closer than the sample can separate are joined.

The labelling (:mod:`.labelling`) decides each Delaunay cell by its ball.  Where
a part is thinner than the sample spacing -- a thin plate attached to a body
(the elk's antlers), a tentacle's root, a neck sampled a few times around --
the cells across the attachment can take the outside label, and M_S comes out
as two closed pieces that face each other across a slab of outside cells
thinner than the spacing.

Such a gap is below what the sample resolves: two sheets g apart have
LFS <= g / 2 between them, so an eps < 1 sample needs a sampling radius below
g / 2, and two components closer than :data:`~..analysis.features.GAP_MIN` = 2
spacings are exactly the ones the features analysis calls uncertain
(:mod:`crustview.core.analysis.features`).  The rule undoes the separation
where the labelling allows it: for each such component, smallest first, the
outside cells all of whose vertices are *contact samples* (samples whose
nearest sample on another component is closer than GAP_MIN of their own
spacings) and that have vertices on both sides take the inside label;
``repair-vertex`` and ``sculpt-sample`` run on the cells touched
(:class:`.cut_handle._Local`).  The contact is taken first in the nearest-
neighbour unit (the narrowest slab), then in the features' own unit, the
larger of that and the sampling radius (a slab across long thin triangles).
Where neither set joins a piece closer than GAP_MIN sampling radii (noise can
leave a contact of a few samples whose cells touch neither piece's inside), a
third trial takes the least confident chain of outside cells across the gap
(:func:`_chain`).  A trial is kept when

* every vertex touched is a manifold vertex, and every sample that was a
  vertex still is one;
* M_S has fewer components, and no more handles than before.  Joining along a
  long contact can leave a short tunnel between two joins; ``cut-handle``
  (:mod:`.cut_handle`) then runs on the result, and the trial is kept only if
  the handles are back to the count before.

A join decides what the sample does not: two touching objects (the foot bones
at their joints) look the same as a thin attachment.  Every join is therefore
reported as an *uncertain* component, marked ``removed`` (the separation the
labelling had), with the gap it closed; a result is never silently joined.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components, dijkstra
from scipy.spatial import cKDTree

from ..analysis.features import GAP_MIN, Feature, local_spacing
from ..errors import check_cancel
from .cut_handle import LOCAL_ROUNDS, Cut, _euler, _Local, _was_on, cut_handles
from .drop_stray import STRAY_MAX, STRAY_SHARE
from .label_repair import LabelEditor

#: Nearest samples looked at for a sample's closest approach to another component (as the features'
#: component gaps: a sample's 16 nearest include its own ring and, at a contact, the other side).
NEIGHBOURS = 16
#: The two units of a contact (:class:`_Contacts`), and the name of the third trial, the chain.
NEAREST, SAMPLING_RADIUS, CHAIN = "the nearest-neighbour distance", "the sampling radius", "chain"


@dataclass
class Join:
    """One join: the feature it removed, the cells that took the inside label, the faces changed."""

    feature: Feature
    cells: np.ndarray
    removed: np.ndarray
    added: np.ndarray
    cost: float
    unit: str
    cuts: list[Cut] = field(default_factory=list)
    #: "contact" (the contact cells) or "chain" (the least-confident chain of cells across the gap)
    how: str = "contact"


@dataclass
class JoinParts:
    """What the rule did."""

    joins: list[Join] = field(default_factory=list)

    @property
    def removed(self) -> list[Feature]:
        """The separations that were removed (each an uncertain component)."""
        return [j.feature for j in self.joins]


def _vertex_components(faces: np.ndarray, n: int) -> np.ndarray:
    """Each sample's component of the triangle set, -1 for samples in no face."""
    rows = np.r_[faces[:, 0], faces[:, 1]]
    cols = np.r_[faces[:, 1], faces[:, 2]]
    _, label = connected_components(
        coo_matrix((np.ones(len(rows), np.int8), (rows, cols)), shape=(n, n)), directed=False
    )
    on = np.zeros(n, bool)
    on[faces.ravel()] = True
    return np.where(on, label, -1)


def _b1(faces: np.ndarray, comp: np.ndarray, n: int) -> int:
    """First Betti number of a closed surface: 2 b0 - chi."""
    return 2 * len(np.unique(comp[comp >= 0])) - _euler(faces, n)


class _Contacts:
    """The closest approach of every vertex of M_S to another component, in two units."""

    def __init__(self, points: np.ndarray, faces: np.ndarray, comp: np.ndarray, last: _Contacts | None = None) -> None:
        verts = np.flatnonzero(comp >= 0)
        h = local_spacing(points, faces)
        if last is not None and np.array_equal(last.verts, verts):
            dist, idx = last.near  # the same vertices as the round before: the same neighbours
        else:
            k = min(len(verts), NEIGHBOURS)
            dist, idx = cKDTree(points[verts]).query(points[verts], k=k)
        self.near = (dist, idx)
        other = comp[verts[idx]] != comp[verts][:, None]
        gap = np.where(other, dist, np.inf).min(axis=1)
        own = np.where(~other & (dist > 0), dist, np.inf).min(axis=1)
        nn = np.where(np.isfinite(own), own, h[verts])
        self.n = len(points)
        self.verts = verts
        self.h = h
        self.units = {NEAREST: gap / nn, SAMPLING_RADIUS: gap / np.maximum(nn, h[verts])}
        # the nearest sample of another component (the first such neighbour), or -1
        first = np.argmax(other, axis=1)
        self.partner = np.where(other.any(axis=1), verts[idx[np.arange(len(verts)), first]], -1).astype(np.int64)

    def mask(self, unit: str) -> np.ndarray:
        """Samples closer to another component than GAP_MIN of their spacings in this unit."""
        out = np.zeros(self.n, bool)
        out[self.verts[self.units[unit] < GAP_MIN]] = True
        return out

    def closest(self, members: np.ndarray, unit: str) -> tuple[float, int, int]:
        """The component's closest approach: (gap in the unit, its sample, the other side's sample)."""
        mine = np.isin(self.verts, members)
        rel = np.where(mine, self.units[unit], np.inf)
        i = int(np.argmin(rel))
        return float(rel[i]), int(self.verts[i]), int(self.partner[i])


def join_parts(ed: LabelEditor, points: np.ndarray, cancel: object | None = None) -> JoinParts:
    """Apply ``join-parts`` to the labelling in ``ed`` (changed in place).

    Parameters
    ----------
    ed : LabelEditor
        The labelling after ``cut-handle``.
    points : ndarray of shape (n, 3)
        The samples.

    Returns
    -------
    JoinParts
        The joins, in order, each with the faces M_S lost and gained and the
        ``cut-handle`` cuts that followed it.
    """
    lab = ed.lab
    n = lab.n
    out = JoinParts()
    local = _Local(ed)
    simp = lab.simplices
    real = (simp < n).all(axis=1)
    corner = np.where(simp < n, simp, 0)
    tree = None  # a k-d tree of the samples, made when a chain is first looked for
    contacts = None  # the round before's contacts (their neighbour lists are reused while M_S has the same vertices)
    while True:
        check_cancel(cancel)
        surf = lab.faces[ed.cut]
        if len(surf) == 0:
            break
        comp = _vertex_components(surf, n)
        ids, counts = np.unique(comp[comp >= 0], return_counts=True)
        if len(ids) < 2:
            break
        # the pieces to join: every one but the largest, and not a stray (drop-stray removes those later
        # and insert-sample puts their samples on the rest: a bubble in the noise layer, not a part)
        n_faces = np.bincount(comp[surf[:, 0]], minlength=n)
        largest = int(n_faces.max())
        pieces = [
            int(c)
            for c in ids[np.argsort(counts, kind="stable")][:-1]
            if n_faces[c] >= STRAY_MAX or n_faces[c] >= STRAY_SHARE * largest
        ]
        if not pieces:
            break
        contacts = _Contacts(points, surf, comp, contacts)
        b1 = _b1(surf, comp, n)
        # per unit, the undecided real cells all of whose vertices are contact samples (the same for every
        # piece: each piece's own are those among them with a vertex on it and one on another component)
        open_cells = real & ~lab.inside & ~lab.outside
        at_contact = {
            unit: np.flatnonzero(open_cells & contacts.mask(unit)[corner].all(axis=1)) for unit in contacts.units
        }
        join = None
        for cid in pieces:
            for unit in (*contacts.units, CHAIN):
                check_cancel(cancel)
                how = "contact"
                if unit == CHAIN:
                    # the contact cells did not join it: the least confident chain of cells across the gap
                    how, unit = "chain", SAMPLING_RADIUS
                    gap, v, u = contacts.closest(np.flatnonzero(comp == cid), unit)
                    sel = np.zeros(0, np.int64)
                    if gap < GAP_MIN and u >= 0:
                        tree = cKDTree(points) if tree is None else tree
                        sel = _chain(ed, comp, cid, v, u, contacts.h, points, tree)
                else:
                    cells = at_contact[unit]
                    owner = comp[corner[cells]]
                    mine = owner == cid
                    sel = cells[mine.any(axis=1) & ((owner >= 0) & ~mine).any(axis=1)]
                if len(sel) == 0:
                    continue
                join = _trial(ed, local, sel, comp, len(ids), b1, points, cancel)
                if join is not None:
                    gap, v, u = contacts.closest(np.flatnonzero(comp == cid), unit)
                    size = int((comp == cid).sum())
                    join.unit, join.how = unit, how
                    join.feature = Feature(
                        "component",
                        (points[v] + points[u]) / 2 if u >= 0 else points[v],
                        gap,
                        True,
                        np.array([v, u] if u >= 0 else [v]),
                        f"a part of {size} samples, {gap:.2g} spacings ({unit}) from the next one, joined to it: "
                        "closer than the sample can separate, so one object or two that touch",
                        removed=True,
                    )
                    break
            if join is not None:
                break
        if join is None:
            break
        out.joins.append(join)
    return out


def _chain(
    ed: LabelEditor, comp: np.ndarray, cid: int, v: int, u: int, h: np.ndarray, points: np.ndarray, tree: cKDTree
) -> np.ndarray:
    """The least confident chain of outside cells from piece ``cid``'s inside to the other piece's, at a contact.

    The contact is the closest approach, sample ``v`` of the piece and ``u``
    of the other, less than GAP_MIN sampling radii apart.  The chain runs
    through the cells of the contact's neighbourhood: the stars of ``v`` and
    ``u``, and the cells whose vertices all lie within GAP_MIN sampling radii
    (the larger of the two samples') of ``v`` or of ``u``, two balls that
    overlap since the gap is shorter than their radius.  It starts at an
    inside cell with a vertex on the piece, ends at one with a vertex on the
    other piece, and crosses only outside cells (never a cell with a bounding
    vertex); each one crossed costs one plus its labelling confidence, so the
    chain is the shortest one and, of those, the least confident.  Empty when
    the neighbourhood holds none.  Only the stars of the samples near the
    contact are read (``tree`` is a k-d tree of ``points``).
    """
    lab = ed.lab
    n = lab.n
    radius = GAP_MIN * max(float(h[v]), float(h[u]))
    near = np.unique(np.concatenate([np.asarray(tree.query_ball_point(points[s], radius), np.int64) for s in (v, u)]))
    close = np.zeros(n, bool)
    close[near] = True
    # every cell of the neighbourhood has a vertex near the contact (v and u are), so it is in their stars
    cand = np.unique(np.concatenate([ed.star(int(s)) for s in near]))
    simp = lab.simplices[cand]
    real = (simp < n).all(axis=1)
    star = (simp == v).any(axis=1) | (simp == u).any(axis=1)
    keep_cell = real & (star | close[np.where(simp < n, simp, 0)].all(axis=1))
    region = cand[keep_cell]
    if len(region) == 0:
        return np.zeros(0, np.int64)
    corner = comp[simp[keep_cell]]
    inside = lab.inside[region]
    source = inside & (corner == cid).any(axis=1)
    target = inside & ((corner >= 0) & (corner != cid)).any(axis=1) & ~source
    through = ~inside & ~lab.outside[region]
    if not source.any() or not target.any():
        return np.zeros(0, np.int64)
    # the shared faces between two cells of the region, in face order
    faces = ed.faces_of(region)
    a = np.searchsorted(region, lab.a[faces])
    b = np.searchsorted(region, lab.b[faces])
    k = len(region)
    inner = (a < k) & (b < k)
    inner[inner] = (region[a[inner]] == lab.a[faces[inner]]) & (region[b[inner]] == lab.b[faces[inner]])
    a, b = a[inner], b[inner]
    # entering a cell costs one plus its confidence; the inside ends cost (almost) nothing
    cost = np.where(through, 1.0 + lab.confidence[region], np.where(source | target, 1e-9, np.inf))
    usable = np.isfinite(cost)
    edges = usable[a] & usable[b]
    a, b = a[edges], b[edges]
    rows = np.r_[a, b, np.full(int(source.sum()), k)]
    cols = np.r_[b, a, np.flatnonzero(source)]
    weights = np.r_[cost[b], cost[a], np.full(int(source.sum()), 1e-9)]
    graph = coo_matrix((weights, (rows, cols)), shape=(k + 1, k + 1)).tocsr()
    dist, pred = dijkstra(graph, directed=True, indices=k, return_predecessors=True)
    ends = np.flatnonzero(target & np.isfinite(dist[:k]))
    if len(ends) == 0:
        return np.zeros(0, np.int64)
    node = int(ends[np.argmin(dist[ends])])
    path = []
    while node != k and node >= 0:
        path.append(node)
        node = int(pred[node])
    cells = region[np.array(path, np.int64)]
    return np.sort(cells[~lab.inside[cells]])


def _trial(
    ed: LabelEditor,
    local: _Local,
    sel: np.ndarray,
    comp: np.ndarray,
    b0: int,
    b1: int,
    points: np.ndarray,
    cancel: object | None = None,
) -> Join | None:
    """Give ``sel`` the inside label, repair around it and judge; the join, or None (labels restored)."""
    lab = ed.lab
    n = lab.n
    inside0 = lab.inside.copy()
    cut0 = ed.cut.copy()
    flipped = [sel]
    ed.flip(sel)
    vs = {int(u) for u in np.unique(lab.simplices[sel]).tolist() if u < n}
    ok = True
    for _ in range(LOCAL_ROUNDS):
        if not local.repair(vs, flipped):
            ok = False
            break
        more = local.sculpt(vs, flipped)
        if not more:
            break
        vs |= more
    if ok:
        allc = np.unique(np.concatenate(flipped))
        touched = np.unique(lab.simplices[allc])
        rv = touched[touched < n].tolist()
        ok = all(local.on_surface(v) for v in rv if _was_on(ed, inside0, v))
        ok = ok and all(local.pieces(v)[1].max(initial=-1) + 1 <= 2 for v in rv)
    if ok:
        surf = lab.faces[ed.cut]
        now = _vertex_components(surf, n)
        ok = len(np.unique(now[now >= 0])) < b0 and bool(((comp >= 0) <= (now >= 0)).all())
    cuts: list[Cut] = []
    if ok:
        changed = np.flatnonzero(cut0 != ed.cut)
        removed, added = changed[cut0[changed]], changed[ed.cut[changed]]
        if _b1(surf, now, n) > b1:
            # a long contact joined in two places leaves a tunnel between them: cut-handle's to judge
            cuts = cut_handles(ed, points, cancel).cuts
            surf = lab.faces[ed.cut]
            after = _vertex_components(surf, n)
            ok = (
                _b1(surf, after, n) <= b1
                and len(np.unique(after[after >= 0])) < b0
                and bool(((comp >= 0) <= (after >= 0)).all())
            )
    if not ok:
        lab.inside[:] = inside0
        ed.cut[:] = cut0
        return None
    allc = np.unique(np.concatenate(flipped))
    placeholder = Feature("component", np.zeros(points.shape[1]), 0.0, True, np.zeros(0, np.int64), "", True)
    return Join(placeholder, allc, removed, added, float(lab.confidence[allc].sum()), "", cuts)
