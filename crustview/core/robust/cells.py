"""The labelling path of the robust extension: Delaunay cells inside or outside, then local repairs.

For a surface in R^3 (more generally a hypersurface, codimension 1) the robust
extension first labels every Delaunay cell (rule ``label-cells``,
:mod:`.labelling`) and takes the faces between the two labels as M_S: closed
by construction, in one step.  Then, each a step of the log:

1. ``repair-vertex`` and ``sculpt-sample`` (:mod:`.label_repair`) make it a
   manifold through every sample it can reach by flipping cells;
2. ``open-cap``: a face larger than :data:`~.grow.SIZE_MAX` (circumradius
   over the local spacing; 99 % of the true triangles of the public scans are
   below 2.2, see :mod:`.grow`) spans a gap no sample supports -- the cap
   the labelling puts over the opening of an open scan, or webbing between
   parts.  Such faces are removed, and the holes they leave are real
   openings that ``fill-hole`` does not close again (on a closed object
   with a few large faces this leaves holes, and the driver then prefers the
   growing path's closed result);
3. the last phase shared with the growing path (:meth:`.patcher.Patcher.settle`):
   holes that are undersampling gaps are closed again (``fill-hole``), real
   openings stay open, left-out samples are inserted (``insert-sample``),
   stray pieces dropped (``drop-stray``).

The driver (:mod:`.driver`) runs this path before the growing one and keeps
whichever result the sample supports better.
"""

from __future__ import annotations

import math

import numpy as np

from ..steps import RULE_LABEL, RULE_OPEN, RULE_REPAIR, RULE_SCULPT, Extraction
from .grow import SIZE_MAX, size_ratio
from .label_repair import LabelEditor
from .labelling import Labelling, oriented
from .patcher import Patcher
from .steplog import StepLog


def extract_by_labels(
    points: np.ndarray,
    delaunay_points: np.ndarray,
    simplices: np.ndarray,
    centres: np.ndarray,
    faces: np.ndarray,
    candidates: np.ndarray,
    spacing: float,
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

    Returns
    -------
    Extraction
        ``mode = "robust"``; ``labelling`` holds the :class:`~.labelling.Labelling`.
    """
    n = len(points)
    lab = Labelling(points, delaunay_points, simplices, centres)
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
    ed = LabelEditor(lab)
    for v, cells, removed, added in ed.repair():
        log.step(
            RULE_REPAIR,
            (int(v),),
            lab.faces[added],
            lab.faces[removed],
            math.nan,
            f"M_S pinched at sample {v}; {len(cells)} less confident cells of its star took the other label "
            f"(confidence {float(lab.confidence[cells].max()):.2f} or less)",
        )
    for v, _cells, removed, added in ed.sculpt():
        log.step(
            RULE_SCULPT,
            (int(v),),
            lab.faces[added],
            lab.faces[removed],
            math.nan,
            f"sample {v} was no vertex: the cell of its star with its opposite face on M_S took the other "
            "label, so M_S runs through the sample (Boissonnat's sculpting)",
        )
    # the rest edits M_S face by face
    cut = ed.cut
    inner = np.where(lab.inside[lab.a[cut]], lab.a[cut], lab.b[cut])
    now = lab.faces[cut]
    orient = oriented(now, inner, simplices, delaunay_points)
    pt = Patcher(points, list(map(tuple, now.tolist())), faces, spacing, orient=orient.tolist(), orientable=True)
    big = np.flatnonzero(size_ratio(points, now) > SIZE_MAX)
    if len(big):
        for i in big.tolist():
            pt._delete(i)
        pt.log.append(
            (
                RULE_OPEN,
                pt.simp[int(big[0])],
                (),
                tuple(big.tolist()),
                math.nan,
                f"removed {len(big)} faces larger than {SIZE_MAX:g} local spacings (circumradius): no sample "
                "supports them (the cap over an open scan's opening, webbing between parts)",
            )
        )
        pt.suspects.update(int(v) for i in big.tolist() for v in pt.simp[i])
        # the openings stay open: fill-hole would span them again with smaller faces
        pt.keep_open = frozenset(pt.boundary())
    start = len(log.steps)
    left = pt.settle()
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
    ext = log.extraction(stopped, notes)
    ext.labelling = lab  # type: ignore[attr-defined]
    ext.patch_start = start  # type: ignore[attr-defined]
    return ext
