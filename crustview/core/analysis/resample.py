"""Rule ``resample-check``: a handle just above the resolution bound must survive losing a tenth of the samples.

Why
---
:mod:`.features` calls a handle uncertain when its shortest loop is below
:data:`~.features.LOOP_SUPPORTED` = 4 pi sampling radii (what an eps = 1/2
sample resolves).  A loop just above that bound is resolved by the sampling
condition, but the bound is on lengths only: under scanner noise a tunnel of
outside cells, made by where a few noisy samples happen to lie, can measure
more (nefertiti at 0.3 h, another noise draw: a closed genus-1 surface for a
genus-0 bust, its one handle a loop of 13.6 radii, reported as sure).  What
separates such a tunnel from a real thin handle is not its length but whether
the sample as a whole carries it: a real handle is a feature of the surface,
and a sample of the same surface with some points fewer shows it too; a
tunnel made by particular samples goes when some of them do.

The check
---------
When the robust extension built M_S (not the paper's loop) for a surface in
R^3, every handle that is not already uncertain and whose loop is shorter
than :data:`LOOP_CHECKED` = 8 pi radii (what an eps = 1/4 sample resolves:
a handle above it is resolved with a margin of two in eps, and the check is
not run) is checked: the reconstruction is run again, the same way, on the
samples a fixed random draw keeps with probability :data:`RESAMPLE_KEEP`.
The spacing grows by 1 / sqrt(0.9) - 1, about 5 %, so a loop of 4 pi radii
still measures about 11.9, well above LOOP_MIN = 2 pi: a real handle in the
checked band stays resolved.  If that run gives a closed manifold with fewer
handles, each checked handle with no handle loop of the resample nearby (loop
centroids within :data:`MATCH` times the sum of the two loops' radii: loops
around the same tube) is made uncertain, with the reason.  A resample that
is not a closed manifold, or has as many handles, says nothing against them.
On an open M_S (a surface with boundary: an open scan; since session 44) the
same, with a resample without fins in place of a closed one and handles counted as
handle loops, since an open surface's b1 counts its holes too: the elephant
with a hole cut into it, at 0.1 h, came out open with a false bridge whose
loop measured 20.6 radii, sure, because the check looked at closed results
only.  The check only adds doubt: it never changes M_S, and a handle it leaves
alone stays as it was.  Its cost is one more reconstruction, paid only by
results with a handle in the checked band.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from .dispute import disagreement
from .features import LOOP_SUPPORTED, Feature

#: Loop length (sampling radii) below which a handle not already uncertain is checked: 2 pi / eps at
#: eps = 1/4, twice LOOP_SUPPORTED (its eps = 1/2), as LOOP_SUPPORTED is twice LOOP_MIN (eps = 1).
LOOP_CHECKED = 2 * LOOP_SUPPORTED
#: Share of the samples the resample keeps: the spacing grows by about 5 %, so a loop of LOOP_SUPPORTED
#: radii still measures about 11.9, far above LOOP_MIN; a tunnel carried by a few noisy samples loses
#: one of k of them with probability 1 - 0.9^k.
RESAMPLE_KEEP = 0.9
#: Seed of the draw (the check, like the rest of the pipeline, gives the same answer every run).
RESAMPLE_SEED = 0
#: Two handle loops are around the same tube when their centroids are closer than this many times the
#: sum of their radii (length / 2 pi): a meridian moved along a tube stays within a few tube radii.
MATCH = 2.0

#: A run of the reconstruction on the kept samples: their Betti numbers, whether M_S is a closed manifold
#: (for an open M_S's check: a surface without fins, closed or not), its features, and the samples its
#: features index.
Resampled = tuple[tuple[int, ...], bool, list[Feature], np.ndarray]


def checked(features: list[Feature]) -> list[int]:
    """Indices of the handles the check looks at: not removed, not uncertain, loop under LOOP_CHECKED."""
    return [
        i
        for i, f in enumerate(features)
        if f.kind == "handle" and not f.removed and not f.uncertain and f.size_spacings < LOOP_CHECKED
    ]


def _handle_loops(features: list[Feature]) -> int:
    """The handle loops of M_S among ``features`` (not removed, not disputed: a dispute marks a place)."""
    return sum(f.kind == "handle" and not f.removed and not f.disputed for f in features)


def _uncounted(features: list[Feature]) -> bool:
    """Whether the handles were too many to list (``features()``'s one stand-in handle without samples)."""
    return any(f.kind == "handle" and not f.removed and len(f.vertices) == 0 for f in features)


def _loop(points: np.ndarray, f: Feature) -> tuple[np.ndarray, float]:
    """A handle loop's centroid and radius (length / 2 pi) in the samples' frame."""
    q = points[f.vertices]
    length = float(np.linalg.norm(q - np.roll(q, 1, axis=0), axis=1).sum())
    return q.mean(axis=0), length / (2 * math.pi)


def resample_check(
    points: np.ndarray,
    features: list[Feature],
    betti: tuple[int, ...],
    run: Callable[[np.ndarray], Resampled],
    closed: bool = True,
) -> tuple[list[Feature], str | None]:
    """The features, with the checked handles a resample does not show made uncertain; and a message.

    On an open M_S (a surface with boundary: an open scan), ``closed=False``: the run's second value then
    says whether the resample is a surface without fins (closed or with boundary; the topology report
    counts pinches on closed complexes only), ``betti`` is not used, and handles are counted as the handle
    loops of the features (an open surface's b1 counts its holes too, which a resample may change).  A side
    with more loops than the features list (their one stand-in without samples) says nothing.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
        The samples the features index.
    features : list of Feature
        The result's features (:func:`~.features.features`, with the driver's additions).
    betti : tuple of int
        The result's Betti numbers (closed M_S only).
    run : callable
        Reconstructs the kept samples the same way (without this check) and returns
        :data:`Resampled`.
    closed : bool
        Whether M_S is a closed manifold (else a manifold with boundary).

    Returns
    -------
    features : list of Feature
        A new list; only checked handles can change, and only to uncertain.
    message : str or None
        What the check did, for the topology messages; None when nothing was checked.
    """
    todo = checked(features)
    if not todo:
        return features, None
    keep = np.random.default_rng(RESAMPLE_SEED).random(len(points)) < RESAMPLE_KEEP
    sub_betti, sub_ok, sub_features, sub_points = run(points[keep])
    lengths = ", ".join(f"{features[i].size_spacings:.3g}" for i in todo)
    head = f"resample-check: {len(todo)} handle loop(s) of {lengths} sampling radii (under {LOOP_CHECKED:.3g})"
    if closed:
        handles, sub_handles = sum(betti[1:-1]), sum(sub_betti[1:-1])
        said_sub = f"b1 = {sub_handles}"
    else:
        if _uncounted(features) or _uncounted(sub_features):
            return features, f"{head}; too many loops to count in the reconstruction of {RESAMPLE_KEEP:.0%}: kept"
        handles, sub_handles = _handle_loops(features), _handle_loops(sub_features)
        said_sub = f"{sub_handles} handle loops"
    if not sub_ok or sub_handles >= handles:
        what = ("not a closed manifold" if closed else "a surface with fins") if not sub_ok else said_sub
        return features, f"{head}; the reconstruction of {RESAMPLE_KEEP:.0%} of the samples gives {what}: kept"
    loops = [_loop(sub_points, f) for f in sub_features if f.kind == "handle" and not f.removed]
    out = list(features)
    gone = 0
    for i in todo:
        c, r = _loop(points, features[i])
        if any(np.linalg.norm(c - c2) <= MATCH * (r + r2) for c2, r2 in loops):
            continue
        gone += 1
        out[i] = replace(
            features[i],
            uncertain=True,
            reason=f"{features[i].reason} (rule resample-check: not there when {1 - RESAMPLE_KEEP:.0%} of the "
            "samples are left out, so particular samples, noise perhaps, make it)",
        )
    return out, (
        f"{head}; the reconstruction of {RESAMPLE_KEEP:.0%} of the samples has {said_sub} where this one has "
        f"{handles}"
        + (
            f": {gone} of these loops {'is' if gone == 1 else 'are'} not there, made uncertain"
            if gone
            else ": each of these loops is there too, kept"
        )
    )


def resample_betti(
    points: np.ndarray,
    manifold: np.ndarray,
    betti: tuple[int, ...],
    run: Callable[[np.ndarray], tuple[tuple[int, ...], bool, np.ndarray]],
) -> tuple[list[Feature], str]:
    """``resample-check`` for a closed d-manifold, d >= 3: the same Betti numbers from a tenth fewer samples.

    The features measure the holes, components and (since session 37, :mod:`.tunnels`) the tunnels of a
    d >= 3 result, but not its voids, and a tunnel measured long enough can still be one the sample does not
    decide, or a thin handle can be lost without a loop left to measure.  Where the robust extension built
    it, the reconstruction runs again on the same draw of :data:`RESAMPLE_KEEP` of the samples as for
    surfaces; where that gives a closed manifold with other Betti numbers, the sample does not decide between
    the two, and each differing number is an uncertain feature (:func:`~.dispute.disagreement`, placed where
    the two complexes differ most).  A resample that is no closed manifold says nothing either way.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    manifold : ndarray of shape (m, d + 1)
        M_S, indices into ``points``.
    betti : tuple of int
        Its Betti numbers.
    run : callable
        Reconstructs the kept samples the same way (without this check) and returns their Betti numbers,
        whether M_S is a closed manifold, and M_S on the rows of the samples it was given.

    Returns
    -------
    features : list of Feature
        The uncertain features (empty when the resample agrees).
    message : str
        What the check did, for the topology messages.
    """
    keep = np.random.default_rng(RESAMPLE_SEED).random(len(points)) < RESAMPLE_KEEP
    ids = np.flatnonzero(keep)
    sub_betti, sub_closed, sub_manifold = run(points[keep])
    head = f"resample-check: the reconstruction of {RESAMPLE_KEEP:.0%} of the samples"
    if not sub_closed:
        return [], f"{head} is not a closed manifold: says nothing either way"
    if tuple(sub_betti) == tuple(betti):
        return [], f"{head} has the same Betti numbers {tuple(betti)}"
    found = disagreement(points, manifold, ids[sub_manifold], tuple(betti), tuple(sub_betti))
    return found, f"{head} has Betti numbers {tuple(sub_betti)} where this one has {tuple(betti)}: uncertain"
