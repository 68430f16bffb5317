"""Holes the robust extension's own rule calls gaps but could not close: uncertain, whatever their size.

Why
---
``fill-hole`` (:mod:`.fill_hole`) takes a hole of at most FILL_MAX_FACES boundary faces and at most
FILL_MAX_SPAN sample spacings across for an undersampling gap and closes it; larger holes are real
openings.  Where it fails (no Delaunay face, ear, cone or chain fits: the complex is folded there) the
hole stays, and the features (:mod:`crustview.core.analysis.features`) measure it like any other:
above HOLE_SUPPORTED = 4 spacings it is a *sure* opening.  S^3 in R^4 with noise of 3 % of its reach
kept a hole of 24 faces 4.9 spacings across that way: the result said "open", with no doubt, of a
closed sample.  But the extension's own rule had called that hole a gap: its openness is a failure of
the extension, not something the sample shows.

The rule
--------
In a robust result that is not the paper's own, a hole the features call sure is made *uncertain* when
fill-hole's own bounds call it a gap, measured as fill-hole measures: its boundary faces (for d >= 3 only
as a bound on the work, FILL_MAX_FACES squared: the face bound is a surface's rim loop's, and a
3-manifold's rim is a sphere, whose faces grow with the square of its span), and the largest distance
between two of its samples over the larger of their mean nearest-neighbour distance and the sample's
median one; unless ``open-cap`` kept it open as a real opening (the labelled path's ``opened``).  No new
constant: the bounds are fill-hole's.  The check never changes M_S.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..analysis.features import Feature
from ..paper.facets import facet_structure
from ..util.nearest import nearest_distances
from .fill_hole import FILL_MAX_FACES, FILL_MAX_SPAN, gap_span


def unclosed_gaps(
    points: np.ndarray, manifold: np.ndarray, feats: list[Feature], openings: list, spacing: float
) -> list[Feature]:
    """``feats`` with each sure hole that fill-hole's bounds call a gap made uncertain (module docstring).

    Parameters
    ----------
    points : ndarray of shape (n, k)
    manifold : ndarray of shape (s, d + 1)
        M_S, d >= 2.
    feats : list of Feature
    openings : list of (ndarray of int, float)
        The openings ``open-cap`` kept open (their samples first); a hole on their samples stays as it is.
    spacing : float
        The sample's median nearest-neighbour distance (fill-hole's ``spacing``).
    """
    opened = [set(np.asarray(o[0]).tolist()) for o in openings]
    # the openings open-cap kept are real boundary: only the other sure holes are measured
    sure = [
        i
        for i, f in enumerate(feats)
        if f.kind == "hole"
        and not f.uncertain
        and not f.removed
        and len(f.vertices) >= 2
        and not any(o.intersection(np.asarray(f.vertices).tolist()) for o in opened)
    ]
    if not sure or len(manifold) == 0:
        return feats
    simplices = np.asarray(manifold, dtype=np.int64)
    d = simplices.shape[1] - 1
    faces, facet_of, _, _ = facet_structure(simplices)
    rim = faces[np.bincount(facet_of.ravel(), minlength=len(faces)) == 1]
    nn = None
    out = list(feats)
    for i in sure:
        f = feats[i]
        vs = np.asarray(f.vertices, dtype=np.int64)
        n_faces = int(np.isin(rim, vs).all(axis=1).sum())
        # counted first: a long rim is a real opening, and pdist is quadratic.  The face bound is a surface's
        # (50 rim edges: a loop some 16 spacings across); a 3-manifold's rim is a sphere whose face count grows
        # with the square of its span (S^3 at 3 % of its reach, 1,200 samples: a hole of 156 faces 6.5
        # spacings across, reported sure), so there the span bound alone decides, with a bound on the work
        if n_faces == 0 or n_faces > (FILL_MAX_FACES if d == 2 else FILL_MAX_FACES**2):
            continue
        if nn is None:
            nn = nearest_distances(points)  # the merging's, where nothing merged (reconstruct kept them)
        span, local = gap_span(points, vs, nn, spacing)
        span /= local
        if span <= FILL_MAX_SPAN:
            out[i] = replace(
                f,
                uncertain=True,
                reason=f"{f.reason} (by fill-hole's own measure, {n_faces} faces and {span:.3g} nearest-neighbour "
                + (
                    f"spacings across, within its bounds for a sampling gap, {FILL_MAX_FACES} faces and "
                    f"{FILL_MAX_SPAN:g} spacings; it could not close it (a fold of M_S there, or no closing its "
                    "rules try)"
                    if n_faces <= FILL_MAX_FACES
                    else f"spacings across, within the {FILL_MAX_SPAN:g} it takes for a sampling gap; its rim of "
                    "more faces than it closes"
                )
                + ": the opening may be the extension's, not the object's)",
            )
    return out
