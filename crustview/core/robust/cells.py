"""The labelling path of the robust extension: Delaunay cells inside or outside, then local repairs.

For a surface in R^3 (more generally a hypersurface, codimension 1) the robust
extension first labels every Delaunay cell (rule ``label-cells``,
:mod:`.labelling`) and takes the faces between the two labels as M_S: closed
by construction, in one step.  Then, each a step of the log:

1. ``repair-vertex`` and ``sculpt-sample`` (:mod:`.label_repair`) make it a
   manifold through every sample it can reach by flipping cells;
2. ``open-cap``: a face larger than :data:`~.grow.SIZE_MAX` (circumradius
   over the local spacing; 99 % of the true triangles of the public scans are
   below 2.2, see :mod:`.grow`) spans a gap no sample supports.  A patch of
   at least :data:`OPEN_MIN_FACES` adjacent ones, more than :data:`CAP_RATIO`
   times larger than the faces around it, is the cap the labelling
   puts over the opening of an open scan: it is removed, and the opening is
   never closed again by ``fill-hole``, if the sample is an open scan's
   (some cap over :data:`CAP_SURE`); where none is, caps up to CAP_SURE stay
   closed as uncertain holes (:func:`kept_caps`).  A patch between two rims the sample shows is a wall,
   not a cap over one opening (:mod:`.walls`): it stays closed, named, whatever its ratio, and two caps
   kept closed that face each other through the solid name a possible tunnel
   (:func:`~.cap_holes.facing_caps`).  Smaller patches (where
   noise or one missing sample leaves a few large faces on a closed object)
   stay, and so do patches whose faces are at most :data:`CAP_TYPICAL` times
   the median face of M_S (sampled as densely as the surface in general,
   large only beside an oversampled ring);
3. the last phase shared with the growing path (:meth:`.patcher.Patcher.settle`):
   holes that are undersampling gaps are closed again (``fill-hole``), real
   openings stay open, left-out samples are inserted (``insert-sample``),
   stray pieces dropped (``drop-stray``).

The driver (:mod:`.driver`) runs this path before the growing one and keeps
whichever result the sample supports better.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..analysis.features import enclosing_radii
from ..analysis.topology import is_closed_manifold
from ..errors import check_cancel
from ..steps import RULE_JOIN, RULE_LABEL, RULE_OPEN, RULE_REPAIR, RULE_SCULPT, Extraction
from ..util.nearest import nearest_distances
from .cap_holes import closed_openings, facing_caps, kept_caps
from .cut_handle import CutHandles, cut_handles, log_cut
from .grow import SIZE_MAX, size_ratio
from .join_parts import JoinParts, join_parts
from .label_repair import LabelEditor
from .labelling import Labelling, oriented
from .patcher import Patcher
from .steplog import StepLog
from .walls import is_wall, kept_walls

#: Fewest adjacent faces larger than SIZE_MAX that make an opening.  One missing sample leaves a
#: hole that deg - 2 faces cover, about 4 (the mean vertex degree of a closed surface is 6, by
#: Euler's formula); a patch of twice that is not one missing sample.  The public scans' noisy
#: copies have patches of at most 4 such faces, their openings 15-322 (``benchmarks/bench_scans.py``).
OPEN_MIN_FACES = 8
#: How much larger than the surface around it a patch of big faces must be to be a cap over an opening:
#: its largest enclosing radius over the median enclosing radius of the faces that share a vertex with it.
#: The sampling radius of an eps-sample changes slowly (LFS is 1-Lipschitz): at two points one sampling
#: radius apart it differs by at most (1 + eps) / (1 - eps), 3 at eps = 1/2.  A patch within that of its
#: surroundings is a sparsely sampled part (thin ears and fins sampled in long thin triangles), not an
#: opening.  On the public open scans the openings' patches are 3.9-58 times their ring, the sparse parts'
#: 1.07-2.3 (``benchmarks/bench_scans.py`` reruns the files).
CAP_RATIO = 3.0
#: A cap at most this many times larger than its ring is not decided by the sample: twice CAP_RATIO, as
#: the handles' LOOP_SUPPORTED is twice LOOP_MIN.  Beside a cap over it (an open scan) such a cap is
#: removed and its hole uncertain (:func:`weak_openings`); where no cap is over it, it stays closed as an
#: uncertain hole (:func:`kept_caps`).  Scanner noise
#: makes caps the bound lets through.  Over the public scans, their noisy copies and three more draws at
#: 0.3 h (``benchmarks/bench_caps.py --seeds 11,12,13``), the caps over closed parts of single objects
#: measure 3.0-5.4 (one more, 14.7, on the elk, whose result is open and flagged anyway; the CAD gears
#: have up to 9.3), the true openings 7.2-60, except the plastic vase's small real holes, 3.1-5.5.
CAP_SURE = 2 * CAP_RATIO
#: How much larger than the faces of M_S in general a cap's largest face must be to span a gap of the sample:
#: its largest enclosing radius over the median enclosing radius of all faces of M_S.  One missing sample of an
#: even sample leaves a hole whose faces are sqrt(3) times the others (a hexagon of circumradius s, fanned from
#: one corner: enclosing radius s against s / sqrt(3) for the lattice's own triangles), so a patch no larger is
#: sampled as densely as the surface is in general.  It stands out against its ring only because the ring is
#: oversampled (a lathe mesh's rings near its axis, all with as many vertices as the widest; a tentacle tip):
#: CAP_RATIO's Lipschitz argument bounds how fast the sampling radius may grow, not how dense a sample may be.
#: Such a patch is no cap.  ``benchmarks/bench_caps.py --lathes`` lists both ratios: on the public scans and
#: their noisy copies the 28 true openings measure 2.99-69.8 here, 14 of the 94 false caps at most sqrt(3); on
#: ``bench_shapes.py``'s noisy lathe meshes 77 of the 85 false caps (51 of them 0.53-1.1).
CAP_TYPICAL = math.sqrt(3)


def cap_patches(faces: np.ndarray, big: np.ndarray, n: int) -> list[np.ndarray]:
    """Edge-connected patches of at least :data:`OPEN_MIN_FACES` big faces (indices into ``faces``)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    ids = np.flatnonzero(big)
    if len(ids) < OPEN_MIN_FACES:
        return []
    bf = faces[ids]
    d = faces.shape[1]
    ridge = np.sort(np.concatenate([np.delete(bf, j, axis=1) for j in range(d)]), axis=1)
    key = np.zeros(len(ridge), np.int64)
    for c in range(ridge.shape[1]):
        key = key * np.int64(n) + ridge[:, c]
    owner = np.tile(np.arange(len(bf)), d)
    o = np.argsort(key, kind="stable")
    same = np.flatnonzero(key[o][1:] == key[o][:-1])
    g = coo_matrix((np.ones(len(same)), (owner[o[same]], owner[o[same + 1]])), shape=(len(bf), len(bf)))
    _, label = connected_components(g, directed=False)
    sizes = np.bincount(label)
    return [ids[label == c] for c in np.flatnonzero(sizes >= OPEN_MIN_FACES)]


