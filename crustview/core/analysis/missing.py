"""Samples that M_S does not reach, reported as uncertain features.

A result can be a closed manifold of some genus and still leave out a piece
of the object: the samples of a thin part the extraction could not take in
(an elk's antler sampled at a quarter of its density: 127 samples left out of
a closed genus-0 result, for a genus-1 toy).  Its topology says nothing about
the part it lacks, so a cluster of left-out samples is a feature the result
is not sure of.

* Two left-out samples closer than :data:`~.features.GAP_MIN` spacings cannot
  be told apart from one piece (the components' bound): they are one cluster.
  The spacing is the surface's own there, as ``insert-sample`` measures it
  (:data:`~crustview.core.robust.insert_sample.INSERT_MAX`): the larger of the
  sample's median nearest-neighbour distance and the median nearest-neighbour
  distance of the :data:`SURFACE_NEAREST` vertices of M_S nearest to the
  left-out sample (of a pair, the larger of the two).  Not the left-out
  sample's own nearest-neighbour distance: a lone outlier's is far, and would
  join it to anything.  Where the density varies (a scanner's falls with
  distance), the median alone split the samples of a thin part the result
  lacked at the sparse end into lone samples, none reported: a trident's tip
  sampled at a quarter of the density, 7 samples 1.8-10 median spacings apart
  and 6-15 from M_S, where the surface's samples were 2.4 apart (held-out
  probe ``bench_scans.py --gradient 0.25 --seed 3``, neptune at 0.1 h).
* A cluster of at least d + 1 samples (a d-simplex's worth: the smallest piece
  of a d-manifold that samples can carry) is reported, as an uncertain
  ``component`` at its centroid, its size the cluster's span in spacings.
  Fewer samples are outliers or noise, named in the report's left-out list
  and not here.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..util.nearest import nearest_distances
from .features import GAP_MIN, Feature
from .topology import graph_components

#: Nearest left-out samples each one is linked to (within reach): the features' component gaps' 16
#: (a sample's own ring and, at a contact, the other side).
LINKS = 16
#: Vertices of M_S nearest to a left-out sample whose median nearest-neighbour distance is the surface's spacing
#: there (``insert-sample``'s 8: the sample's own ring of neighbours on a surface, about 6, and a few beyond).
SURFACE_NEAREST = 8


def _surface_spacing(
    points: np.ndarray, vertices: np.ndarray, ids: np.ndarray, nn: np.ndarray, floor: float
) -> np.ndarray:
    """Per sample in ``ids``: the median nearest-neighbour distance of the nearest vertices, at least ``floor``."""
    if len(vertices) == 0:
        return np.full(len(ids), floor)
    k = min(SURFACE_NEAREST, len(vertices))
    _, near = cKDTree(points[vertices]).query(points[ids], k=k)
    near = np.asarray(near).reshape(len(ids), k)
    return np.maximum(np.median(nn[vertices[near]], axis=1), floor)


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
    if len(out_ids) < d + 1 or n < 2 or not used.any():
        # an empty M_S lacks everything: no part of it is a feature (its verdict, FAILED, says so)
        return []
    # the unit: the surface's own spacing near each left-out sample, never below the sample's median
    # (not the sample's own nearest-neighbour distance: a lone outlier's is far, and would join it to anything)
    nn = nearest_distances(points)
    unit = float(np.median(nn[nn > 0])) if (nn > 0).any() else 1.0
    local = _surface_spacing(points, np.flatnonzero(used), out_ids, nn, unit)
    # each left-out sample linked to its LINKS nearest left-out samples within reach: bounded work however
    # large the reach (one radius for all, or all pairs within it, grows with the square of a dense left-out
    # patch beside a sparse M_S); a chain of nearer links joins what a farther pair within reach would
    m = len(out_ids)
    k = min(m, LINKS + 1)
    dist, idx = cKDTree(points[out_ids]).query(points[out_ids], k=k)
    dist, idx = dist.reshape(m, k), idx.reshape(m, k)
    rows = np.repeat(np.arange(m), k)
    cols = idx.ravel()
    reach = GAP_MIN * np.maximum(local[rows], local[cols])
    keep = (cols != rows) & (dist.ravel() < reach)
    _, label = graph_components(m, np.stack([rows[keep], cols[keep]], axis=1))
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
