"""The robust extension's choice between its two paths for hypersurfaces: labelling, and growing where in doubt.

:func:`choose` runs the labelling path (:mod:`.cells`) and, where its result leaves doubt, the growing path
(:mod:`.grown_path`), and keeps the result the sample supports better (:mod:`.verdict`).  Where a second core
is free, the growing path begins in a helper process as the labelling begins
(:class:`~crustview.core.util.second_core.Speculation`) and is stopped if the labelling's result is kept:
the same result, on the public noisy scans up to as much sooner as the shorter of the two paths takes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.features import LOOP_MIN, features
from ..analysis.topology import analyse
from ..errors import check_cancel
from ..steps import Extraction
from ..util import second_core
from .cap_holes import closed_openings, weak_openings
from .cells import extract_by_labels
from .grown_path import grown_path
from .verdict import _boundary_vertices, _disputed, _state, _tie, ranked, weighed

#: Fewest samples for which the growing path is begun in a helper process (:mod:`~..util.second_core`)
#: while the labelling runs.  ``benchmarks/bench_second_core.py`` times the same job in the helper and here on
#: the public cases that grow: the helper's extra (sending the arguments and the result) had a median of
#: 0.097 s, -0.095 s and 0.205 s in three runs, and the growing path takes a median 522-664 us per sample,
#: so at most about 400 samples' worth.  1,000 leaves room for the job begun and then not needed, which
#: costs its sending too.
SPECULATE_MIN_N = 1000


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
    ahead = None
    if len(points) >= SPECULATE_MIN_N and second_core.enabled():
        ahead = second_core.Speculation(grown_path, (points, faces, scores, admitted, spacing), with_progress=True)
    try:
        return _choose(points, faces, tset, scores, admitted, spacing, cells, cancel, progress, note_paper, ahead)
    finally:
        if ahead is not None:
            ahead.discard()  # not needed (the labelled result kept), or already taken: a no-op


def _choose(points, faces, tset, scores, admitted, spacing, cells, cancel, progress, note_paper, ahead) -> Extraction:
    """:func:`choose`, with the growing path's :class:`~..util.second_core.Speculation` if one was begun."""
    from ..analysis.dispute import disagreement
    from ..analysis.features import uncertain

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
    grown = _grown(points, faces, scores, admitted, spacing, cancel, lambda f: report(0.5 + 0.5 * f), ahead)
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
        reclosed = getattr(lab, "reclosed_features", [])
        grown.removed_features = (
            list(grown.removed_features)
            + [
                f
                for f in lab.removed_features
                if f.kind == "hole" and not any(f is r for r in reclosed) and not rim.intersection(f.vertices.tolist())
            ]
            # and an opening the labelled path showed beyond doubt, which the grown M_S closes, is no surer
            + spanned
            # nor one open-cap made that the labelled path's fill-hole closed again (its features say so of the
            # labelled M_S), where the grown M_S closes it too
            + closed_openings(points, getattr(lab, "reclosed", []), rim_gro, sure_only=False)
        )
        # and where the grown M_S is open there, its hole is no surer than the cap was
        grown.features = weak_openings(
            grown.features or [], getattr(lab, "undecided", []), how="where the labelled M_S had a cap open-cap kept"
        )
        # and so is one where the labelled M_S kept a wall, at any ratio (walls.py: no wall shows an opening)
        grown.features = weak_openings(
            grown.features,
            getattr(lab, "walls", []),
            how="where the labelled M_S had a wall open-cap kept",
            any_ratio=True,
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


def _grown(points, faces, scores, admitted, spacing, cancel, progress, ahead) -> Extraction:
    """The growing path's result: from the helper begun ahead if there is one, else (or if it was lost) here."""
    if ahead is not None:
        try:
            return ahead.result(lambda: check_cancel(cancel), progress)
        except second_core.Lost:
            pass  # the same function, here: a lost helper costs time, never the result
    return grown_path(points, faces, scores, admitted, spacing, progress, cancel)


def _features(count: int) -> str:
    """``count`` uncertain feature(s), in words."""
    return f"{count} uncertain feature{'' if count == 1 else 's'}"
