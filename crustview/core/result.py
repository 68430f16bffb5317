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

#: Names of the two candidate tests of Algorithm 2.
CANDIDATE_TESTS = ("cocone", "cocone-all", "literal")

#: Names of the rules of Algorithm 3 that appear in :class:`Step` records.
RULE_PRUNE = "prune-sharp"
RULE_RESOLVE = "resolve-nonmanifold"
#: Rules of the robust extension (``core.robust``), never used by the paper's loop.
RULE_SEED = "seed"
RULE_CORE = "seed-core"
RULE_GROW = "grow"
RULE_RELAX = "grow-relaxed"
RULE_FILL = "fill-hole"
RULE_INSERT = "insert-sample"
RULE_STRAY = "drop-stray"
RULES = (RULE_PRUNE, RULE_RESOLVE, RULE_CORE, RULE_SEED, RULE_GROW, RULE_RELAX, RULE_FILL, RULE_INSERT, RULE_STRAY)
#: Rules that remove simplices (the paper's) and rules that add them (the extension's).
REMOVING_RULES = (RULE_PRUNE, RULE_RESOLVE)
ADDING_RULES = (RULE_CORE, RULE_SEED, RULE_GROW, RULE_RELAX, RULE_FILL, RULE_INSERT)

#: Extraction modes: the paper's Algorithm 3 as printed, and the robust extension.
EXTRACTION_MODES = ("robust", "paper")


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
    added : tuple of int
        Simplex ids added by this step (the robust extension's rules
        ``seed``, ``grow``, ``grow-relaxed`` and ``fill-hole``; empty for the
        paper's rules).
    cause : int
        For ``prune-sharp``: the step whose removals exposed ``tau`` (made it
        sharp or a boundary face), or -1 when ``tau`` was already sharp or a
        hole of T_S before extraction started.  Following ``cause`` back
        gives the *origin* of each prune cascade.  -1 for the other rules.
    """

    index: int
    rule: str
    tau: tuple[int, ...]
    kept: tuple[int, ...]
    removed: tuple[int, ...]
    angle: float
    reason: str
    added: tuple[int, ...] = ()
    cause: int = -1


@dataclass(frozen=True)
class Cascade:
    """A prune cascade: every step whose ``cause`` chain ends at one origin step.

    Attributes
    ----------
    origin : int
        Index of the origin step (a prune of a face that was sharp or a hole
        in T_S, or a ``resolve-nonmanifold`` decision whose removals exposed
        faces).
    tau : tuple of int
        The origin step's (d-1)-face.
    rule : str
        The origin step's rule.
    hole : bool
        True when the origin face had a single simplex in T_S (a hole).
    steps : ndarray of int
        Indices of every step of the cascade, origin included, ascending.
    removed : int
        Number of simplices that the cascade's steps removed.
    """

    origin: int
    tau: tuple[int, ...]
    rule: str
    hole: bool
    steps: np.ndarray
    removed: int


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
        ``prune_boundary`` was off, or holes the robust extension left open).
    added_at : ndarray of shape (c,), optional
        Number of steps after which each simplex exists: 0 for the simplices
        of T_S (present from the start), ``j + 1`` for a simplex added by step
        ``j`` (robust extension).  The complex after ``i`` steps is
        ``(added_at <= i) & (removed_at >= i)``.
    holes : ndarray of shape (h, d), optional
        The (d-1)-faces of T_S that lie in a single d-simplex before the
        extraction starts (the holes of T_S).
    mode : str
        ``"paper"`` (Algorithm 3 as printed) or ``"robust"`` (the extension of
        :mod:`crustview.core.robust.driver`).
    in_candidates : ndarray of shape (c,) of bool, optional
        Which of :attr:`simplices` are in T_S (the robust extension may add
        Delaunay d-faces outside T_S).  None: all are.
    notes : list of str
        Sentences on how the run went (e.g. why the robust extension took
        over from the paper's loop).
    """

    simplices: np.ndarray
    steps: list[Step]
    removed_at: np.ndarray
    stopped: str
    added_at: np.ndarray | None = None
    holes: np.ndarray | None = None
    mode: str = "paper"
    in_candidates: np.ndarray | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def n_steps(self) -> int:
        return len(self.steps)

    def alive(self, i: int) -> np.ndarray:
        """Boolean mask over :attr:`simplices` of the complex after ``i`` steps."""
        i = int(min(max(i, 0), len(self.steps)))
        if self.added_at is None:
            return self.removed_at >= i
        return (self.removed_at >= i) & (self.added_at <= i)

    def removed_by(self, i: int) -> np.ndarray:
        """Boolean mask of the simplices removed by the first ``i`` steps."""
        i = int(min(max(i, 0), len(self.steps)))
        return self.removed_at < i

    def cascades(self) -> list[Cascade]:
        """Prune cascades grouped by origin, largest (most simplices removed) first.

        Only cascades that removed at least one simplex after their origin
        step, or whose origin is a hole or sharp face of T_S, are listed.
        """
        n = len(self.steps)
        if n == 0:
            return []
        cause = np.fromiter((s.cause for s in self.steps), np.int64, n)
        nrem = np.fromiter((len(s.removed) for s in self.steps), np.int64, n)
        root = np.arange(n)
        for i in np.flatnonzero(cause >= 0):  # cause[i] < i, so one pass suffices
            root[i] = root[cause[i]]
        removing = np.isin(np.array([s.rule for s in self.steps]), REMOVING_RULES)
        keep_origin = removing & (cause < 0)
        order = np.argsort(root, kind="stable")
        sizes = np.bincount(root, weights=nrem, minlength=n).astype(np.int64)
        counts = np.bincount(root, minlength=n)
        starts = np.concatenate([[0], np.cumsum(counts)])
        hole_set = set()
        if self.holes is not None and len(self.holes):
            hole_set = {tuple(int(v) for v in h) for h in self.holes}
        out = []
        for o in np.flatnonzero(keep_origin):
            st = self.steps[o]
            if st.rule == RULE_RESOLVE and counts[o] <= 1:
                continue  # a decision that exposed nothing is no cascade
            out.append(
                Cascade(
                    int(o),
                    st.tau,
                    st.rule,
                    st.rule == RULE_PRUNE and st.tau in hole_set and len(st.removed) == 1,
                    np.sort(order[starts[o] : starts[o + 1]]),
                    int(sizes[o]),
                )
            )
        out.sort(key=lambda c: (-c.removed, c.origin))
        return out

    def complex_at(self, i: int) -> np.ndarray:
        """The d-simplices (rows of point indices) after ``i`` steps."""
        return self.simplices[self.alive(i)]

    def counts_by_rule(self) -> dict[str, dict[str, int]]:
        """Number of steps and of removed simplices per rule."""
        if self.mode == "paper":
            out = {r: {"steps": 0, "removed": 0} for r in REMOVING_RULES}
        else:
            out = {r: {"steps": 0, "removed": 0, "added": 0} for r in RULES}
        for s in self.steps:
            out[s.rule]["steps"] += 1
            out[s.rule]["removed"] += len(s.removed)
            if "added" in out[s.rule]:
                out[s.rule]["added"] += len(s.added)
        return out


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

    def __init__(self, literal: np.ndarray, vertex_angles: np.ndarray) -> None:
        self._values: dict[str, np.ndarray] = {"literal": literal}
        self._vertex = vertex_angles

    def __getitem__(self, test: str) -> np.ndarray:
        got = self._values.get(test)
        if got is None:
            if test not in self._DERIVED:
                raise KeyError(test)
            fold = self._DERIVED[test]
            got = self._vertex[:, 0].copy()
            for c in range(1, self._vertex.shape[1]):
                fold(got, self._vertex[:, c], out=got)
            self._values[test] = got
        return got

    def __iter__(self) -> Iterator[str]:
        return iter(("cocone", "cocone-all", "literal"))

    def __len__(self) -> int:
        return 3


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
    mode : str
        ``"robust"`` (default: the paper's Algorithm 3, and the extension of
        :mod:`crustview.core.robust.driver` when the paper's loop cannot give a
        closed manifold through every sample) or ``"paper"``.
    delaunay_backend : str
        The Delaunay code that ran (:func:`.delaunay.backend_label`); empty
        for results made before it was recorded.
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
    mode: str = "robust"
    delaunay_backend: str = ""

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
