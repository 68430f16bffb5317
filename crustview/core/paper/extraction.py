"""Algorithm 3: manifold extraction as a recorded, replayable sequence of steps.

The paper's loop::

    while T is not a closed d-manifold:
        recursively remove d-simplices that have a (d-1)-face without an
            adjacent d-simplex meeting it at an angle of 3pi/2 or larger   (2)
        find a (d-1)-simplex tau in more than two d-simplices               (3)
        let sigma, sigma' be two of them meeting at an angle < pi/2         (4)
        remove all d-simplices containing tau except sigma and sigma'       (5)

Angles in any codimension
-------------------------
The paper speaks of dihedral angles, which only exist in codimension 1.  For
a (d-1)-face ``tau`` of a d-simplex ``sigma`` let ``u(sigma, tau)`` be the
unit vector from ``aff(tau)`` to the vertex of ``sigma`` opposite ``tau``,
orthogonal to ``aff(tau)``.  The angle between two d-simplices at ``tau`` is
``phi = arccos(u . u')`` in ``[0, pi]``: ``pi`` means flat (they continue
each other), ``0`` means folded onto each other.  In codimension 1 this is the
ordinary dihedral angle.

* **Sharp face (line 2).**  In codimension 1 the simplices around ``tau`` are
  cyclically ordered; "no simplex meets at 3pi/2 or larger" is Cocone's sharp
  edge: some gap between consecutive simplices exceeds 3pi/2, i.e. all of them
  lie in a wedge narrower than pi/2, i.e. *every pair meets at phi < pi/2*.
  That last form needs no cyclic order, so it is our definition in every
  codimension.  A face with a single simplex is sharp (boundary).  All
  simplices at a sharp face are removed in one step (rule ``prune-sharp``),
  and the faces they touch are re-examined ("recursively").
* **Non-manifold face (lines 3-5).**  "Meet at an angle smaller than pi/2" is
  the deviation from flat, ``pi - phi < pi/2``.  Among the eligible pairs we
  keep the one whose removal of the others starts the smallest prune cascade
  (simulated, capped at :data:`CASCADE_LIMIT` simplices), then the flattest
  (largest ``phi``), then the smallest ids, so the run is deterministic.
  Faces are processed most-confident first: largest best ``phi`` first
  (rule ``resolve-nonmanifold``).

The loop stops when no rule applies.  Then every (d-1)-face has 0 or 2
simplices; if the complex is nevertheless not a closed manifold (a pinched
vertex) or is empty, :attr:`Extraction.stopped` says so and the topology
report explains it -- the paper's loop would not terminate there.
"""

from __future__ import annotations

import heapq
import math
from collections import deque
from collections.abc import Callable

import numpy as np

from ..steps import RULE_PRUNE, RULE_RESOLVE, Extraction, Step
from ..util.parallel import start_in_background
from . import compiled_loop
from .facets import OPPOSITE_BLOCK, facet_structure, opposite_vectors

HALF_PI = np.pi / 2
#: Largest prune cascade simulated when choosing a pair (see _choose_pair).
CASCADE_LIMIT = 64
#: Candidate simplices from which the facet table is built on another thread while the opposite vectors
#: are computed (a scheduling choice, not a threshold of the algorithm: below it starting the thread costs
#: more than it saves; the same arrays either way).  Torus 300k: the two took 0.12 and 0.13 s one after the
#: other.
BESIDE_MIN = 50_000


def _max_pair(ang: list[list[float]]) -> float:
    """Largest off-diagonal entry of a symmetric angle matrix (m >= 2 rows)."""
    return max(max(row[i + 1 :]) for i, row in enumerate(ang[:-1]))