def cap_ratios(
    faces: np.ndarray, patches: list[np.ndarray], points: np.ndarray, radii: np.ndarray | None = None
) -> list[float]:
    """Per patch: its largest enclosing radius over the median one of the faces sharing a vertex with it.

    ``inf`` for a patch with no such face around it.  ``radii``: the faces' enclosing radii, if known;
    otherwise those of the faces near the patches only are computed (the same values, to rounding: a
    degenerate face in a batch sends ``circumradii`` to a pseudo-inverse for the whole batch).  The rings are
    sought among the faces near the patches only: an i.i.d. sample's closed surface has hundreds of small
    patches of big faces (232 on a 300,000-sample torus), and a pass over every face per patch took 2.5 s.
    """
    if not patches:
        return []
    near = np.flatnonzero(np.isin(faces, np.unique(np.concatenate([faces[p].ravel() for p in patches]))).any(axis=1))
    local = faces[near]
    r = enclosing_radii(points, local) if radii is None else radii[near]
    where = np.full(len(faces), -1, np.int64)
    where[near] = np.arange(len(near))
    out = []
    for p in patches:
        inside = np.zeros(len(near), bool)
        inside[where[p]] = True
        ring = np.isin(local, np.unique(faces[p])).any(axis=1) & ~inside
        out.append(float(r[inside].max()) / float(np.median(r[ring])) if ring.any() else math.inf)
    return out


