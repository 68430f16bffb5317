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

from dataclasses import dataclass, field

import numpy as np

#: Names of the two candidate tests of Algorithm 2.
CANDIDATE_TESTS = ("cocone", "cocone-all", "literal")

#: Names of the rules of Algorithm 3 that appear in :class:`Step` records.
RULE_PRUNE = "prune-sharp"
RULE_RESOLVE = "resolve-nonmanifold"
RULES = (RULE_PRUNE, RULE_RESOLVE)


@dataclass(frozen=True)
class Step:
    """One recorded step of Algorithm 3.

    Attributes
    ----------
    index : int
        Position in :attr:`Extraction.steps` (0-based).  The complex *after*
        this step is ``Extraction.alive(index + 1)``.
    rule : str
        ``"prune-sharp"`` (line 2: every d-simplex at a sharp or boundary
        (d-1)-face is removed) or ``"resolve-nonmanifold"`` (lines 3-5: a face
        with more than two d-simplices keeps its flattest pair).
    tau : tuple of int
        The (d-1)-face (d sample indices, sorted) the rule acted on.
    kept : tuple of int
        Candidate-simplex ids (rows of :attr:`Extraction.simplices`) kept at
        ``tau`` (the chosen pair for ``resolve-nonmanifold``; empty for prune).
    removed : tuple of int
        Candidate-simplex ids removed by this step.
    angle : float
        The deciding angle in radians: for prune, the largest pairwise angle
        at ``tau`` (< pi/2 makes it sharp; ``nan`` when only one simplex was
        left); for resolve, the angle of the kept pair (pi = flat).
    reason : str
        Human-readable sentence.
    """

    index: int
    rule: str
    tau: tuple[int, ...]
    kept: tuple[int, ...]
    removed: tuple[int, ...]
    angle: float
    reason: str


@dataclass
class Extraction:
    """Algorithm 3 as a replayable sequence of steps.

    Attributes
    ----------
    simplices : ndarray of shape (c, d + 1)
        The input complex T_S (candidate d-simplices, indices into points).
    steps : list of Step
        Steps in the order they were taken.
    removed_at : ndarray of shape (c,)
        Index of the step that removed each simplex, or ``len(steps)`` (never
        removed).  The complex after ``i`` steps is
        ``simplices[removed_at >= i]``, so scrubbing costs one comparison.
    stopped : str
        Why the loop ended: ``"closed"`` (every (d-1)-face in 0 or 2
        simplices), ``"empty"``, or ``"open"`` (boundary faces kept because
        ``prune_boundary`` was off).
    """

    simplices: np.ndarray
    steps: list[Step]
    removed_at: np.ndarray
    stopped: str

    @property
    def n_steps(self) -> int:
        return len(self.steps)

    def alive(self, i: int) -> np.ndarray:
        """Boolean mask over :attr:`simplices` of the complex after ``i`` steps."""
        i = int(min(max(i, 0), len(self.steps)))
        return self.removed_at >= i

    def complex_at(self, i: int) -> np.ndarray:
        """The d-simplices (rows of point indices) after ``i`` steps."""
        return self.simplices[self.alive(i)]

    def counts_by_rule(self) -> dict[str, dict[str, int]]:
        """Number of steps and of removed simplices per rule."""
        out = {r: {"steps": 0, "removed": 0} for r in RULES}
        for s in self.steps:
            out[s.rule]["steps"] += 1
            out[s.rule]["removed"] += len(s.removed)
        return out


@dataclass
class Candidates:
    """All Delaunay d-faces among the samples and both tests' verdicts.

    Attributes
    ----------
    faces : ndarray of shape (f, d + 1)
        Every Delaunay d-face whose vertices are all samples (sorted rows).
    angles : dict of str to ndarray of shape (f,)
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
    angles: dict[str, np.ndarray]
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
        None when the complex is not a closed pseudo-manifold.
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
