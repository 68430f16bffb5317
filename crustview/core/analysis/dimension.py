"""An estimate of the intrinsic dimension d of a sample (``crustview reconstruct -d auto``).

Local PCA: at up to :data:`MAX_CENTRES` evenly chosen samples, the
covariance of the nearest neighbours has eigenvalues
``l_1 >= ... >= l_k``, taken as shares of their sum and floored at
:data:`NOISE_FLOOR`.  Near a smooth d-manifold the first d are of the
order of the neighbourhood's radius squared and the others much smaller
(curvature and noise), so each centre votes for the d in ``1 .. k-1`` with
the largest gap ``l_d / l_(d+1)``.  This is done at
several neighbourhood sizes; the estimate is the d with the most votes over
all of them, and its *confidence* is that share of the votes.  A sample in
R^2 gets d = 1 with confidence 1, the only dimension there is to reconstruct:
no estimate, and its sentence says so (points filling a square get it too).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from ..util.vectors import power_of_two_above

#: At most this many centres of local PCA (evenly spread over the input order).
MAX_CENTRES = 600
#: Neighbourhood sizes, as multiples of k (at least :data:`MIN_NEIGHBOURS`): small, so that curvature stays small.
SCALES = (2, 4)
#: The fewest neighbours of a centre.
MIN_NEIGHBOURS = 6
#: Local variance below this share of the total is taken as noise (the spectrum is floored there).
NOISE_FLOOR = 0.01
#: A d the user gave is questioned (:func:`contradiction`) when more than this share of the local votes chose
#: one other d: a majority of the centres and neighbourhood sizes sees another dimension, not a split vote.
CONTRADICTION_SHARE = 0.5


@dataclass(frozen=True)
class DimensionEstimate:
    """The estimated intrinsic dimension and why.

    Attributes
    ----------
    d : int
    confidence : float
        Share of all local votes (every centre at every scale) that chose ``d``.
    votes : dict of int to float
        Share of the votes for each candidate d.
    gap : float
        Median ratio ``l_d / l_(d+1)`` of the local spectra at the chosen d.
    neighbours : tuple of int
        The neighbourhood sizes used.
    centres : int
    samples_d : int or None
        Local PCA's own choice where a mesh file's faces overruled it (:func:`with_faces`); None otherwise.
    """

    d: int
    confidence: float
    votes: dict[int, float] = field(default_factory=dict)
    gap: float = float("inf")
    neighbours: tuple[int, ...] = ()
    centres: int = 0
    #: What local PCA of the samples chose where a mesh file's faces overruled it (:func:`with_faces`), else None.
    samples_d: int | None = None

    def sentence(self) -> str:
        """What was chosen and why, in one sentence."""
        if self.samples_d is not None:
            word = {1: "a curve", 2: "a surface"}.get(self.d, f"a {self.d}-manifold")
            return (
                f"d = {self.d} ({word}), taken from the file's faces: local PCA of the vertices alone found "
                f"{self.samples_d} large direction{'s' if self.samples_d > 1 else ''} "
                f"({100 * self.votes.get(self.samples_d, 0.0):.0f}% of the votes), a d the faces do not fit, as the "
                "vertices of a mesh tessellated in long thin faces along lines (a CAD part meshed on its edges) can."
            )
        if not self.neighbours:
            return (
                f"d = {self.d} (a curve): in R^2 the only dimension there is to reconstruct "
                "(not an estimate: whether the points lie on a curve is not checked)."
            )
        word = {1: "a curve", 2: "a surface"}.get(self.d, f"a {self.d}-manifold")
        others = ", ".join(f"d = {d}: {100 * v:.0f}%" for d, v in sorted(self.votes.items()) if d != self.d and v > 0)
        level = "high" if self.confidence >= 0.8 else "moderate" if self.confidence >= 0.6 else "low"
        return (
            f"d = {self.d} ({word}), {level} confidence {100 * self.confidence:.0f}%: local PCA at {self.centres} "
            f"samples with {'/'.join(map(str, self.neighbours))} neighbours finds {self.d} large "
            f"direction{'s' if self.d > 1 else ''} "
            f"(median gap {self.gap:.0f}x to the next)" + (f"; other votes {others}" if others else "") + "."
        )

    def as_dict(self) -> dict:
        return {
            "d": self.d,
            "confidence": self.confidence,
            "votes": {str(d): v for d, v in sorted(self.votes.items())},
            "median_gap": self.gap,
            "neighbours": list(self.neighbours),
            "centres": self.centres,
            "method": "local PCA, largest eigenvalue gap, votes over centres and neighbourhood sizes",
            **({} if self.samples_d is None else {"decided_by": "the file's faces", "local_pca_d": self.samples_d}),
        }


def with_faces(estimate: DimensionEstimate, fitting: list[int]) -> DimensionEstimate:
    """The estimate, or the dimension of a mesh file's faces where local PCA chose one they cannot have.

    A mesh's polygons are its own statement of d (their vertices are the sample, the polygons the surface
    through it).  Local PCA sees only the vertices, and a mesh tessellated in long thin faces has its vertices
    on lines (a CAD part meshed on its edges: a held-out gear's vertices voted 98 % for d = 1, and its
    triangles then fitted no curve).  Where the faces fit exactly one d (:meth:`MeshData.fitting_dimensions
    <crustview.meshfiles.mesh.MeshData.fitting_dimensions>`) and the estimate is another, that d is taken, with
    confidence 1 and the estimate's own votes kept; where they fit several, the one nearest the estimate.

    Parameters
    ----------
    estimate : DimensionEstimate
        Local PCA's estimate (:func:`estimate_dimension`).
    fitting : list of int
        The d the file's faces fit (empty: no faces, the estimate stands).
    """
    if not fitting or estimate.d in fitting:
        return estimate
    d = min(fitting, key=lambda f: (abs(f - estimate.d), -f))
    return replace(estimate, d=d, confidence=1.0, samples_d=estimate.d)


def estimate_file_dimension(points: np.ndarray, mesh: object | None = None) -> DimensionEstimate:
    """:func:`estimate_dimension` of a file's points, overruled by its faces (:func:`with_faces`) if it has any.

    The one place ``-d auto``, ``view -d auto`` and the window's suggestion take d from.  ``mesh``: the
    file's :class:`~crustview.meshfiles.mesh.MeshData` (its ``fitting_dimensions()``), or None for a point file.
    """
    estimate = estimate_dimension(points)
    return estimate if mesh is None else with_faces(estimate, mesh.fitting_dimensions())  # type: ignore[attr-defined]


def estimate_dimension(points: np.ndarray, *, distinct: bool = False) -> DimensionEstimate:
    """Estimate the intrinsic dimension of a sample (see the module docstring).

    Parameters
    ----------
    points : ndarray of shape (n, k)
    distinct : bool
        The points are known to be distinct (a reconstruction's merged samples): they are not made unique
        again, which at a million points took most of the time.

    Returns
    -------
    DimensionEstimate

    Raises
    ------
    InputError
        When there are too few distinct points to estimate d.
    """
    pts = np.asarray(points, dtype=np.float64)
    if not distinct:
        pts = np.unique(pts, axis=0)
    n, k = pts.shape
    if k < 2:
        raise InputError(f"Cannot estimate d: points need at least 2 coordinates, these have {k}.")
    if k == 2:
        return DimensionEstimate(1, 1.0, {1: 1.0})
    if n < k + 2:
        raise InputError(f"Cannot estimate d from {n} distinct points in R^{k}: give -d.")
    # divided by a power of two (exact, as prepare's prescale): the covariances of points near 1e-300
    # underflowed to 0 (every sample voted d = 1) and those near 1e300 overflowed
    top = float(np.abs(pts).max())
    if np.isfinite(top) and top > 0:
        pts = pts / power_of_two_above(top)
    sizes = tuple(sorted({min(n - 1, max(MIN_NEIGHBOURS, s * k)) for s in SCALES}))
    centres = np.linspace(0, n - 1, min(n, MAX_CENTRES)).astype(np.intp)
    tree = cKDTree(pts)
    _, idx = tree.query(pts[centres], k=sizes[-1] + 1)
    votes = np.zeros(k, dtype=np.int64)  # votes[d] for d in 1 .. k-1
    gaps: dict[int, list[float]] = {}
    for size in sizes:
        nb = pts[idx[:, : size + 1]]
        nb = nb - nb.mean(axis=1, keepdims=True)
        cov = np.einsum("mij,mik->mjk", nb, nb) / size
        ev = np.linalg.eigvalsh(cov)[:, ::-1]  # descending
        ev = ev / np.maximum(ev.sum(axis=1, keepdims=True), 1e-300)
        logs = np.log(np.maximum(ev, NOISE_FLOOR))
        jump = logs[:, :-1] - logs[:, 1:]  # jump[:, d-1] = log(l_d / l_(d+1)), d = 1 .. k-1
        choice = np.argmax(jump, axis=1) + 1
        np.add.at(votes, choice, 1)
        for d in range(1, k):
            gaps.setdefault(d, []).extend(np.exp(jump[choice == d, d - 1]).tolist())
    total = int(votes.sum())
    d = int(np.argmax(votes[1:]) + 1)
    shares = {int(i): float(votes[i] / total) for i in range(1, k)}
    gap = float(np.median(gaps[d])) if gaps.get(d) else float("inf")
    return DimensionEstimate(d, shares[d], shares, gap, sizes, len(centres))


def contradiction(
    points: np.ndarray, d: int, mesh: object | None = None, *, distinct: bool = False
) -> DimensionEstimate | None:
    """Local PCA's estimate (:func:`estimate_dimension`) where it contradicts a given ``d``; else None.

    A contradiction is an estimate of another d that a majority of the local votes chose (more than
    :data:`CONTRADICTION_SHARE`).  None where no estimate is made (fewer than k + 2 distinct points, or
    points in the plane, where there is one dimension to reconstruct), and for a mesh file whose faces fit
    ``d``: its faces are its own statement of d (:func:`with_faces`).  ``distinct``: as for
    :func:`estimate_dimension`.  The reconstruction runs with the given d either way; this is what a result
    says about it.
    """
    if mesh is not None and d in mesh.fitting_dimensions():  # type: ignore[attr-defined]
        return None
    try:
        est = estimate_dimension(points, distinct=distinct)
    except InputError:
        return None
    if est.d == d or not est.neighbours or est.confidence <= CONTRADICTION_SHARE:
        return None
    return est