def typical_ratios(faces: np.ndarray, patches: list[np.ndarray], radii: np.ndarray) -> list[float]:
    """Per patch: its largest enclosing radius over the median one of all ``faces`` (see :data:`CAP_TYPICAL`)."""
    typical = float(np.median(radii)) if len(radii) else 0.0
    return [float(radii[p].max()) / typical if typical > 0 else math.inf for p in patches]


def caps(faces: np.ndarray, patches: list[np.ndarray], points: np.ndarray) -> list[np.ndarray]:
    """The patches whose faces are more than :data:`CAP_RATIO` times larger than the faces around them."""
    return [p for p, q in zip(patches, cap_ratios(faces, patches, points), strict=True) if q > CAP_RATIO]


def extract_by_labels(
    points: np.ndarray,
    delaunay_points: np.ndarray,
    simplices: np.ndarray,
    centres: np.ndarray,
    faces: np.ndarray,
    candidates: np.ndarray,
    spacing: float,
    progress: Callable[[float], None] | None = None,
    cancel: object | None = None,
) -> Extraction:
    """M_S from a labelling of the Delaunay cells, with its repairs recorded as steps.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    delaunay_points : ndarray of shape (n + b, k)
        Samples and far bounding points.
    simplices : ndarray of shape (m, k + 1)
        Delaunay k-simplices.
    centres : ndarray of shape (m, k)
        Their circumcentres.
    faces : ndarray of shape (f, k)
        Every Delaunay (k-1)-face among the samples, sorted rows (for hole filling).
    candidates : ndarray of shape (t, k)
        T_S, sorted rows (the first rows of the result, as in paper mode).
    spacing : float
        Median nearest-neighbour distance.
    progress : callable(fraction), optional
        Called between the rules, with fractions of the whole path.
    cancel : object with ``is_set()``, optional
        Checked between the rules and within the long ones (``cut-handle``, ``join-parts``): when set,
        :class:`~crustview.core.errors.Cancelled` is raised.

    Returns
    -------
    Extraction
        ``mode = "robust"``; ``labelling`` holds the :class:`~.labelling.Labelling`.
    """
    lab = Labelling(points, delaunay_points, simplices, centres)
    inside0 = lab.inside.copy()
    told = progress or (lambda f: None)

    def report(fraction: float) -> None:
        told(fraction)
        check_cancel(cancel)

    ext = _labelled(points, delaunay_points, lab, faces, candidates, spacing, report, frozenset(), cancel)
    # samples left out where sculpt-sample's size bound held some back (which changes what the later rules do,
    # not only for those): run again with the held ones sculpted through their least confident cell, as before
    # the bound (every sample a vertex comes first)
    free = frozenset(ext.sculpt_held) if ext.left_samples else frozenset()  # type: ignore[attr-defined]
    if free:
        lab.inside[:] = inside0
        ext = _labelled(points, delaunay_points, lab, faces, candidates, spacing, report, free, cancel)
    return ext


