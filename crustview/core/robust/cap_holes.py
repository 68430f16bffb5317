"""The holes that ``open-cap``'s caps leave in the report: removed, kept closed, or closed by the other path.

:mod:`.cells` finds the caps (patches of big faces over an opening) and decides them by their ratio to the
faces around them (CAP_RATIO, CAP_SURE, CAP_TYPICAL, documented there).  This module turns what it decided into
features of the result, each an uncertain ``hole``:

* :func:`weak_openings`: a hole ``open-cap`` opened from a cap under CAP_SURE (beside a sure opening);
* :func:`kept_caps`: a cap between CAP_RATIO and CAP_SURE kept closed (no sure opening in the sample);
* :func:`closed_openings`: a sure opening (a cap over CAP_SURE) of the labelled M_S that the grown M_S,
  kept instead (:func:`~.driver.choose`), closes;

all placed at the cap's samples by :func:`cap_hole`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np


def weak_openings(
    feats: list, openings: list[tuple[np.ndarray, float]], how: str = "opened by open-cap", any_ratio: bool = False
) -> list:
    """The features, with every hole whose cap was less than :data:`CAP_SURE` times its ring made uncertain.

    A hole uncertain already for another reason keeps it and is given this one too.

    Parameters
    ----------
    feats : list of Feature
        The features of M_S (:func:`~crustview.core.analysis.features.features`).
    openings : list of (ndarray of int, float)
        Each cap ``open-cap`` removed (or kept closed, for a grown M_S open there): its samples and its
        ratio (:func:`cap_ratios`).
    how : str
        How the hole relates to the cap, for the reason.
    any_ratio : bool
        Every one of ``openings`` makes its holes uncertain, whatever its ratio: open-cap's walls
        (:mod:`.walls`), which show no opening at any size.
    """
    from dataclasses import replace

    from .cells import CAP_SURE

    weak_caps = [(set(v.tolist()), q) for v, q in openings if any_ratio or q < CAP_SURE]
    if not weak_caps:
        return feats
    out = []
    for f in feats:
        on = [q for w, q in weak_caps if w.intersection(f.vertices.tolist())] if f.kind == "hole" else []
        if on:  # also where the hole is uncertain already for another reason: both reasons are said
            q = min(on)
            why = (
                "a patch between two rims the sample shows, no evidence of an opening"
                if any_ratio
                else f"under {CAP_SURE:g}: noise or sparse sampling may have made it"
            )
            f = replace(
                f, uncertain=True, reason=f"{f.reason} ({how}: its cap was {q:.2g} times the faces around it, {why})"
            )
        out.append(f)
    return out


def cap_hole(points: np.ndarray, vs: np.ndarray, nn: np.ndarray, why: Callable[[float], str]):  # noqa: ANN201
    """A cap as an uncertain, removed ``hole`` feature at its samples ``vs``; ``why(size)`` gives the reason.

    Its size is the span of its samples (as for a hole's rim) over their median nearest-neighbour distance:
    a rim's local spacing, the enclosing cover of M_S, would be inflated by the cap's own large faces.
    """
    from ..analysis.features import Feature

    p = points[vs]
    span = float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)) * 2)
    h = float(np.median(nn[vs]))
    size = span / h if h > 0 else math.inf
    return Feature("hole", p.mean(axis=0), size, True, np.asarray(vs, np.int64), why(size), removed=True)


def kept_caps(points: np.ndarray, caps_kept: list[tuple[np.ndarray, float]]) -> list:
    """The caps ``open-cap`` kept closed, as uncertain holes (removed features: not holes of M_S).

    A cap more than :data:`CAP_RATIO` but at most :data:`CAP_SURE` times its ring is one the sample does
    not decide: such caps are mostly what noise makes over closed parts, and some real openings measure
    the same.  Where no cap of the sample is over CAP_SURE (nothing shows it is an open scan), the closed
    answer is the theory's (Algorithm 3 reconstructs closed manifolds; openings are this extension's), so
    the cap stays, and the possible opening is named.  Beside a sure opening such caps are removed
    (:func:`weak_openings` flags their holes): the scan is open, and its real openings may measure as
    little (two ends of a cut tube: 6.0 and 5.9), which a kept cap would span with a ribbon.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    caps_kept : list of (ndarray of int, float)
        Each cap kept: its samples and its ratio (:func:`cap_ratios`).

    Returns
    -------
    list of Feature
        ``kind = "hole"``, ``uncertain``, ``removed``; ``size_spacings`` is the span of the cap's samples
        (as for a hole's rim) over their median nearest-neighbour distance: a rim's local spacing, the
        enclosing cover of M_S, would be inflated here by the cap's own large faces.
    """
    from ..util.nearest import nearest_distances
    from .cells import CAP_RATIO, CAP_SURE

    if not caps_kept:
        return []
    nn = nearest_distances(points)
    out = []
    for vs, q in caps_kept:
        out.append(
            cap_hole(
                points,
                vs,
                nn,
                lambda size, vs=vs, q=q: (
                    f"a possible opening kept closed (rule open-cap): a cap of {len(vs)} "
                    f"samples, {size:.3g} spacings across, its faces {q:.2g} times the size of those around it: more "
                    f"than the {CAP_RATIO:g} a surface's sampling can change by over one radius, less than the "
                    f"{CAP_SURE:g} above which a cap is surely over an opening; noise over a closed part makes such "
                    "caps, and so may a small real opening"
                ),
            )
        )
    return out


def closed_openings(
    points: np.ndarray,
    opened: list[tuple[np.ndarray, float]],
    rim: set[int],
    how: str = "closed in the grown M_S that was kept",
    sure_only: bool = True,
) -> list:
    """The sure openings of the labelled M_S that another M_S closes, as uncertain holes (removed features).

    ``open-cap`` removes a cap more than :data:`CAP_SURE` times larger than its ring: by the same Lipschitz
    bound as CAP_RATIO's, the sample shows an opening there beyond doubt.  When the growing path's M_S is
    kept instead (:func:`~.driver.choose`; :func:`~.verdict.ranked` weighs these openings) and closes that
    opening (``fill-hole`` spans it; none of the cap's samples is on its rim ``rim``), the closed answer spans a
    gap the sample shows: never silently.  ``opened``: the caps still open in the labelled M_S.  Each such
    opening is named where its cap was, as :func:`kept_caps` names a cap kept closed.

    The labelled path asks the same of its own M_S after ``settle`` (:mod:`.cells`): ``fill-hole`` may close an
    opening ``open-cap`` made as a slit (a thin part's rim whose two sides the labelling kept apart looks the
    same as a narrow opening); ``how`` then says so, and ``sure_only=False`` names the caps under CAP_SURE it
    removed beside a sure one too (a cap kept closed in that band is named, :func:`kept_caps`).
    """
    from ..util.nearest import nearest_distances
    from .cells import CAP_SURE

    sure = [(vs, q) for vs, q in opened if (q > CAP_SURE or not sure_only) and not rim.intersection(vs.tolist())]
    if not sure:
        return []
    nn = nearest_distances(points)
    return [
        cap_hole(
            points,
            vs,
            nn,
            lambda size, vs=vs, q=q: (
                f"an opening open-cap made in the labelled M_S (a cap of {len(vs)} samples, {size:.3g} "
                f"spacings across, its faces {q:.2g} times the size of those around it, "
                + (
                    f"over the {CAP_SURE:g} above which a cap is surely over an opening"
                    if q > CAP_SURE
                    else f"beside a cap over the {CAP_SURE:g} above which a cap is surely over an opening"
                )
                + f"), {how}"
            ),
        )
        for vs, q in sure
    ]


def facing_caps(points: np.ndarray, faces: np.ndarray, caps_kept: list[tuple[np.ndarray, float]]) -> list:
    """Pairs of caps ``open-cap`` kept closed that face each other through the solid, as uncertain handles.

    Two possible openings of one closed part, joined by a straight path inside it that crosses no face of M_S,
    may be the two ends of one tunnel whose wall the sample has no points on (a bore sampled only where it meets
    the faces, as CAD meshes are: the held-out pinion's bore, 8 spacings across and 38 long, session 46).  If
    both are openings, the part has one handle more than M_S: named as an uncertain ``handle``, ``removed``
    (not a handle of M_S), at the path's middle, its size the path's length in the caps' spacing.  The path
    runs between the caps' centroids; it is inside when it crosses no face but the caps' own and a ray from its
    middle crosses M_S an odd number of times.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    faces : ndarray of shape (f, 3)
        M_S (closed where the caps are).
    caps_kept : list of (ndarray of int, float)
        Each cap kept closed: its samples and its ratio (:func:`kept_caps`).
    """
    from ..analysis.features import Feature
    from ..util.nearest import nearest_distances

    if len(caps_kept) < 2 or len(faces) == 0:
        return []
    nn = nearest_distances(points)
    tri = points[faces]
    out = []
    for i in range(len(caps_kept)):
        for j in range(i + 1, len(caps_kept)):
            (a, qa), (b, qb) = caps_kept[i], caps_kept[j]
            ca, cb = points[a].mean(axis=0), points[b].mean(axis=0)
            own = np.isin(faces, np.concatenate([a, b])).all(axis=1)
            if (
                len(np.intersect1d(a, b))
                or _hits(tri[~own], ca, cb - ca, 1.0)
                or _hits(tri, (ca + cb) / 2, _RAY) % 2 == 0
            ):
                continue
            unit = float(np.median(nn[np.concatenate([a, b])]))
            size = float(np.linalg.norm(cb - ca)) / unit if unit > 0 else math.inf
            ends = np.array(
                [
                    a[np.argmin(np.linalg.norm(points[a] - ca, axis=1))],
                    b[np.argmin(np.linalg.norm(points[b] - cb, axis=1))],
                ]
            )
            out.append(
                Feature(
                    "handle",
                    (ca + cb) / 2,
                    size,
                    True,
                    ends,
                    f"two possible openings kept closed (rule open-cap, caps {qa:.2g} and {qb:.2g} times their rings) "
                    f"face each other through the solid, {size:.3g} spacings apart: if both are the ends of one tunnel "
                    "whose wall the sample has no points on, the part has one handle more",
                    removed=True,
                )
            )
    return out


#: A direction for the inside test's ray, in general position (no axis, no diagonal).
_RAY = np.array([0.5773502691896258, 0.5345224838248488, 0.6172133998483676])


def _hits(tri: np.ndarray, origin: np.ndarray, direction: np.ndarray, t_max: float = math.inf) -> int:
    """How many triangles ``tri`` (f, 3, 3) the segment or ray ``origin + t direction``, 0 < t < t_max, crosses."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    h = np.cross(direction, e2)
    det = (e1 * h).sum(axis=1)
    scale = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(direction)
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - tri[:, 0]
    u = inv * (s * h).sum(axis=1)
    q = np.cross(s, e1)
    v = inv * (q * direction).sum(axis=1)
    t = inv * (q * e2).sum(axis=1)
    return int((ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < t_max)).sum())
