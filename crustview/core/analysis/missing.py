"""Samples that M_S does not reach, reported as uncertain features.

A result can be a closed manifold of some genus and still leave out a piece
of the object: the samples of a thin part the extraction could not take in
(an elk's antler sampled at a quarter of its density: 127 samples left out of
a closed genus-0 result, for a genus-1 toy).  Its topology says nothing about
the part it lacks, so a cluster of left-out samples is a feature the result
is not sure of.

* Two left-out samples closer than :data:`~.features.GAP_MIN` spacings (the
  sample's median nearest-neighbour distance) cannot be told apart from one
  piece (the components' bound): they are one cluster.
* A cluster of at least d + 1 samples (a d-simplex's worth: the smallest piece
  of a d-manifold that samples can carry) is reported, as an uncertain
  ``component`` at its centroid, its size the cluster's span in spacings.
  Fewer samples are outliers or noise, named in the report's left-out list
  and not here.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..util.nearest import nearest_distances
from .features import GAP_MIN, Feature


def left_out(points: np.ndarray, simplices: np.ndarray, d: int) -> list[Feature]:
    """One uncertain feature per cluster of at least d + 1 samples that are in no simplex.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (s, d + 1)
        M_S.
    d : int
        Its dimension.

    Returns
    -------
    list of Feature
        Kind ``component``, uncertain, the cluster's samples as ``vertices``.
    """
    n = len(points)
    used = np.zeros(n, bool)
    used[np.asarray(simplices, dtype=np.int64).ravel()] = True
    out_ids = np.flatnonzero(~used)
    if len(out_ids) < d + 1 or n < 2:
        return []
    # the unit: the sample's median nearest-neighbour spacing (a lone outlier's own nearest
    # neighbour is far, and would join it to anything)
    nn = nearest_distances(points)
    unit = float(np.median(nn[nn > 0])) if (nn > 0).any() else 1.0
    pairs = cKDTree(points[out_ids]).query_pairs(GAP_MIN * unit, output_type="ndarray").reshape(-1, 2)
    m = len(out_ids)
    graph = coo_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    result = []
    for c in np.flatnonzero(np.bincount(label) >= d + 1).tolist():
        ids = out_ids[label == c]
        p = points[ids]
        span = float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)) * 2) / unit
        reason = (
            f"{len(ids)} samples that M_S does not reach, {span:.3g} spacings across: "
            "a part of the object the result may lack"
        )
        result.append(Feature("component", p.mean(axis=0), span, True, ids, reason))
    return result
