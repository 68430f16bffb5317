"""Rule ``cut-handle`` on a grown surface in codimension 2 and more: loops no sample resolves are cut.

The labelling path (surfaces in R^3) cuts a handle whose shortest loop is
under :data:`~crustview.core.analysis.features.LOOP_MIN` = 2 pi sampling
radii by relabelling cells (:mod:`.cut_handle`): no eps < 1 sample resolves
such a loop, so it is a tunnel of noise or a bridge.  A surface in R^4 or R^5
is grown instead (:mod:`.grow`), and there nothing forbids a gluing move from
closing a Moebius band: a closed surface in codimension 2 may be
non-orientable (the Klein bottle), so the orientation rule of codimension 1
cannot apply.  Under noise the walk then closes crosscaps and handles around
three samples (the flat Klein bottle and the sphere in R^4 with noise of 1 %
of their size: loops of 2.2-2.6 sampling radii, ``benchmarks/bench_variants.py``).

The cut here is surgery on the grown complex: every simplex at a vertex of
the loop is removed (the stars of its vertices, a neighbourhood of the loop:
an annulus around a handle's loop, a Moebius band around a crosscap's), and
the last phase (:meth:`.patcher.Patcher.settle`) closes what is left with
``fill-hole`` (the rim is the stars' link, a few spacings long) and takes the
loop's samples back with ``insert-sample``.  A trial is kept only when the
result is a closed manifold through as many samples as before, with as many
components and fewer independent loops (b1 lower); otherwise the complex is
left as it was.  Each cut is a step of the log, followed by the steps of the
rules that closed it, and the loop is reported as a removed feature: sure
when it ran through three samples (:data:`SURE_SAMPLES`), uncertain when it
ran through more.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..analysis.features import LOOP_MIN, Feature, features
from ..analysis.topology import analyse
from ..steps import RULE_CUT
from .patcher import Patcher

#: Loops of at most this many samples are cut as sure: three samples are one triangle's boundary, a tunnel
#: no sample shows (as a one-triangle hole does not show).  A longer loop under LOOP_MIN is cut too, but
#: reported uncertain: its length is measured in the noisy complex's own sampling radii, which noise
#: inflates (the flat Klein bottle with noise of 1.5 % of its size: its real crosscaps measured 3.9 and
#: 6.1 radii, loops of 4 and 5 samples, and cutting them as sure gave a sphere without a flag).
SURE_SAMPLES = 3


def _alive(pt: Patcher) -> np.ndarray:
    rows = [s for s, a in zip(pt.simp, pt.alive, strict=True) if a]
    return np.array(rows, dtype=np.int64).reshape(-1, len(pt.simp[0]) if pt.simp else 3)


def _loop(f: Feature) -> tuple[int, ...]:
    """A loop's samples, sorted (what identifies a loop already tried)."""
    return tuple(sorted(set(f.vertices.tolist())))


def cut_short_loops(pt: Patcher, points: np.ndarray, left: list[int]) -> tuple[Patcher, list[int], list[Feature]]:
    """Cut every handle or crosscap loop under LOOP_MIN sampling radii from a closed grown surface.

    Parameters
    ----------
    pt : Patcher
        The grown complex after its last phase (a surface, d = 2).
    points : ndarray of shape (n, k)
        The samples.
    left : list of int
        The samples ``pt`` leaves out.

    Returns
    -------
    (Patcher, list of int, list of Feature)
        The complex (``pt`` itself when nothing was cut), the samples it
        leaves out, and the loops cut (as the features of the complex before).
    """
    n = len(points)
    cut: list[Feature] = []
    tried: set[tuple[int, ...]] = set()
    while True:
        tri = _alive(pt)
        if tri.shape[1] != 3 or len(tri) == 0:
            return pt, left, cut
        top = analyse(tri, n, 2)
        if not top.closed_manifold or top.betti[1] == 0:
            return pt, left, cut
        short = [
            f
            for f in features(points, tri, 2, tighten_loops=False, handles_only=True)
            if f.kind == "handle" and f.size_spacings < LOOP_MIN and _loop(f) not in tried
        ]
        if not short:
            return pt, left, cut
        f = min(short, key=lambda x: x.size_spacings)
        loop = _loop(f)
        tried.add(loop)
        trial = pt.trial_copy()
        on = set(loop)
        gone = [i for i, (s, a) in enumerate(zip(trial.simp, trial.alive, strict=True)) if a and on.intersection(s)]
        for i in gone:
            trial._delete(i)
        trial.log.append(
            (
                RULE_CUT,
                loop,
                (),
                tuple(gone),
                math.nan,
                f"a loop through {len(loop)} samples, {f.size_spacings:.3g} sampling radii long as measured on the "
                "grown surface (below 2 pi: no eps < 1 sample resolves it), closed by the walk (a handle, or a "
                f"crosscap: codimension 2 allows a Moebius band); the {len(gone)} simplices at its samples removed, "
                "the hole closed and the samples taken back by the rules that follow",
            )
        )
        left2 = trial.settle()
        after = analyse(_alive(trial), n, 2)
        if (
            after.closed_manifold
            and len(left2) <= len(left)
            and after.betti[0] == top.betti[0]
            and after.betti[1] < top.betti[1]
        ):
            pt, left = trial, left2
            sure = len(loop) <= SURE_SAMPLES
            cut.append(
                replace(
                    f,
                    removed=True,
                    uncertain=not sure,
                    reason=f.reason
                    + (
                        "; cut: it runs through three distinct samples, one missing triangle's boundary, which no "
                        "sample tells from a filled triangle"
                        if sure
                        else f"; cut: it runs through {len(loop)} distinct samples, and noise inflates the sampling "
                        "radii it is measured in, so the sample may not decide it (a real loop of the object measured "
                        "under 2 pi under heavy noise)"
                    ),
                )
            )
