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

from collections.abc import Callable

import numpy as np

from ..analysis.features import features
from ..analysis.topology import analyse
from ..paper.extraction import extract
from ..steps import Extraction
from ..util.parallel import start_in_background
from .choose import SECOND_OPINION_N, choose
from .grown_path import grown_path

__all__ = ["SECOND_OPINION_N", "choose", "extract_robust", "grown_path"]


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
            n_steps, n_holes = paper.n_steps, len(paper.holes)
            # the faces on holes, not holes: the holes layer and its legend count the holes (a review)
            size = len(paper.holes[0]) if n_holes else 0  # samples per face on a hole: d
            unit = {1: "end", 2: "edge", 3: "triangle"}.get(size, "face")
            note_paper = (
                f"the paper's Algorithm 3 was abandoned after {n_steps} step{'' if n_steps == 1 else 's'}, "
                f"when {paper.notes[-1].split(' lost')[0]} lost its last simplex "
                f"({n_holes} {unit}{'' if n_holes == 1 else 's'} on holes of T_S)"
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
        ext = grown_path(points, faces, scores, admitted, spacing, progress, cancel)
        ext.notes.insert(0, note_paper + "; the robust extension grew M_S instead")
    ext.holes = holes
    return ext