def _labelled(
    points: np.ndarray,
    delaunay_points: np.ndarray,
    lab: Labelling,
    faces: np.ndarray,
    candidates: np.ndarray,
    spacing: float,
    report: Callable[[float], None],
    free: frozenset,
    cancel: object | None = None,
) -> Extraction:
    """One run of the labelled path on ``lab`` (its labels as the labelling left them); see :func:`extract_by_labels`.

    ``free``: samples ``sculpt-sample`` brings onto M_S without its size bound.
    """
    n = len(points)
    log = StepLog(candidates, n)
    surf, _ = lab.surface()
    n_in = int(lab.inside.sum())
    log.step(
        RULE_LABEL,
        tuple(surf[0].tolist()) if len(surf) else (),
        surf,
        np.zeros((0, surf.shape[1]), np.int64),
        math.nan,
        f"labelled the {lab.m} Delaunay cells inside ({n_in}) or outside ({lab.m - n_in}) by their balls "
        f"(deep overlap: same side; shallow touch and a sample's two poles: opposite sides; big balls first); "
        f"M_S is the {len(surf)} faces between the two ({lab.violated} ties could not be kept)",
    )
    report(0.4)
    ed = LabelEditor(lab)
    # the vertex test of repair-vertex costs a pass over every cell corner: only when something pinches
    pinched = not is_closed_manifold(surf, surf.shape[1] - 1)
    repairs = [((int(v),), c, rem, add) for v, c, rem, add in ed.repair()] if pinched else []
    # in R^k, k >= 4, M_S can also pinch where every star has one piece of each label (LabelEditor.repair_ridges)
    for tau, cells, removed, added in repairs + (ed.repair_ridges(cancel) if pinched and points.shape[1] >= 4 else []):
        log.step(
            RULE_REPAIR,
            tau,
            lab.faces[added],
            lab.faces[removed],
            math.nan,
            f"M_S pinched at {f'sample {tau[0]}' if len(tau) == 1 else f'the ridge {tau}'}; {len(cells)} less "
            f"confident cells around it took the other label (confidence {float(lab.confidence[cells].max()):.2f} "
            "or less)",
        )
    report(0.6)
    for v, _cells, removed, added in ed.sculpt(free):
        log.step(
            RULE_SCULPT,
            (int(v),),
            lab.faces[added],
            lab.faces[removed],
            math.nan,
            f"sample {v} was no vertex: the cell of its star with its opposite face on M_S took the other "
            "label, so M_S runs through the sample (Boissonnat's sculpting)",
        )
    report(0.65)
    # cut-handle, join-parts and open-cap measure a surface's loops, parts and caps: in R^3 only (a surface in a
    # 3-flat of R^k is here in the flat's coordinates, reconstruct.reextract).  A hypersurface in R^k, k >= 4 (a
    # 3-manifold in R^4), is labelled, repaired and sculpted as above and settled below; its holes and handles
    # are measured by the report (see module docstring)
    surface = points.shape[1] == 3
    handles = cut_handles(ed, points, cancel) if surface else CutHandles()
    for c in handles.cuts:
        log_cut(log, lab.faces, c)
    joined = join_parts(ed, points, cancel) if surface else JoinParts()
    for j in joined.joins:
        log.step(
            RULE_JOIN,
            tuple(int(v) for v in j.feature.vertices.tolist()),
            lab.faces[j.added],
            lab.faces[j.removed],
            math.nan,
            f"{j.feature.reason}; "
            + (
                f"{len(j.cells)} outside cells between the two (all their vertices that close, in units of {j.unit})"
                if j.how == "contact"
                else f"a chain of {len(j.cells)} outside cells across the gap (the least confident from one piece's "
                "inside to the other's; the contact cells alone did not join them)"
            )
            + f" took the inside label (labelling confidence {j.cost:.2f} in all)",
        )
        for c in j.cuts:
            log_cut(log, lab.faces, c)
    # a join changes the loops around it (the elk at 0.1 h, draw 50: a handle's loop 7.1 radii before its
    # part was joined, 4.7 after): cut-handle judges the joined surface again
    after = cut_handles(ed, points, cancel) if joined.joins else CutHandles()
    for c in after.cuts:
        log_cut(log, lab.faces, c)
    # the rest edits M_S face by face
    cut = ed.cut
    inner = np.where(lab.inside[lab.a[cut]], lab.a[cut], lab.b[cut])
    now = lab.faces[cut]
    orient = oriented(now, inner, lab.simplices, delaunay_points)
    pt = Patcher(points, list(map(tuple, now.tolist())), faces, spacing, orient=orient.tolist(), orientable=True)
    examined = cap_patches(now, size_ratio(points, now) > SIZE_MAX, n) if surface else []
    radii = enclosing_radii(points, now) if examined else np.zeros(0)
    ratios = cap_ratios(now, examined, points, radii)
    typical = typical_ratios(now, examined, radii)
    # a patch no larger than the faces of M_S in general is sampled as densely as the rest: no cap
    dense = [(q, t) for q, t in zip(ratios, typical, strict=True) if q > CAP_RATIO and t <= CAP_TYPICAL]
    # every patch over CAP_RATIO with both ratios, for benchmarks/bench_caps.py
    over = [(np.unique(now[p]), q, t) for p, q, t in zip(examined, ratios, typical, strict=True) if q > CAP_RATIO]
    ratios = [q if t > CAP_TYPICAL else min(q, CAP_RATIO) for q, t in zip(ratios, typical, strict=True)]
    # a cap over CAP_SURE times its ring is an opening: the sample is an open scan's, and every cap over
    # CAP_RATIO is removed (those under CAP_SURE become uncertain holes, weak_openings).  Where no cap is
    # over CAP_SURE the sample shows no opening beyond doubt: a cap between CAP_RATIO and CAP_SURE stays
    # closed, the theory's answer, and is reported as an uncertain hole (kept_caps)
    band = [(p, np.unique(now[p]), q) for p, q in zip(examined, ratios, strict=True) if q > CAP_RATIO]
    # a patch between two rims the sample shows is a wall, not a cap over one opening (walls.py): it stays, named
    nn = nearest_distances(points) if band else np.zeros(0)
    wall = [is_wall(now, p, points, nn) for p, _, _ in band]
    walls = [b for b, w in zip(band, wall, strict=True) if w]
    band = [b for b, w in zip(band, wall, strict=True) if not w]
    open_scan = any(q > CAP_SURE for _, _, q in band)
    patches = [p for p, _, _ in band] if open_scan else []
    opened = [(vs, q) for _, vs, q in band] if open_scan else []
    undecided = [] if open_scan else [(vs, q) for _, vs, q in band]
    for patch, (_, ratio) in zip(patches, opened, strict=True):
        for i in patch.tolist():
            pt._delete(i)
        pt.log.append(
            (
                RULE_OPEN,
                pt.simp[int(patch[0])],
                (),
                tuple(patch.tolist()),
                math.nan,
                f"removed a patch of {len(patch)} adjacent faces larger than {SIZE_MAX:g} local spacings, "
                f"{ratio:.2g} times the faces around it: no sample supports it (the cap over an open scan's "
                "opening); the opening stays open",
            )
        )
        pt.suspects.update(int(v) for i in patch.tolist() for v in pt.simp[i])
    if patches:
        # the openings stay open: fill-hole would span them again with smaller faces
        pt.keep_open = frozenset(pt.boundary())
    start = len(log.steps)
    report(0.75)
    left = pt.settle()
    report(0.95)
    for rule, tau, added, removed, angle, why in pt.log:
        log.step(
            rule,
            tau,
            np.array([pt.simp[i] for i in added], np.int64).reshape(-1, now.shape[1]),
            np.array([pt.simp[i] for i in removed], np.int64).reshape(-1, now.shape[1]),
            angle,
            why,
        )
    bnd = len(pt.boundary())
    alive = log.faces()
    stopped = "empty" if len(alive) == 0 else ("closed" if bnd == 0 else "open")
    notes = []
    if left:
        shown = ", ".join(str(x) for x in left[:10]) + (" ..." if len(left) > 10 else "")
        notes.append(f"{len(left)} samples are farther than the insertion limit from M_S and were left out: {shown}")
    if dense:
        notes.append(
            f"open-cap passed over {len(dense)} "
            + ("patches" if len(dense) > 1 else "patch")
            + f" of big faces more than {CAP_RATIO:g} times the size of the faces around "
            + ("them" if len(dense) > 1 else "it")
            + f" but at most {CAP_TYPICAL:.3g} times the median face of M_S ("
            + ", ".join(f"{q:.2g} and {t:.2g}" for q, t in dense[:5])
            + (" ..." if len(dense) > 5 else "")
            + "): sampled as densely as the surface in general, beside an oversampled ring; not openings"
        )
    ext = log.extraction(stopped, notes)
    ext.labelling = lab  # type: ignore[attr-defined]
    ext.sculpt_held = sorted(ed.held)  # type: ignore[attr-defined]
    ext.left_samples = list(left)  # type: ignore[attr-defined]
    closed_caps = kept_caps(points, undecided)
    # an opening open-cap made that settle closed again (fill-hole zips a slit: a thin part's rim whose two
    # sides the labelling kept apart looks the same as a narrow opening) is closed with no sample on it
    rim = {v for f in pt.boundary() for v in f}
    ext.reclosed = [(vs, q) for vs, q in opened if not rim.intersection(vs.tolist())]  # type: ignore[attr-defined]
    reclosed = closed_openings(
        points,
        ext.reclosed,  # type: ignore[attr-defined]
        rim,
        how="closed again by fill-hole (a slit: the rim of a thin part sampled on both sides looks the same)",
        sure_only=False,
    )
    if walls:
        ext.notes.append(
            f"open-cap kept {len(walls)} "
            + ("walls" if len(walls) > 1 else "wall")
            + " closed: "
            + ("patches" if len(walls) > 1 else "a patch")
            + " of big faces ("
            + ", ".join(f"{q:.2g}" for _, _, q in walls[:5])
            + (" ..." if len(walls) > 5 else "")
            + " times the faces around "
            + ("them" if len(walls) > 1 else "it")
            + ") between two rims or more that the sample shows, not over one opening: a side no sample lies on, "
            "or openings; each is an uncertain hole (and an uncertain component where it holds two parts together)"
        )
    if closed_caps:
        ext.notes.append(
            f"open-cap kept {len(closed_caps)} "
            + ("caps" if len(closed_caps) > 1 else "cap")
            + f" closed whose faces are {CAP_RATIO:g}-{CAP_SURE:g} times the faces around them (ratios "
            + ", ".join(f"{q:.2g}" for _, q in undecided[:5])
            + (" ..." if len(undecided) > 5 else "")
            + "): the sample does not tell noise from a small opening there; each is an uncertain hole"
        )
    ext.removed_features = (
        handles.removed
        + [c.feature for j in joined.joins for c in j.cuts]
        + after.removed
        + joined.removed
        + closed_caps
        + reclosed
    )
    # a wall is a possible opening (a hole, kept as a cap is) and may hold two parts together (a component);
    # two caps kept closed facing each other may be a tunnel's ends (a handle): open-cap's own words
    named = kept_walls(points, now, walls) + facing_caps(points, alive, undecided)
    ext.removed_features += [f for f in named if f.kind == "hole"]
    ext.reclosed_features = reclosed  # type: ignore[attr-defined]
    ext.named_features = [f for f in named if f.kind != "hole"]
    ext.openings = len(patches)  # type: ignore[attr-defined]
    ext.opened = opened  # type: ignore[attr-defined]
    ext.undecided = undecided  # type: ignore[attr-defined]
    ext.walls = [(vs, q) for _, vs, q in walls]  # type: ignore[attr-defined]
    ext.examined_caps = over  # type: ignore[attr-defined]
    ext.patch_start = start  # type: ignore[attr-defined]
    return ext
