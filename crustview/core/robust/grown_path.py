"""The growing path of the robust extension, assembled into one replayable :class:`~crustview.core.steps.Extraction`.

Phases 2 and 3 of :mod:`.driver`'s docstring: the manifold core of T_S, Delaunay faces added across the
boundary one per step (:mod:`.grow`), then the last phase shared with the labelling path
(:meth:`.patcher.Patcher.settle`).  :func:`grown_path` is the whole path on the run's arrays alone, so that
:func:`.choose.choose` can begin it in a second process (:mod:`crustview.core.util.second_core`) while the
labelling runs, and take it only if the labelling's result leaves doubt.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..errors import check_cancel
from ..steps import RULE_CORE, RULE_GROW, RULE_RELAX, RULE_SEED, Extraction, Step
from .cut_loop import cut_short_loops
from .grow import COS_CREASE, COS_PAPER, SIZE_MAX, Grower, size_ratio
from .patcher import Patcher
from .seed_core import manifold_core
from .tour_curve import tour_curve


def grown_path(
    points: np.ndarray,
    faces: np.ndarray,
    scores: np.ndarray,
    admitted: np.ndarray,
    spacing: float,
    progress: Callable[[float], None] | None = None,
    cancel: object | None = None,
) -> Extraction:
    """M_S grown from T_S's manifold core and settled (phases 2 and 3 of :mod:`.driver`).

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    faces : ndarray of shape (f, d + 1)
        Every Delaunay d-face among the samples, sorted rows.
    scores : ndarray of shape (f,)
        The candidate test's angle of each face.
    admitted : ndarray of bool, shape (f,)
        Which faces are in T_S.
    spacing : float
        Median nearest-neighbour distance of the samples.
    progress : callable(fraction), optional
        Called during the growth with the fraction done.
    cancel : object with ``is_set()``, optional
        Checked during the growth.

    Returns
    -------
    Extraction
        ``mode = "robust"``: T_S's rows first, then the other faces in the order they were first added.
    """
    return _grow_and_patch(
        points, _prepare_growth(points, faces, scores, admitted), spacing, cancel, progress or (lambda f: None)
    )


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
