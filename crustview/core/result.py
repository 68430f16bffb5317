"""Containers for everything a reconstruction computes.

The viewer only displays what these objects hold, so every intermediate
product of Algorithms 1-3 is kept here.  All coordinates are in the ambient
space R^k of the *input* (original scale, not the centred/scaled working
frame used for Qhull).

Index conventions
-----------------
* ``points`` are the unique samples after duplicate merging; every simplex
  array (``faces``, ``manifold`` ...) indexes into ``points``.
* ``input_index[i]`` is the row of ``points`` that input row ``i`` was merged
  into; ``point_input[j]`` is the first input row of point ``j``.
* Delaunay vertices are the ``n`` samples followed by the far bounding points
  (``delaunay_points``).  ``delaunay_simplices`` index into that array.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np

from .steps import Extraction

#: Names of the two candidate tests of Algorithm 2.
CANDIDATE_TESTS = ("cocone", "cocone-all", "literal")

#: Extraction modes: the paper's Algorithm 3 as printed, and the robust extension.
EXTRACTION_MODES = ("robust", "paper")


class CandidateAngles(Mapping):
    """The three tests' angles, with the cocone ones derived from the per-vertex angles.

    ``"cocone"`` and ``"cocone-all"`` are the minimum and maximum of
    ``vertex_angles`` over each face's vertices.  They are computed on first
    access and kept, so a run that extracts with one of them never holds the
    other (one float64 per Delaunay face: 70 MB at 300,000 samples).

    Parameters
    ----------
    literal : ndarray of shape (f,)
    vertex_angles : ndarray of shape (f, d + 1)
    """

    #: Per-face reductions of the vertex angles; column by column, which is
    #: several times faster than an axis-1 reduction over a narrow (f, d+1) array.
    _DERIVED = {"cocone": np.minimum, "cocone-all": np.maximum}

    def __init__(self, literal: np.ndarray, vertex_angles: np.ndarray, cocone: np.ndarray | None = None) -> None:
        self._values: dict[str, np.ndarray] = {"literal": literal}
        if cocone is not None:  # made beside the vertex angles (cocone_angles(..., minimum=)): the same values
            self._values["cocone"] = cocone
        self._vertex = vertex_angles

    def __getitem__(self, test: str) -> np.ndarray:
        got = self._values.get(test)
        if got is None:
            if test not in self._DERIVED:
                raise KeyError(test)
            got = np.empty(len(self._vertex))
            fold_columns(self._DERIVED[test], self._vertex, got)
            self._values[test] = got
        return got

    def __iter__(self) -> Iterator[str]:
        return iter(("cocone", "cocone-all", "literal"))

    def __len__(self) -> int:
        return 3


def fold_columns(fold: np.ufunc, values: np.ndarray, out: np.ndarray) -> None:
    """``fold`` (``np.minimum``, ``np.maximum``) of each row of ``values`` (f, c) into ``out`` (f,), column by column.

    Several times faster than an axis-1 reduction over a narrow array; the minimum and maximum are exact, so
    any order of the columns gives the same values (the scoring threads fold their rows with it as they go).
    """
    np.copyto(out, values[:, 0])
    for c in range(1, values.shape[1]):
        fold(out, values[:, c], out=out)


@dataclass
class Candidates:
    """All Delaunay d-faces among the samples and both tests' verdicts.

    Attributes
    ----------
    faces : ndarray of shape (f, d + 1)
        Every Delaunay d-face whose vertices are all samples (sorted rows).
    angles : mapping of str to ndarray of shape (f,)
        The deciding angle of each test, radians.  ``"literal"``: the smallest
        over the face's vertices s of the angle between the dual Voronoi
        (k-d)-cell and AN_s.  ``"cocone"`` / ``"cocone-all"``: the smallest /
        largest over the vertices s of the smallest angle between ``y - s``
        and AT_s over points y of the dual cell (``vertex_angles`` holds the
        per-vertex values).  A face is admitted by a test when its angle <
        ``theta``.
    theta : float
        Threshold used for :attr:`mask`.
    vertex_angles : ndarray of shape (f, d + 1), optional
        Cocone angle of each face at each of its vertices.
    """

    faces: np.ndarray
    angles: Mapping[str, np.ndarray]
    theta: float
    vertex_angles: np.ndarray | None = None

    def mask(self, test: str, theta: float | None = None) -> np.ndarray:
        """Faces admitted by ``test`` at threshold ``theta`` (default: own)."""
        t = self.theta if theta is None else theta
        return self.angles[test] < t

    def select(self, test: str, theta: float | None = None) -> np.ndarray:
        """Rows of :attr:`faces` admitted by ``test``."""
        return self.faces[self.mask(test, theta)]


@dataclass
class TopologyReport:
    """What the extracted complex is, topologically.

    Attributes
    ----------
    n_simplices : int
    closed_manifold : bool
        Every (d-1)-face in exactly two d-simplices and every vertex link a
        (d-1)-sphere (checked as: connected closed pseudo-manifold with the
        Euler characteristic of S^(d-1); exact for d <= 3).
    boundary_faces, nonmanifold_faces : int
        (d-1)-faces in one, resp. more than two, d-simplices.
    singular_vertices : int
        Vertices whose link is not a (d-1)-sphere.
    unused_samples : int
        Samples that are not vertices of the complex (paper: must be 0).
    betti : tuple of int
        Z/2 Betti numbers b_0..b_d.
    euler : int
    orientable : bool or None
        Whether the simplices can be oriented consistently across every (d-1)-face they share (a
        boundary face asks nothing: a disc is orientable, a Moebius band is not).  None when a
        (d-1)-face lies in more than two simplices.
    components : int
    messages : list of str
        Sentences for the user (e.g. undersampling diagnosis).
    """

    n_simplices: int
    closed_manifold: bool
    boundary_faces: int
    nonmanifold_faces: int
    singular_vertices: int
    unused_samples: int
    betti: tuple[int, ...]
    euler: int
    orientable: bool | None
    components: int
    messages: list[str] = field(default_factory=list)

    def as_dict(self) -> dict:
        return {
            "n_simplices": self.n_simplices,
            "closed_manifold": self.closed_manifold,
            "boundary_faces": self.boundary_faces,
            "nonmanifold_faces": self.nonmanifold_faces,
            "singular_vertices": self.singular_vertices,
            "unused_samples": self.unused_samples,
            "betti": list(self.betti),
            "euler": self.euler,
            "orientable": self.orientable,
            "components": self.components,
            "messages": list(self.messages),
        }


@dataclass
class Reconstruction:
    """Everything one run of the generalized crust algorithm produced.

    Attributes
    ----------
    d, k : int
        Intrinsic and ambient dimension.
    input_points : ndarray of shape (n_in, k)
    input_index : ndarray of shape (n_in,)
        Row of ``points`` each input row was merged into.
    points : ndarray of shape (n, k)
        Unique samples.
    point_input : ndarray of shape (n,)
        First input row of each sample.
    spacing : float
        Median nearest-neighbour distance of the samples.
    joggle : float
        Size of the deterministic perturbation applied before Qhull (ambient
        units); 0 when none was applied.
    subspace_dim : int
        Dimension of the affine hull of the samples (``k`` unless flat).
    bounding_points : ndarray of shape (b, k)
        Far points added so that every Voronoi cell of a sample is bounded.
    delaunay_simplices : ndarray of shape (t, r + 1)
        Delaunay simplices (r = subspace_dim) over ``delaunay_points``.
    voronoi_vertices : ndarray of shape (t + h, k)
        Circumcentre of each Delaunay simplex, followed by one drawable
        representative of the vertex at infinity of each of the h samples on
        the convex hull (their cells are unbounded; see ``core.normals``).
    pole_index : ndarray of shape (n, k - d)
        Rows of ``voronoi_vertices`` chosen by Algorithm 1, in greedy order.
        When the samples span a lower-dimensional affine subspace the last
        ``k - subspace_dim`` entries are -1: those normal directions are the
        subspace's orthogonal complement (no finite pole).
    normals : ndarray of shape (n, k, k - d)
        Orthonormal basis (columns) of AN_s.
    tangents : ndarray of shape (n, k, d)
        Orthonormal basis (columns) of AT_s.
    candidates : Candidates
    test : str
        Candidate test used for the extraction (``"cocone"`` or ``"literal"``).
    theta : float
    extraction : Extraction
    manifold : ndarray of shape (m, d + 1)
        M_S, the final complex.
    topology : TopologyReport
    timings : dict of str to float
        Seconds per stage.
    prune_boundary : bool
        Whether Algorithm 3 pruned boundary faces (the paper; default).
    mode : str
        ``"robust"`` (default: the paper's Algorithm 3, and the extension of
        :mod:`crustview.core.robust.driver` when the paper's loop cannot give a
        closed manifold through every sample) or ``"paper"``.
    delaunay_backend : str
        The Delaunay code that ran (:func:`.delaunay.backend_label`); empty
        for results made before it was recorded.
    normals_method : str
        ``"paper"`` (Algorithm 1 as printed) or ``"smoothed"``
        (:mod:`crustview.core.robust.smooth_normals`).
    features : list of Feature
        Every handle, hole and component of M_S with its size in local
        sampling radii, and whether the sample supports it
        (:mod:`crustview.core.analysis.features`), plus the extraction's
        :attr:`Extraction.disputed`.
    """

    d: int
    k: int
    input_points: np.ndarray
    input_index: np.ndarray
    points: np.ndarray
    point_input: np.ndarray
    spacing: float
    joggle: float
    subspace_dim: int
    bounding_points: np.ndarray
    delaunay_simplices: np.ndarray
    voronoi_vertices: np.ndarray
    pole_index: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    candidates: Candidates
    test: str
    theta: float
    extraction: Extraction
    manifold: np.ndarray
    topology: TopologyReport
    timings: dict[str, float]
    prune_boundary: bool = True
    labelling: bool = True
    mode: str = "robust"
    delaunay_backend: str = ""
    features: list = field(default_factory=list)
    normals_method: str = "paper"

    @property
    def uncertain_features(self) -> list:
        """The features the sample does not support (an empty list when it supports them all)."""
        return [f for f in self.features if f.uncertain]

    @property
    def n(self) -> int:
        return len(self.points)

    @property
    def delaunay_points(self) -> np.ndarray:
        """Samples followed by the bounding points, shape (n + b, k)."""
        return np.vstack([self.points, self.bounding_points])

    @property
    def poles(self) -> np.ndarray:
        """Pole positions, shape (n, k - d, k)."""
        return self.voronoi_vertices[self.pole_index]

    def manifold_input_simplices(self) -> np.ndarray:
        """M_S with indices into the *input* rows (first row of each sample)."""
        return self.point_input[self.manifold]

    def voronoi_cell(self, i: int) -> np.ndarray:
        """Voronoi vertices of sample ``i``'s cell, shape (v, k)."""
        rows = np.flatnonzero((self.delaunay_simplices == i).any(axis=1))
        return self.voronoi_vertices[rows]
