"""Robust extraction: the paper's Algorithm 3, extended for undersampled input.

Why the paper's loop fails on real scans
----------------------------------------
Algorithm 3 only *removes* simplices, and line 2 removes every d-simplex at a
(d-1)-face that has a single one.  Where a scan is thin or creased, T_S has
holes (faces with one simplex, :attr:`Extraction.holes`).  Pruning such a
face exposes the faces behind it, and the cascade runs on until it meets a
closed sheet -- on a real scan usually never: ``fertility.off`` loses all
11,011 candidates in 10,749 steps.  :meth:`Extraction.cascades` groups those
steps by origin.

The extension
-------------
1. **The paper first.**  Algorithm 3 runs on T_S exactly as in paper mode.
   If it ends with a closed manifold through every sample, that result is
   returned unchanged: the extension never alters a run on which the paper
   succeeds.  Algorithm 3 only removes simplices, so as soon as a sample has
   lost its last simplex the paper can no longer succeed, and the loop is
   abandoned there (``stop_when_sample_lost``); so is a sample that has no
   simplex in T_S at all.
2. **Hypersurfaces of dimension d >= 2: labelling the Delaunay cells** (surfaces in R^3,
   3-manifolds in R^4, ...; :mod:`.cells`,
   :mod:`.labelling`, :mod:`.label_repair`): every Delaunay cell inside or
   outside by its ball (``label-cells``), M_S the faces between the two,
   made a manifold through every sample (``repair-vertex``,
   ``sculpt-sample``), with, in R^3, the caps over real openings removed
   (``open-cap``).  :func:`choose` keeps it, or the growing path's result
   (3.) where that one has fewer problems, and reports the two as disputed
   where both are closed and differ.  Curves in the plane are grown (3.):
   the growing path gets every built-in curve variant right.
3. **Growing a manifold instead of pruning one** (every other case; the direction the paper's
   closing section names: Cocone's "walk on the outer boundary").  The
   walk starts from the largest piece of the *manifold core* of T_S, the
   faces it would take without a choice, added in one step (rule
   ``seed-core``, :mod:`crustview.core.robust.seed_core`); where there is none,
   and for every later component, from the best-scored free candidate
   (rule ``seed``).  Delaunay d-faces are then added across the current
   boundary, one per step, always keeping a manifold with boundary
   (:mod:`crustview.core.robust.grow`).  A face f may be
   added across a boundary (d-1)-face tau of simplex sigma when

   * f and sigma meet at phi > pi/2 at tau (the paper's line 4: a pair
     meeting within pi/2 of flat), and likewise at every other face of f
     that already has a simplex; a second pass allows phi > pi/3, for the
     creases of real objects;
   * every (d-1)-face of f lies in at most one simplex so far (no
     non-manifold face ever appears);
   * f's new vertex is either not yet used, or lies on the boundary (a
     vertex inside the surface is never touched again);
   * if f is a *gluing* move (it touches the surface only at tau and one
     distant boundary vertex -- the only way handles form), f is in T_S,
     and it waits until no other move is left.

   Candidates are taken smallest first, by size (circumradius over the mean
   nearest-neighbour distance of the vertices, about 1 for a good face;
   never above :data:`~crustview.core.robust.grow.SIZE_MAX`), doubled outside T_S
   and weighted by the candidate score.  Faces of T_S at phi > pi/2 are rule
   ``grow``; the others are ``grow-relaxed`` (theta, or the angle, relaxed
   only where the boundary needs it).
4. **Closing gaps, keeping holes** (:mod:`crustview.core.robust.patcher`).  Stray
   components far smaller than the largest are dropped (``drop-stray``).
   A boundary component with at most
   :data:`~crustview.core.robust.fill_hole.FILL_MAX_FACES` faces spanning at most
   :data:`~crustview.core.robust.fill_hole.FILL_MAX_SPAN` local spacings is an
   undersampling gap, closed by Delaunay faces, ears in the hole's plane
   (d = 2) or joined ends (d = 1) (``fill-hole``).  Larger holes are real
   boundary (an open scan) and stay open, so no ribbon is drawn across a
   real gap; the report names them.  A sample that is no vertex is inserted
   by a stellar subdivision of the nearest face (``insert-sample``), and a
   vertex where M_S pinches keeps only its largest fan.

The run is one replayable sequence of steps over :attr:`Extraction.simplices`
(T_S followed by the Delaunay faces the extension added); the paper's
abandoned attempt is summarised in :attr:`Extraction.notes` and can be
replayed in paper mode.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..analysis.features import LOOP_MIN, features
from ..analysis.topology import analyse
from ..errors import check_cancel
from ..paper.extraction import extract
from ..steps import RULE_CORE, RULE_GROW, RULE_RELAX, RULE_SEED, Extraction, Step
from ..util.parallel import start_in_background
from .cap_holes import closed_openings, weak_openings
from .cells import extract_by_labels
from .cut_loop import cut_short_loops
from .grow import COS_CREASE, COS_PAPER, SIZE_MAX, Grower, size_ratio
from .patcher import Patcher
from .seed_core import manifold_core
from .tour_curve import tour_curve
from .verdict import _boundary_vertices, _disputed, _state, _tie, ranked, weighed


def extract_robust(
    points: np.ndarray,
    faces: np.ndarray,
    scores: np.ndarray,
    theta: float,
    *,
    spacing: float,
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | Callable[[], tuple] | None = None,
    cancel: object | None = None,
    progress: Callable[[float], None] | None = None,
    rows_sorted: bool = False,
    measured: list | None = None,
) -> Extraction:
    """Algorithm 3, and the extension (labelling, growing) where the paper's loop fails.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    faces : ndarray of shape (f, d + 1)
        Every Delaunay d-face among the samples (``Candidates.faces``).
    scores : ndarray of shape (f,)
        The chosen candidate test's angle of each face; T_S is
        ``faces[scores < theta]``.
    theta : float
        The candidate threshold.
    spacing : float
        Median nearest-neighbour distance of the samples (for hole sizes).
    cells : (delaunay_points, simplices, centres), optional
        The Delaunay k-cells (over the samples and the bounding points) and
        their circumcentres.  Given for hypersurfaces; for those of dimension
        d >= 2 the labelling path (:mod:`.cells`) runs before the growing one.  Or a function that
        returns them, called only where the paper's loop fails (rescaled
        copies of the Voronoi vertices take 118 MB at 300,000 samples).
    cancel, progress
        As in :func:`crustview.core.paper.extraction.extract`.
    rows_sorted : bool
        Every row of ``faces`` is known to be sorted (``Candidates.faces`` are): the check, a pass over all
        Delaunay faces (0.12 s at 300,000 samples), is skipped.
    measured : list, optional
        Where the paper's loop gives the result, a future of its
        :func:`~crustview.core.analysis.features.features` is appended (measured on the other core while
        the result is analysed); kept apart from the returned :class:`Extraction`, which stays picklable.

    Returns
    -------
    Extraction
        ``mode = "robust"``.  Its simplices are T_S followed by the Delaunay
        faces the extension added; ``in_candidates`` tells them apart.
    """
    n = len(points)
    faces = np.asarray(faces, dtype=np.int64)
    if not rows_sorted and faces.ndim == 2 and faces.shape[1] > 1 and not (faces[:, 1:] > faces[:, :-1]).all():
        # Candidates.faces already has sorted rows: no copy of all Delaunay faces
        # (220 MB at 300,000 samples, at the run's memory peak) unless needed
        faces = np.sort(faces, axis=1)
    scores = np.asarray(scores, dtype=float)
    admitted = scores < theta
    tset = faces[admitted]
    covered = np.zeros(n, dtype=bool)
    covered[tset.ravel()] = True
    d1 = faces.shape[1] if faces.ndim == 2 else 2
    note_paper: str
    if len(tset) and covered.all():
        paper = extract(points, tset, stop_when_sample_lost=True, cancel=cancel)
        if paper.stopped == "closed":
            final = paper.complex_at(paper.n_steps)
            # the report measures the features of this complex if it is the result: begun on the other
            # core while it is analysed (the same values as measured afterwards; see uncertainty.py).  Where
            # the loop ended pinched (rare) the measurement is not used, and its thread ends by itself.
            pending = start_in_background(features, points, final, d1 - 1) if measured is not None else None
            top = analyse(final, n, d1 - 1)
            if top.closed_manifold:
                paper.final_topology = (paper.n_steps, n, d1 - 1, top)  # type: ignore[attr-defined]
                if pending is not None:
                    measured.append(pending)
                paper.mode = "robust"
                paper.notes.append(
                    "the paper's Algorithm 3 gave a closed manifold through every sample; the extension was not needed"
                )
                return paper
            note_paper = "the paper's Algorithm 3 ended with a pinched complex"
        elif paper.stopped == "sample-lost":
            note_paper = (
                f"the paper's Algorithm 3 was abandoned after {paper.n_steps} steps, "
                f"when {paper.notes[-1].split(' lost')[0]} lost its last simplex "
                f"({len(paper.holes)} holes in T_S)"
            )
        else:
            note_paper = f"the paper's Algorithm 3 ended {paper.stopped}"
        holes = paper.holes
    else:
        missing = int((~covered).sum())
        note_paper = f"{missing} samples are in no simplex of T_S, so the paper's Algorithm 3 cannot succeed"
        holes = None
    if cells is not None and d1 == points.shape[1] and d1 >= 3:  # surfaces in R^3, 3-manifolds in R^4, ...
        cells = cells() if callable(cells) else cells
        ext = choose(points, faces, tset, scores, admitted, spacing, cells, cancel, progress, note_paper)
    else:
        ext = _grow_and_patch(points, _prepare_growth(points, faces, scores, admitted), spacing, cancel, progress)
        ext.notes.insert(0, note_paper + "; the robust extension grew M_S instead")
    ext.holes = holes
    return ext


#: Up to this many samples the growing path also runs as a second opinion on a labelled result that
#: looks sound but has uncertain features, or for which ``cut-handle`` removed a handle the sample may
#: resolve (a loop of at least LOOP_MIN): a cost rule (growing takes under half a second there, against
#: up to 36 s on the public noisy scans: gears at 0.1 h).  Above it a sound labelled result through
#: every sample is kept as it is: its uncertain features already say where it is unsure (on the public
#: files of more than 5,000 samples growing again never gave a right answer where the labelled one was
#: wrong: seahorse at 0.1 h, plastic-vase, casting; both answers wrong and flagged).  The decimated
#: knight (502 samples of long slivers) is why the second opinion exists: the labelling closes a torus
#: through a 9.5-radius loop where the arm touches the body, cut-handle removes it, and growing, the
#: independent answer, gives the same sphere.  A sound labelled result with no uncertain feature and
#: no such cut is not grown again at any size: on the public scans of up to 5,000 samples the grown
#: result never replaced one (21 files).
SECOND_OPINION_N = 5000


def choose(points, faces, tset, scores, admitted, spacing, cells, cancel, progress, note_paper) -> Extraction:
    """The labelling path, and the growing path where the labelling leaves doubt; the better of the two.

    The labelling's result is kept at once when it is a closed manifold
    (or a manifold open only at the openings ``open-cap`` found)
    through every sample, and either the sample has more than
    :data:`SECOND_OPINION_N` points or the result has no uncertain feature
    (:func:`~crustview.core.analysis.features.features`) and ``cut-handle``
    removed no handle whose loop was at least LOOP_MIN.  Otherwise M_S is also grown,
    and the result with fewer problems is kept, in this order: not closed,
    uncertain features, samples left out, boundary faces (topology first:
    a sample left out is named in the report, a feature in doubt may be a
    wrong genus; where the grown M_S closes an opening the labelled one shows
    beyond doubt, :func:`.verdict.ranked` counts that against the grown one
    and not the labelled one's openness).  Of two answers
    the sample supports equally, the one claiming fewer handles, unless every
    handle loop of the other is long enough for an eps = 1/2 sample to
    resolve (:func:`.verdict._tie`).
    When
    both are closed manifolds through (nearly) every sample and their Betti
    numbers differ, the sample does not decide between them: the difference
    is reported as an uncertain feature of the kept result
    (:attr:`Extraction.disputed`), even when the other result flags its own
    version of it (two parts that nearly touch, kept apart and flagged by
    one path, joined by the other: the joined result must not look sure).
    Where they differ only in b_1 and the kept one has more handles, every
    loop of them resolved at eps = 1/2
    (:func:`~crustview.core.analysis.features.handles_decided`), there is no
    dispute: the other has spanned tunnels the sample shows.
    """
    from ..analysis.dispute import disagreement
    from ..analysis.features import features, uncertain

    n = len(points)
    d = faces.shape[1] - 1
    report = progress or (lambda f: None)
    report(0.05)
    # the labelling path takes the first half of the bar, the growing path (when it runs) the rest
    lab = extract_by_labels(
        points,
        *cells,
        faces,
        np.sort(tset, axis=1),
        spacing,
        progress=lambda f: report(0.05 + 0.45 * f),
        cancel=cancel,
    )
    check_cancel(cancel)
    m_lab = lab.complex_at(lab.n_steps)
    top_lab = analyse(m_lab, n, d)
    # a hole open-cap made beside a sure opening from a cap under CAP_SURE times its ring is uncertain
    lab.features = weak_openings(features(points, m_lab, d, b1=top_lab.betti[1]), getattr(lab, "opened", []))
    f_lab = weighed(uncertain(lab.features), d)
    # sound: a closed manifold, or one whose only boundary is the openings open-cap kept open
    sound = top_lab.closed_manifold or (
        getattr(lab, "openings", 0) > 0 and top_lab.nonmanifold_faces == 0 and top_lab.singular_vertices == 0
    )
    # a cut in [LOOP_MIN, LOOP_SUPPORTED) or any join-parts join decided what the sample did not
    # (and a cap open-cap kept closed undecided: the sample did not decide that either)
    band_cut = any(f.kind in ("component", "hole") or f.size_spacings >= LOOP_MIN for f in lab.removed_features)
    # above SECOND_OPINION_N a sound result through every sample is kept as it is: its uncertain
    # features already say where it is unsure, and growing again costs up to 36 s (gears at 0.1 h)
    if sound and top_lab.unused_samples == 0 and (n > SECOND_OPINION_N or (not f_lab and not band_cut)):
        lab.notes.insert(0, note_paper + "; the robust extension labelled the Delaunay cells instead")
        lab.final_topology = (lab.n_steps, n, d, top_lab)  # type: ignore[attr-defined]
        return lab
    report(0.5)
    grown = _grow_and_patch(
        points, _prepare_growth(points, faces, scores, admitted), spacing, cancel, lambda f: report(0.5 + 0.5 * f)
    )
    m_gro = grown.complex_at(grown.n_steps)
    top_gro = analyse(m_gro, n, d)
    grown.features = features(points, m_gro, d, b1=top_gro.betti[1])
    f_gro = weighed(uncertain(grown.features), d)

    # (the caps open-cap kept closed are removed features, in neither f_lab nor f_gro: they weigh on neither)
    # the sure openings of the labelled M_S that the grown one spans (cap_holes.closed_openings) weigh in the choice:
    # those still open in the labelled M_S (settle may have closed one) whose samples the grown M_S mostly runs
    # through (not an opening only because it left them out)
    opened = getattr(lab, "opened", [])
    rim_gro = _boundary_vertices(m_gro)
    spanned, only_caps = [], False
    if opened:
        rim_lab, on_gro = _boundary_vertices(m_lab), np.unique(m_gro)
        there = [(vs, q) for vs, q in opened if rim_lab.intersection(vs.tolist()) and np.isin(vs, on_gro).mean() > 0.5]
        spanned = closed_openings(points, there, rim_gro)
        # the labelled M_S open only at open-cap's caps (its every rim vertex a cap's sample), not merely sound
        only_caps = sound and bool(rim_lab) and rim_lab <= set(np.concatenate([vs for vs, _ in opened]).tolist())
    p_lab, p_gro = ranked(top_lab, f_lab, top_gro, f_gro, only_caps, len(spanned))
    if p_lab != p_gro:
        keep, why = (lab, "labelled") if p_lab < p_gro else (grown, "grown")
    else:
        keep = _tie(lab, grown, top_lab, top_gro)
        why = "labelled" if keep is lab else "grown"
    m_keep, m_other = (m_lab, m_gro) if keep is lab else (m_gro, m_lab)
    if keep is grown:
        # a possible opening open-cap kept closed stays undecided where the grown M_S closes it too
        rim = rim_gro
        grown.removed_features = (
            list(grown.removed_features)
            + [f for f in lab.removed_features if f.kind == "hole" and not rim.intersection(f.vertices.tolist())]
            # and an opening the labelled path showed beyond doubt, which the grown M_S closes, is no surer
            + spanned
        )
        # and where the grown M_S is open there, its hole is no surer than the cap was
        grown.features = weak_openings(
            grown.features or [], getattr(lab, "undecided", []), how="where the labelled M_S had a cap open-cap kept"
        )
    t_keep, t_other = (top_lab, top_gro) if keep is lab else (top_gro, top_lab)
    keep.notes.insert(
        0,
        f"{note_paper}; the robust extension labelled the Delaunay cells ({_state(top_lab)}, Betti "
        f"{top_lab.betti}, {top_lab.unused_samples} samples left out, {_features(len(f_lab))}) and grew "
        f"M_S ({_state(top_gro)}, Betti {top_gro.betti}, {top_gro.unused_samples} left out, {len(f_gro)} "
        f"uncertain); the {why} result is kept (the checks of the kept result, its contacts and a resample, "
        "may find more uncertain features)",
    )
    if _disputed(t_keep, t_other, keep.features or [], n, labelled=keep is lab):
        keep.disputed = disagreement(points, m_keep, m_other, t_keep.betti, t_other.betti)
    keep.final_topology = (keep.n_steps, n, d, t_keep)  # type: ignore[attr-defined]
    return keep


def _row_keys(rows: np.ndarray, base: int) -> np.ndarray:
    """One int64 (or byte-string) key per sorted row of vertex ids below ``base``."""
    from ..util.rows import row_keys

    rows = np.asarray(rows, dtype=np.int64).reshape(len(rows), -1)
    keys = row_keys(rows, base)
    if keys is None:
        keys = np.array([r.tobytes() for r in np.ascontiguousarray(rows)])
    return keys


def _prepare_growth(
    points: np.ndarray, faces: np.ndarray, scores: np.ndarray, admitted: np.ndarray
) -> tuple[np.ndarray, np.ndarray, int, Grower, np.ndarray]:
    """The walk's faces (T_S first), its Grower, and the manifold core added to it.

    Pure array work on its own inputs.
    """
    # faces too large to be grown never enter the grower (T_S is kept whole for its row ids)
    size = size_ratio(points, faces)
    fits = size <= SIZE_MAX
    order = np.concatenate([np.flatnonzero(admitted), np.flatnonzero(~admitted & fits)])
    F, S = faces[order], scores[order]
    n_ts = int(admitted.sum())
    tier = (np.arange(len(F)) >= n_ts).astype(np.int8)
    gr = Grower(points, F, S, tier, size[order])
    core, core_orient = manifold_core(
        F, gr.facet_of, gr.u, tier == 0, gr.size <= SIZE_MAX, gr.cost, COS_PAPER, gr.orientable, gr.by_facet
    )
    gr.add_bulk(core, core_orient, RULE_CORE)
    return F, S, n_ts, gr, core


def _grow_and_patch(points, prepared, spacing, cancel, progress) -> Extraction:
    """Phases 2 and 3 of the module docstring, assembled into one replayable Extraction."""
    F, S, n_ts, gr, core = prepared
    tier = gr.tier

    def rule_of(f: int, cos: float) -> str:
        return RULE_GROW if tier[f] == 0 and cos < COS_PAPER else RULE_RELAX

    n_core = len(core)
    for limit in (COS_PAPER, COS_CREASE):
        gr.cos_limit = limit
        gr.requeue_front()
        while True:
            gr.grow(rule_of, cancel, progress)
            if not gr.seed():
                break
    check_cancel(cancel)
    grown = np.array([f for f, *_ in gr.log], dtype=np.int64)
    pt = Patcher(
        points,
        list(map(tuple, F[grown].tolist())),
        F,
        spacing,
        orient=[gr.orient[f] for f in grown.tolist()],
        orientable=gr.orientable,
    )
    # only gluing moves leave pinched vertices behind in the grown complex
    pt.suspects = set(gr.glued)
    left = pt.settle()
    loops_cut: list = []
    if F.shape[1] == 3 and points.shape[1] > 3:  # a surface in codimension 2 or more: no orientation rule
        pt, left, loops_cut = cut_short_loops(pt, points, left)
    doubts: list = []
    if F.shape[1] == 2:  # a curve the growing left broken: its samples' short tours
        pt, left, doubts = tour_curve(pt, points, F, left, cancel)
    # rows: T_S first (as in paper mode), then every other simplex in the order it first appeared
    outside = grown[grown >= n_ts]
    grown_rows = grown.copy()
    grown_rows[grown >= n_ts] = n_ts + np.arange(len(outside))
    extra: list[tuple[int, ...]] = []  # rows beyond T_S and the grown faces outside it
    grown_rows_l = grown_rows.tolist()
    patch_rows = list(grown_rows_l)
    n_base = n_ts + len(outside)
    if len(pt.simp) > len(grown):
        keys = _row_keys(F[:n_ts], len(points))
        order = np.argsort(keys, kind="stable")
        sorted_keys = keys[order]
        new_keys = _row_keys(np.array(pt.simp[len(grown) :], dtype=np.int64), len(points))
        row_of: dict[tuple[int, ...], int] = {}
        taken = set(grown_rows_l)  # a row is added at most once; a re-added simplex gets a new row
        for i in range(len(grown), len(pt.simp)):
            t = pt.simp[i]
            r = row_of.get(t)
            if r is None:
                k = new_keys[i - len(grown)]
                j = int(np.searchsorted(sorted_keys, k))
                if j < len(order) and sorted_keys[j] == k:
                    r = int(order[j])
            if r is None or r in taken:
                r = n_base + len(extra)
                extra.append(t)
                row_of[t] = r
            taken.add(r)
            patch_rows.append(r)
    steps: list[Step] = []
    if n_core:
        steps.append(
            Step(
                0,
                RULE_CORE,
                tuple(F[core[0]].tolist()),
                (),
                (),
                math.nan,
                f"seeded M_S with the manifold core of T_S: {n_core} faces where T_S is already a "
                "manifold and the cheapest choice on both sides of every face, which growing "
                "would take one by one without a choice",
                added=tuple(grown_rows_l[:n_core]),
            )
        )
    log_f = [e[0] for e in gr.log]
    score_deg = np.degrees(S[log_f]).tolist() if log_f else []
    sizes = gr.size[log_f].tolist() if log_f else []
    dp1 = F.shape[1]
    fv = gr._fverts  # flat facet vertex lists
    for idx in range(n_core, len(gr.log)):
        f, rule, g, angle = gr.log[idx]
        tau = tuple(fv[g * (dp1 - 1) : (g + 1) * (dp1 - 1)]) if g >= 0 else tuple(F[f].tolist())
        if rule == RULE_SEED:
            why = (
                f"new component started at the best free candidate (score {score_deg[idx]:.1f} deg, "
                f"size {sizes[idx]:.2f})"
            )
        else:
            where = "a face of T_S" if f < n_ts else f"a Delaunay face outside T_S (score {score_deg[idx]:.1f} deg)"
            why = (
                f"added {where} across a boundary face, meeting its neighbour at "
                f"{math.degrees(angle):.1f} deg (180 = flat), size {sizes[idx]:.2f}"
            )
        steps.append(Step(len(steps), rule, tau, (), (), angle, why, added=(grown_rows_l[idx],)))
    for rule, tau, added, removed, angle, why in pt.log:
        steps.append(
            Step(
                len(steps),
                rule,
                tau,
                (),
                tuple(patch_rows[i] for i in removed),
                angle,
                why,
                added=tuple(patch_rows[i] for i in added),
            )
        )
    n_steps = len(steps)
    dp1 = F.shape[1]
    simplices = np.vstack([F[:n_ts], F[outside], np.array(extra, dtype=np.int64).reshape(-1, dp1)])
    added_at = np.full(len(simplices), n_steps + 1, dtype=np.int64)
    removed_at = np.full(len(simplices), n_steps, dtype=np.int64)
    # the core in step 1, then one grown simplex per step, in order
    added_at[grown_rows] = np.maximum(np.arange(len(grown)) + 1 - max(n_core - 1, 0), 1)
    n_grow_steps = len(grown) - max(n_core - 1, 0)
    for st in steps[n_grow_steps:]:
        for r in st.added:
            added_at[r] = min(added_at[r], st.index + 1)
        for r in st.removed:
            removed_at[r] = st.index
    bnd = len(pt.boundary())
    alive_any = any(pt.alive)
    stopped = "empty" if not alive_any else ("closed" if bnd == 0 else "open")
    in_ts = np.arange(len(simplices)) < n_ts
    if extra:  # a simplex the patch added may be a face of T_S, re-added under a new row
        in_ts[n_base:] = np.isin(_row_keys(simplices[n_base:], len(points)), _row_keys(F[:n_ts], len(points)))
    ext = Extraction(simplices, steps, removed_at, stopped, added_at=added_at, mode="robust", in_candidates=in_ts)
    ext.removed_features = list(loops_cut)
    ext.disputed = list(doubts)
    if left:
        shown = ", ".join(str(x) for x in left[:10]) + (" ..." if len(left) > 10 else "")
        ext.notes.append(
            f"{len(left)} samples are farther than the insertion limit from M_S and were left "
            f"out (outliers or unreachable): {shown}"
        )
    return ext


def _features(count: int) -> str:
    """``count`` uncertain feature(s), in words."""
    return f"{count} uncertain feature{'' if count == 1 else 's'}"
