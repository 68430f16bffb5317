"""Two d-complexes compared simplex by simplex: in both, only in A, only in B; and their Hausdorff distance.

The complexes may live on different point arrays (a saved result and a mesh
file, say): B's vertices are matched to A's when they are the same points
(within a tolerance relative to A's size).  When they are not, only the
Hausdorff distance is meaningful and the counts are None.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..result import TopologyReport
from .compare import HausdorffEstimate, hausdorff
from .topology import analyse

#: Vertices closer than this times the diameter of A count as the same point.
MATCH_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ComplexDiff:
    """The result of :func:`diff_complexes`.

    Attributes
    ----------
    points : ndarray of shape (n, k)
        The vertices both complexes index (A's, then B's unmatched ones).
    both, only_a, only_b : ndarray of shape (m, d + 1)
        Sorted vertex rows.  Empty when the vertices could not be matched.
    matched : bool
        Whether B's vertices are A's points.
    hausdorff : HausdorffEstimate
    topology_a, topology_b : TopologyReport
    """

    points: np.ndarray
    d: int
    both: np.ndarray
    only_a: np.ndarray
    only_b: np.ndarray
    matched: bool
    hausdorff: HausdorffEstimate
    topology_a: TopologyReport
    topology_b: TopologyReport

    def counts(self) -> dict:
        """JSON-serialisable counts, distances and topologies."""

        def top(t: TopologyReport) -> dict:
            return {
                "closed_manifold": bool(t.closed_manifold),
                "betti": [int(b) for b in t.betti],
                "simplices": int(t.n_simplices),
            }

        h = self.hausdorff
        return {
            "matched_vertices": self.matched,
            "both": len(self.both) if self.matched else None,
            "only_a": len(self.only_a) if self.matched else None,
            "only_b": len(self.only_b) if self.matched else None,
            "hausdorff": h.distance,
            "a_to_b": h.a_to_b,
            "b_to_a": h.b_to_a,
            "hausdorff_error_bound": h.error_bound,
            "topology_a": top(self.topology_a),
            "topology_b": top(self.topology_b),
        }


def _rows(s: np.ndarray, d: int) -> np.ndarray:
    s = np.sort(np.asarray(s, dtype=np.int64).reshape(-1, d + 1), axis=1)
    return np.unique(s, axis=0) if len(s) else s


def _setdiff(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""(a ∩ b, a \\ b, b \\ a) of sorted unique rows."""
    if len(a) == 0 or len(b) == 0:
        return a[:0], a, b
    both = np.concatenate([a, b])
    uniq, inv, counts = np.unique(both, axis=0, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    in_both = counts[inv] == 2
    na = len(a)
    return a[in_both[:na]], a[~in_both[:na]], b[~in_both[na:]]


def match_vertices(pa: np.ndarray, pb: np.ndarray) -> np.ndarray | None:
    """Row of ``pa`` equal to each row of ``pb`` (within :data:`MATCH_TOLERANCE`), or None if any has none."""
    if pa.shape[1] != pb.shape[1]:
        return None
    if pa.shape == pb.shape and np.array_equal(pa, pb):
        return np.arange(len(pb))
    scale = float(np.ptp(pa, axis=0).max()) or 1.0
    dist, idx = cKDTree(pa).query(pb)
    return idx if np.all(dist <= MATCH_TOLERANCE * scale) else None


def diff_complexes(pa: np.ndarray, a: np.ndarray, pb: np.ndarray, b: np.ndarray, d: int) -> ComplexDiff:
    """Compare complex ``a`` on points ``pa`` with complex ``b`` on points ``pb``.

    Parameters
    ----------
    pa, pb : ndarray of shape (n_a, k), (n_b, k)
    a, b : ndarray of shape (m_a, d + 1), (m_b, d + 1)
        Simplices as rows of ``pa`` and ``pb``.
    d : int

    Returns
    -------
    ComplexDiff
    """
    pa, pb = np.asarray(pa, float), np.asarray(pb, float)
    if pa.shape[1] != pb.shape[1]:
        raise ValueError(f"A is in R^{pa.shape[1]} and B in R^{pb.shape[1]}: nothing to compare")
    ra = _rows(a, d)
    m = match_vertices(pa, pb)
    if m is not None:
        points = pa
        rb = _rows(m[np.asarray(b, dtype=np.int64)], d)
        both, only_a, only_b = _setdiff(ra, rb)
    else:
        points = np.concatenate([pa, pb])
        rb = _rows(np.asarray(b, dtype=np.int64) + len(pa), d)
        both = only_a = only_b = ra[:0]
    return ComplexDiff(
        points,
        d,
        both,
        only_a,
        only_b,
        m is not None,
        hausdorff(points, ra, rb),
        analyse(ra, len(points), d),
        analyse(rb, len(points), d),
    )
