"""Holes of a reconstructed d-manifold, d >= 3 (S^3 in R^4): the surfaces' hole rule in any dimension.

:mod:`.features` measures a surface's holes by their rim loops; a 3-manifold's hole has a rim that is a
2-sphere of boundary faces instead, and the same span and bounds apply (see :func:`holes_of_solids`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .features import HOLE_SUPPORTED, LOOP_MIN, Feature


def holes_of_solids(points: np.ndarray, simplices: np.ndarray, h: np.ndarray) -> list[Feature]:
    """The holes of a d-complex, d >= 3: its boundary (d - 1)-faces, grouped by shared vertices, and their span.

    The surfaces' rule (:func:`_holes`) in any dimension: a hole's rim is here a (d - 1)-sphere of faces
    in one d-simplex each instead of a loop of edges, and its span (twice the largest distance of a rim
    sample from the rim's mean) over the median local spacing of the rim's samples is measured against
    the same bounds.  A span below LOOP_MIN / pi = 2 spacings is one missing sample; below
    :data:`HOLE_SUPPORTED` = 4 only a sample coarser than eps = 1/2 resolves it, and the hole is
    uncertain.  (S^3 in R^4 with noise of 3 % of its reach: four holes of 8-24 faces, 2-3 spacings
    across, left where ``fill-hole`` found no cone: the result was open and listed nothing.)
    """
    simplices = np.asarray(simplices, dtype=np.int64)
    w = simplices.shape[1]
    n = len(points)
    if len(simplices) == 0 or w < 4:
        return []
    srt = np.sort(simplices, axis=1)
    facets = np.concatenate([np.delete(srt, j, axis=1) for j in range(w)])
    rows, count = np.unique(facets, axis=0, return_counts=True)
    rim = rows[count == 1]
    if len(rim) == 0:
        return []
    # the faces of one hole share vertices: each face's vertices joined to its first
    a = np.repeat(rim[:, 0], w - 2)
    b = rim[:, 1:].ravel()
    g = coo_matrix((np.ones(len(a), np.int8), (a, b)), shape=(n, n))
    _, label = connected_components(g, directed=False)
    lab = label[rim[:, 0]]
    result = []
    for c in np.unique(lab).tolist():
        vs = np.unique(rim[lab == c])
        p = points[vs]
        span = float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)) * 2)
        size = span / float(np.median(h[vs]))
        unc = size < HOLE_SUPPORTED
        reason = f"hole with {int((lab == c).sum())} boundary faces, {size:.3g} spacings across" + (
            " (as wide as one missing sample: may be a gap)"
            if size < LOOP_MIN / math.pi
            else " (narrower than 4 spacings: only a sample coarser than eps = 1/2 resolves it, so it may be a gap)"
            if unc
            else ""
        )
        result.append(Feature("hole", p.mean(axis=0), size, unc, vs, reason))
    return result
