"""Algorithm 3 as recorded steps: the rule names, :class:`Step`, :class:`Cascade` and :class:`Extraction`.

The paper's loop and the robust extension both produce an :class:`Extraction`:
a list of steps, each naming its rule, over the rows of
:attr:`Extraction.simplices`, with ``added_at`` and ``removed_at`` so that the
complex after any step is one comparison away.  The viewer, the report and the
command line speak in these rule names.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

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
RULE_TOUR = "tour-curve"
#: Rules of the robust extension's labelling path (``core.robust.cells``).
RULE_LABEL = "label-cells"
RULE_REPAIR = "repair-vertex"
RULE_SCULPT = "sculpt-sample"
RULE_OPEN = "open-cap"
RULE_CUT = "cut-handle"
RULE_JOIN = "join-parts"
RULES = (
    RULE_PRUNE,
    RULE_RESOLVE,
    RULE_LABEL,
    RULE_REPAIR,
    RULE_SCULPT,
    RULE_CUT,
    RULE_JOIN,
    RULE_OPEN,
    RULE_CORE,
    RULE_SEED,
    RULE_GROW,
    RULE_RELAX,
    RULE_FILL,
    RULE_INSERT,
    RULE_STRAY,
    RULE_TOUR,
)
#: Rules that remove simplices (the paper's) and rules that add them (the extension's).
REMOVING_RULES = (RULE_PRUNE, RULE_RESOLVE)
#: Rules whose one step acts everywhere at once (every Delaunay cell labelled): their τ is only the first face
#: they added, no place, and the viewer names and marks none.
PLACELESS_RULES = (RULE_LABEL,)
ADDING_RULES = (
    RULE_LABEL,
    RULE_REPAIR,
    RULE_SCULPT,
    RULE_CUT,
    RULE_JOIN,
    RULE_CORE,
    RULE_SEED,
    RULE_GROW,
    RULE_RELAX,
    RULE_FILL,
    RULE_INSERT,
    RULE_TOUR,
)


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
    disputed : list
        Uncertain features that the extraction itself found: where two of the
        robust extension's methods give closed manifolds of different
        topology (:func:`crustview.core.analysis.dispute.disagreement`).
    features : list or None
        The features of the final complex when the extraction already
        measured them (in the coordinates it was given); None otherwise.
    removed_features : list
        Handles the extraction removed (rule ``cut-handle``,
        :mod:`crustview.core.robust.cut_handle`): loops below CUT_BELOW = 4 pi,
        of which only those below LOOP_MIN = 2 pi are beyond every eps < 1 sample,
        as :class:`~crustview.core.analysis.features.Feature` records of the
        complex before the cut; the parts ``join-parts`` joined; the caps
        ``open-cap`` kept closed (holes).
    named_features : list
        Components and handles ``open-cap`` names in its own words where it kept a wall or two facing
        caps closed (:mod:`crustview.core.robust.walls`, :func:`crustview.core.robust.cap_holes.facing_caps`):
        uncertain, and not features of the complex; reported as they are.
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
    disputed: list = field(default_factory=list)
    features: list | None = None
    removed_features: list = field(default_factory=list)
    named_features: list = field(default_factory=list)

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
