"""Which of two robust answers to keep: the order of their problems, the tie, the dispute.

:func:`~.driver.choose` runs the labelling path and, where it leaves doubt,
the growing path too; these rules compare the two results.  Each is named in
the note the kept result carries.
"""

from __future__ import annotations

import numpy as np

from ..analysis.features import LOOP_SUPPORTED
from ..steps import Extraction
from ..util.rows import unique_rows


def weighed(found: list, d: int) -> list:
    """The uncertain features that ask for the growing path's opinion and weigh in the choice between the two.

    A d >= 3 result's handles (:mod:`~crustview.core.analysis.tunnels`, session 37) are reported, not weighed
    (nor in :func:`_tie` and :func:`_disputed`, which read their loops through this filter): growing a 3-manifold leaves
    it open where the labelling closes it (session 36), so it is no second opinion on its tunnels, and a
    choice swayed by them kept a grown S^2 x S^1 with b2 = 267 (1,500 samples, a tube of radius 0.25).
    """
    return [f for f in found if d == 2 or f.kind != "handle"]


def problems(top, unc: list) -> tuple:
    """What :func:`~.driver.choose` compares, fewer first: closed, uncertain features, samples left out, boundary faces.

    Topology first: an uncertain feature is a place where the result may
    have the wrong genus or the wrong number of holes or parts; a sample left
    out is only a point the surface misses, and the report names it.
    Ordered the other way, a grown M_S with 33 uncertain handles beat the
    right labelled open surface that left 2 of 11,381 samples out (the camel
    head at 0.3 h, noise draw 26).
    """
    return (not top.closed_manifold, len(unc), top.unused_samples, top.boundary_faces)


def ranked(top_lab, f_lab: list, top_gro, f_gro: list, sound: bool, spanned: int) -> tuple[tuple, tuple]:
    """:func:`problems` of the labelled and the grown result, as :func:`~.driver.choose` compares them.

    ``sound``: the labelled M_S is open only at the caps ``open-cap`` removed (every rim vertex a cap's
    sample).  ``spanned``: how many of those it found beyond doubt (caps over CAP_SURE times their ring) are
    still open in it and closed in the grown M_S (:func:`~.cap_holes.closed_openings`).  Where there is one,
    the labelled answer's openness is not its first problem (the sample shows those openings by the same bound
    by which a cap is surely one), and each opening the grown answer spans counts against it as an uncertain
    hole, which it also carries in the report.  The last key, boundary faces, still counts the openings: of two
    answers otherwise even, the closed one is kept, flagged at the opening it spans (the fertility statue with a
    5 % hole, draw 2).  Otherwise the two are :func:`problems`, closed first.
    """
    p_lab, p_gro = problems(top_lab, f_lab), problems(top_gro, f_gro)
    if sound and spanned:
        p_lab = (False, *p_lab[1:])
        p_gro = (p_gro[0], p_gro[1] + spanned, *p_gro[2:])
    return p_lab, p_gro


def _state(top) -> str:
    """A result's closedness in a few words, for the note that compares the two paths."""
    if top.closed_manifold:
        return "closed"
    return f"{top.boundary_faces} boundary faces" if top.boundary_faces else "not a manifold"


def _boundary_vertices(faces: np.ndarray) -> set[int]:
    """The vertices of the boundary ridges of a pure complex (ridges in one face)."""
    d = faces.shape[1]
    if len(faces) == 0:
        return set()
    ridges, inverse = unique_rows(np.sort(np.concatenate([np.delete(faces, j, axis=1) for j in range(d)]), axis=1))
    return set(np.unique(ridges[np.bincount(inverse) == 1]).tolist())


def _open_manifold(top) -> bool:
    """A manifold with boundary: boundary faces, and no non-manifold face or pinched vertex.

    The topology report counts pinched vertices on closed complexes only; two rims touching at a vertex
    pass here, and :func:`~crustview.core.analysis.dispute.disagreement` then names the difference by b1.
    """
    return (
        not top.closed_manifold and top.boundary_faces > 0 and top.nonmanifold_faces == 0 and top.singular_vertices == 0
    )


def _disputed(t_keep, t_other, keep_features: list, n: int, *, labelled: bool = True) -> bool:
    """Whether two results of the same sample are a dispute (:func:`~.driver.choose`).

    Both closed manifolds, or both manifolds with boundary (session 28), through all but at most 1 % of
    the samples, with other Betti numbers; not when they differ only in b_1 and the kept one is
    the labelled result and decided
    (:func:`~crustview.core.analysis.features.handles_decided`).  Two open answers are as undecided as
    two closed ones: a decimated camel head (30 % of its faces) was kept grown with an extra hole, sure,
    over the labelled answer with the true single opening, which had left 5 samples out.

    Only a labelled handle can be decided so: its tunnel is a chain of cells
    the labelling put outside by their balls, evidence from the sample
    itself.  A grown handle comes from a gluing move, which growing takes
    only when no other move is left, with no ball behind it; a grown result
    with more handles than the labelled one stays disputed whatever its
    loops measure (neptune at 0.1 h, another draw: a grown genus 4 with a
    13.7-radius loop against the labelled genus 3 that left 2 samples out).
    """
    from ..analysis.features import handles_decided

    both = (t_keep.closed_manifold and t_other.closed_manifold) or (_open_manifold(t_keep) and _open_manifold(t_other))
    return bool(
        both
        and t_keep.betti != t_other.betti
        and min(t_keep.unused_samples, t_other.unused_samples) <= 0.01 * n
        and not (
            labelled
            and t_keep.betti[0] == t_other.betti[0]
            and handles_decided(weighed(keep_features, len(t_keep.betti) - 1), t_keep.betti[1], t_other.betti[1])
        )
    )


#: Loop length (in sampling radii) that an eps = 1/2 sample resolves: 2 pi / eps
#: (:data:`~crustview.core.analysis.features.LOOP_SUPPORTED`; eps = 1/2 is open-cap's CAP_RATIO's too).
LOOP_RESOLVED = LOOP_SUPPORTED


def _tie(lab: Extraction, grown: Extraction, top_lab, top_gro) -> Extraction:
    """Of two results with the same problems, the one to keep.

    The one claiming fewer handles (a handle needs evidence), unless the other
    one's every handle loop is at least :data:`LOOP_RESOLVED` sampling radii
    long: then its extra handles are features an eps = 1/2 sample resolves,
    and the answer without them has spanned a tunnel the sample shows.
    """
    h_lab, h_gro = sum(top_lab.betti[1:-1]), sum(top_gro.betti[1:-1])
    if h_lab == h_gro:
        return lab
    more, fewer = (lab, grown) if h_lab > h_gro else (grown, lab)
    loops = [f.size_spacings for f in weighed(more.features or [], len(top_lab.betti) - 1) if f.kind == "handle"]
    return more if loops and min(loops) >= LOOP_RESOLVED else fewer