class _Extractor:
    """Mutable state of one run; see :func:`extract`."""

    def __init__(self, points: np.ndarray, simplices: np.ndarray, prune_boundary: bool = True) -> None:
        self.prune_boundary = prune_boundary
        self.simplices = np.sort(np.asarray(simplices, dtype=np.int64), axis=1)
        c = len(self.simplices)
        if c >= BESIDE_MIN:  # the two tables are independent: the facets' on the other core
            table = start_in_background(facet_structure, self.simplices)
            self.u = opposite_vectors(points, self.simplices)
            self.facets, self.facet_of, self.ptr, self.inc = table.result()
        else:
            self.facets, self.facet_of, self.ptr, self.inc = facet_structure(self.simplices)
            self.u = opposite_vectors(points, self.simplices)
        # rows are turned into Python lists one at a time, when a step looks at
        # them: whole-table lists would cost ~40 bytes per entry (hundreds of
        # MB at a million samples) for the few faces a good sample touches
        self.alive = np.ones(c, dtype=bool)
        self.count = np.diff(self.ptr).copy()
        self.removed_at = np.full(c, -1, dtype=np.int64)
        self.steps: list[Step] = []
        # the step whose removals last touched each facet (cascade bookkeeping)
        self.exposer = np.full(len(self.facets), -1, dtype=np.int64)
        # d-simplices alive at each sample; a sample at 0 can never be a vertex again
        self.vcount = np.bincount(self.simplices.ravel(), minlength=int(self.simplices.max()) + 1)
        self.lost: int | None = None

    # -- geometry ---------------------------------------------------------
    def facets_of(self, s: int) -> list[int]:
        """The facets of simplex ``s``, opposite its vertices in order."""
        return self.facet_of[s].tolist()

    def alive_at(self, g: int) -> list[int]:
        alive = self.alive
        ptr = self.ptr
        return [s for s in self.inc[ptr[g] : ptr[g + 1]].tolist() if alive[s]]

    def pair_angles(self, g: int, simp: list[int]) -> list[list[float]]:
        """Angles ``phi`` between the simplices ``simp`` at facet ``g`` (m x m, symmetric, diagonal 0).

        Plain Python floats: the matrices are 2 x 2 to 6 x 6 and there are
        tens of thousands of them, where numpy's per-call cost is 5x the
        arithmetic.
        """
        facet_of, u = self.facet_of, self.u
        vec = [u[s, facet_of[s].tolist().index(g)].tolist() for s in simp]
        m = len(vec)
        ang = [[0.0] * m for _ in range(m)]
        for i in range(m):
            vi = vec[i]
            for j in range(i + 1, m):
                dot = 0.0  # left to right, as the compiled loop (sum() compensates from Python 3.12 on)
                for x, y in zip(vi, vec[j]):
                    dot += x * y
                ang[i][j] = ang[j][i] = math.acos(-1.0 if dot < -1.0 else 1.0 if dot > 1.0 else dot)
        return ang

    def is_sharp(self, g: int) -> tuple[bool, float, list[int]]:
        simp = self.alive_at(g)
        if len(simp) == 0:
            return False, float("nan"), simp
        if len(simp) == 1:
            return self.prune_boundary, float("nan"), simp
        best = _max_pair(self.pair_angles(g, simp))
        return best < HALF_PI, best, simp

    # -- mutation ---------------------------------------------------------
    def remove(self, simp: list[int], step: int) -> set[int]:
        touched: set[int] = set()
        for s in simp:
            if not self.alive[s]:
                continue
            self.alive[s] = False
            self.removed_at[s] = step
            for g in self.facet_of[s].tolist():
                self.count[g] -= 1
                touched.add(g)
            for v in self.simplices[s]:
                self.vcount[v] -= 1
                if self.vcount[v] == 0 and self.lost is None:
                    self.lost = int(v)
        for g in touched:
            self.exposer[g] = step
        return touched

    def tau(self, g: int) -> tuple[int, ...]:
        return tuple(int(v) for v in self.facets[g])


def _initial_sharp(ex: _Extractor) -> list[int]:
    """Facets sharp in the full complex (the test of :meth:`_Extractor.is_sharp`), vectorised.

    Facets are grouped by their number m of simplices; for each m the m unit
    vectors of every facet are gathered at once and the facet is sharp when
    the widest pair angle, arccos of the smallest pairwise dot product, is
    below pi/2.  Thin real scans have tens of thousands of facets with m > 2,
    which one Python call each made the largest cost of Algorithm 3.
    """
    cnt = ex.count
    sharp = (cnt == 1) if ex.prune_boundary else np.zeros(len(cnt), dtype=bool)
    for m in np.unique(cnt[cnt >= 2]).tolist():
        for lo in range(0, len(cnt), OPPOSITE_BLOCK):  # blocks of facets keep temporaries small
            g = lo + np.flatnonzero(cnt[lo : lo + OPPOSITE_BLOCK] == m)
            if len(g) == 0:
                continue
            simp = ex.inc[ex.ptr[g][:, None] + np.arange(m)]  # (G, m)
            pos = np.argmax(ex.facet_of[simp] == g[:, None, None], axis=2)
            vec = ex.u[simp, pos]  # (G, m, k)
            if m == 2:
                # the one pair: einsum's own product sum over k, the bits of the (0, 1) entry of the
                # matrix below (tests/test_core_extraction.py), without the other three entries
                smallest = np.einsum("gk,gk->g", vec[:, 0], vec[:, 1])
            else:
                dots = np.einsum("gik,gjk->gij", vec, vec)
                dots[:, np.arange(m), np.arange(m)] = np.inf
                smallest = dots.min(axis=(1, 2))
            widest = np.arccos(np.clip(smallest, -1.0, 1.0))
            sharp[g[widest < HALF_PI]] = True
    return np.flatnonzero(sharp).tolist()


def extract(
    points: np.ndarray,
    simplices: np.ndarray,
    *,
    prune_boundary: bool = True,
    stop_when_sample_lost: bool = False,
    cancel: object | None = None,
    progress: Callable[[float], None] | None = None,
    compiled: bool = True,
) -> Extraction:
    """Run Algorithm 3 on a d-complex and record every step.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    simplices : ndarray of shape (c, d + 1)
        The candidate complex T_S.
    prune_boundary : bool
        True (the paper): a (d-1)-face with a single d-simplex is sharp and
        pruned.  False keeps such boundary faces; only for inspecting samples
        that are not closed (scans with holes): the result then cannot be a
        closed manifold, and the report says so.
    stop_when_sample_lost : bool
        Stop as soon as some sample has lost its last d-simplex
        (``stopped = "sample-lost"``).  Algorithm 3 only removes simplices,
        so from then on it can no longer return a manifold through every
        sample, as the paper requires; the robust extension uses this to
        hand over early.
    cancel : object with ``is_set()``, optional
        Checked every 256 steps; raises :class:`~crustview.core.errors.Cancelled`.
    progress : callable, optional
        Called with a rough fraction of simplices decided.
    compiled : bool
        Run the loop in C++ (:mod:`.compiled_loop`, the same steps) when the
        extension is built; False runs the Python loop below, the reference.

    Returns
    -------
    Extraction
    """
    simplices = np.asarray(simplices, dtype=np.int64)
    d1 = simplices.shape[1] if simplices.ndim == 2 else 1
    if len(simplices) == 0:
        return Extraction(np.empty((0, d1), np.int64), [], np.zeros(0, np.int64), "empty")
    ex = _Extractor(points, simplices, prune_boundary)
    holes = ex.facets[ex.count == 1]
    first = _initial_sharp(ex)
    if compiled and compiled_loop.available(ex):
        compiled_loop.run(
            ex, first, CASCADE_LIMIT, stop_when_sample_lost=stop_when_sample_lost, cancel=cancel, progress=progress
        )
    else:
        _python_loop(ex, first, stop_when_sample_lost, cancel, progress)
    n_steps = len(ex.steps)
    # a simplex removed by step j is alive after i steps iff i <= j
    removed_at = np.where(ex.removed_at < 0, n_steps, ex.removed_at)
    if stop_when_sample_lost and ex.lost is not None:
        stopped = "sample-lost"
    elif not ex.alive.any():
        stopped = "empty"
    elif (ex.count[ex.count > 0] == 2).all():
        stopped = "closed"
    elif not prune_boundary:
        stopped = "open"  # boundary faces were kept on request
    else:  # pragma: no cover - with pruning the loop only ends with counts in {0, 2}
        stopped = "stuck"
    ext = Extraction(ex.simplices, ex.steps, removed_at, stopped, holes=holes)
    if stopped == "sample-lost":
        ext.notes.append(f"sample {ex.lost} lost its last simplex at step {n_steps - 1}")
    return ext


def _python_loop(
    ex: _Extractor,
    first: list[int],
    stop_when_sample_lost: bool,
    cancel: object | None,
    progress: Callable[[float], None] | None,
) -> None:
    """The paper's loop (lines 2-5) on ``ex``, its steps appended: the reference of :mod:`.compiled_loop`."""
    from ..errors import Cancelled

    prune = deque(first)
    queued = set(prune)
    heap = []
    for g in np.flatnonzero(ex.count > 2):
        heap.append((-np.pi, int(g)))  # evaluated lazily on first pop
    heapq.heapify(heap)

    def check_cancel() -> None:
        if cancel is not None and len(ex.steps) % 256 == 0 and cancel.is_set():
            raise Cancelled("reconstruction cancelled")

    while True:
        while prune:
            g = prune.popleft()
            queued.discard(g)
            sharp, best, simp = ex.is_sharp(g)
            if not sharp:
                continue
            idx = len(ex.steps)
            cause = int(ex.exposer[g])
            touched = ex.remove(simp, idx)
            why = (
                "only one d-simplex left at this face (boundary)"
                if len(simp) == 1
                else f"all {len(simp)} d-simplices meet within {np.degrees(best):.1f} deg < 90 deg (sharp)"
            )
            ex.steps.append(Step(idx, RULE_PRUNE, ex.tau(g), (), tuple(simp), best, why, cause=cause))
            for h in sorted(touched):
                if h != g and ex.count[h] > 0 and h not in queued:
                    prune.append(h)
                    queued.add(h)
            check_cancel()
            if stop_when_sample_lost and ex.lost is not None:
                break
        if stop_when_sample_lost and ex.lost is not None:
            break
        # lines 3-5: one non-manifold face, most confident first
        chosen = None
        while heap:
            key, g = heapq.heappop(heap)
            if ex.count[g] <= 2:
                continue
            simp = ex.alive_at(g)
            ang = ex.pair_angles(g, simp)
            best = _max_pair(ang)
            if -key > best + 1e-12:  # stale priority: re-queue with the true one
                heapq.heappush(heap, (-best, g))
                continue
            chosen = (g, simp, ang)
            break
        if chosen is None:
            break
        g, simp, ang = chosen
        pick = _choose_pair(ex, g, simp, ang)
        if pick is None:  # no eligible pair: the face is sharp, prune handles it
            prune.append(g)
            queued.add(g)
            continue
        i, j = pick
        keep = (simp[i], simp[j])
        drop = [s for s in simp if s not in keep]
        idx = len(ex.steps)
        touched = ex.remove(drop, idx)
        ex.steps.append(
            Step(
                idx,
                RULE_RESOLVE,
                ex.tau(g),
                keep,
                tuple(drop),
                float(ang[i][j]),
                f"{len(simp)} d-simplices at this face; kept the pair meeting at "
                f"{np.degrees(ang[i][j]):.1f} deg (180 = flat), removed {len(drop)}",
            )
        )
        for h in sorted(touched):
            if ex.count[h] > 0 and h not in queued:
                prune.append(h)
                queued.add(h)
            if ex.count[h] > 2:
                heapq.heappush(heap, (-np.pi, h))
        check_cancel()
        if stop_when_sample_lost and ex.lost is not None:
            break
        if progress is not None and idx % 64 == 0:
            progress(1.0 - len(heap) / max(len(ex.facets), 1))


def _cascade_loss(ex: _Extractor, drop: list[int], limit: int) -> int:
    """Simplices removed by dropping ``drop`` plus the prune cascade it starts (capped).

    With boundary pruning off a face left with one simplex is not pruned, but
    it is a new hole in the surface: each such face counts as one loss, so
    the choice still prefers pairs that leave the surface whole.
    """
    gone = set(drop)
    opened: set[int] = set()
    queue = deque()
    for s in drop:
        queue.extend(ex.facets_of(s))
    while queue and len(gone) + len(opened) < limit:
        h = queue.popleft()
        simp = [s for s in ex.alive_at(h) if s not in gone]
        if len(simp) == 1 and not ex.prune_boundary:
            if ex.count[h] >= 2:
                opened.add(h)
            continue
        if not simp:
            continue
        if len(simp) > 1:
            if _max_pair(ex.pair_angles(h, simp)) >= HALF_PI:
                continue
        for s in simp:
            gone.add(s)
            queue.extend(g for g in ex.facets_of(s) if g != h)
    return len(gone) + len(opened)


def _choose_pair(ex: _Extractor, g: int, simp: list[int], ang: list[list[float]]) -> tuple[int, int] | None:
    """Eligible pair (phi > pi/2) whose removals cascade least, then the flattest.

    The paper allows any pair meeting within pi/2 of flat.  A bad choice
    leaves boundary faces whose prune cascade can eat a correct sheet, so
    each choice's cascade is simulated (up to :data:`CASCADE_LIMIT`
    simplices) and the one destroying least wins; ties go to the flattest.
    """
    best = None
    best_key = None
    m = len(simp)
    for i in range(m):
        for j in range(i + 1, m):
            if not ang[i][j] > HALF_PI:
                continue
            drop = [s for t, s in enumerate(simp) if t not in (i, j)]
            key = (_cascade_loss(ex, drop, CASCADE_LIMIT), -ang[i][j], simp[i], simp[j])
            if best_key is None or key < best_key:
                best_key, best = key, (i, j)
    return best
