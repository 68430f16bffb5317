"""Rules ``repair-vertex`` and ``sculpt-sample``: the labelled surface made a manifold through every sample.

The faces between inside and outside cells (:mod:`.labelling`) never have a
boundary, but they can pinch: in R^3, at a vertex v the surface is a manifold exactly
when the inside cells of v's star form one piece and the outside cells one
piece (joined through faces at v; the link of v is a sphere split into two
discs).  Two inside pieces touching at v make a pinched vertex or a
non-manifold edge.  In R^k, k >= 4, the condition is necessary only, and
:meth:`LabelEditor.repair_ridges` mends what it misses.

* ``repair-vertex``: at such a vertex, the most confident piece of each label
  stays, and every other piece takes the other label.  Confidence is the
  labelling's (the weakest tie on a cell's path to the outside), summed over
  the piece.  Repeated until no vertex pinches; a cell flipped there and back
  twice (:data:`PING_PONG`) keeps its label, so two neighbours cannot undo
  each other's repair for ever (a vertex whose only flippable pieces are
  pinned then stays pinched, and the topology report says M_S is not a
  closed manifold, as it did when the rounds ran out).
* ``sculpt-sample``: a sample whose whole star has one label is no vertex of
  M_S.  If one of its star cells has its face opposite the sample on the
  surface, that cell takes the other label: the surface then runs through
  the sample, and since the sample was not on it, this keeps a manifold (the
  sculpting rule of Boissonnat, 1984: a cell with one face on the boundary
  may be removed when its opposite vertex is not on the boundary).  The
  least confident such cell goes, of those whose new faces (the cell's
  faces through the sample, three in R^3) are no larger than
  :data:`~.grow.SIZE_MAX` local spacings (circumradius over the mean spacing
  of their vertices, :func:`face_sizes`; a vertex's spacing the larger of its
  nearest-neighbour distance and the largest enclosing radius of the faces of
  M_S at it, as the features measure across long thin triangles -- in the
  nearest-neighbour distance alone, rings 5 times farther apart than along
  them lost legitimate sculpts: a bottle, a cup and a holed shell of
  ``bench_shapes.py`` at 0.1 h came out wrong, one of them without a flag): the
  largest face the growing path adds, and the size above which ``open-cap``
  calls a face a cap's.  A larger cell is a ball of the medial axis spanning
  the object (the cow head's from an ear to the chin, 51 spacings; a
  Neptune's from the trident to the shoulder, 141): carved out, it left a
  sliver fin of faces that long on a result whose topology was right
  (session 30, found by a new user; the report said nothing, as nothing was
  uncertain).  A sample with no such cell is left to ``insert-sample``, which
  puts it into the nearest face within INSERT_MAX spacings; where that leaves
  it out, the labelled path runs once more with those samples sculpted as
  before, through their least confident cell (every sample a vertex comes
  first, and a fin is the price: the halves of the horse at 1/2 density kept
  11 samples out without it).

Each rule returns the cells it flipped, one group per step, so the driver can
record the faces each step removes and adds.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import connected_components

from ..analysis.radii import enclosing_cover
from ..analysis.topology import all_faces, singular_vertices
from ..errors import check_cancel
from ..util.rows import unique_rows
from .grow import SIZE_MAX, circumradii
from .labelling import Labelling

try:  # the compiled star_pieces; the Python reference below gives the same pieces
    from . import _labels as _kernel
except ImportError:  # pragma: no cover - only without the extension
    _kernel = None

#: Rounds of repair (each flips the extra pieces at every pinched vertex found; flips can move a
#: pinch to a neighbour, real scans settle in 2-6 rounds).
REPAIR_ROUNDS = 30
#: Flips of one cell by ``repair-vertex`` after which it counts as a ping-pong (two neighbours undoing
#: each other's repair, flipped there and back twice) and its piece is kept from then on.  One flip
#: back is a later repair correcting an earlier one and is allowed; a second round trip is a cycle.
PING_PONG = 4
#: Rounds of sculpting (a sample two cells deep comes to the surface in the second round).
SCULPT_ROUNDS = 3


class LabelEditor:
    """The labelling with the incidences that local flips need."""

    def __init__(self, lab: Labelling) -> None:
        self.lab = lab
        s = lab.simplices
        m, w = s.shape
        self.w = w
        n = lab.n
        vert = s.ravel()
        cell = np.repeat(np.arange(m), w)
        ok = vert < n
        star = csr_matrix((np.ones(int(ok.sum()), np.int8), (vert[ok], cell[ok])), shape=(n, m))
        star.sort_indices()  # each star's cells in order: the compiled piece_counts finds them by bisection
        self.star_ptr, self.star_cells = star.indptr, star.indices
        nf = len(lab.faces)
        cf = csr_matrix(
            (np.ones(2 * nf, np.int8), (np.r_[lab.a, lab.b], np.r_[np.arange(nf), np.arange(nf)])), shape=(m, nf)
        )
        self.cell_ptr, self.cell_faces = cf.indptr, cf.indices
        #: star_pieces by (vertex, the labels of its star): the pieces depend on nothing else, and the
        #: local repairs of cut-handle ask again for stars whose labels did not change (43 % of the
        #: calls on six noisy scans)
        self._pieces: dict[tuple[int, bytes], tuple[np.ndarray, np.ndarray]] = {}
        #: the incidences as the compiled star_pieces reads them (int64, contiguous); none without it
        self._k_arrays = (
            tuple(
                np.ascontiguousarray(x, dtype=np.int64)
                for x in (self.star_ptr, self.star_cells, self.cell_ptr, self.cell_faces, lab.faces, lab.a, lab.b)
            )
            if _kernel is not None
            else ()
        )
        #: which shared faces are on M_S now (kept up to date by :meth:`flip`)
        self.cut = lab.cut()

    def star(self, v: int) -> np.ndarray:
        """The cells that have v as a vertex."""
        return self.star_cells[self.star_ptr[v] : self.star_ptr[v + 1]]

    def faces_of(self, cells: np.ndarray) -> np.ndarray:
        """The shared faces of these cells (indices into ``lab.faces``)."""
        if len(cells) == 0:
            return np.zeros(0, np.int64)
        return np.unique(np.concatenate([self.cell_faces[self.cell_ptr[c] : self.cell_ptr[c + 1]] for c in cells]))

    def pieces(self) -> tuple[np.ndarray, np.ndarray]:
        """Per sample, the number of same-label pieces of its star; and each (cell, corner)'s piece."""
        lab = self.lab
        n, w = lab.n, self.w
        s = lab.simplices
        inside = lab.inside
        fa, fb = [], []
        same = inside[lab.a] == inside[lab.b]
        for c in range(lab.faces.shape[1]):
            v = lab.faces[:, c]
            keep = same & (v < n)
            a, b, vk = lab.a[keep], lab.b[keep], v[keep]
            ia = np.argmax(s[a] == vk[:, None], axis=1)
            ib = np.argmax(s[b] == vk[:, None], axis=1)
            fa.append(a * w + ia)
            fb.append(b * w + ib)
        fa_, fb_ = np.concatenate(fa), np.concatenate(fb)
        size = len(s) * w
        g = coo_matrix((np.ones(len(fa_), np.int8), (fa_, fb_)), shape=(size, size))
        _, comp = connected_components(g, directed=False)
        vert = s.ravel()
        ok = vert < n
        key = np.unique(vert[ok].astype(np.int64) * size + comp[ok])
        return np.bincount((key // size).astype(np.int64), minlength=n), comp

    def piece_counts(self) -> np.ndarray:
        """Per sample, the number of same-label pieces of its star (:meth:`pieces`' first array)."""
        if _kernel is None or not self.lab.inside.flags.c_contiguous:
            return self.pieces()[0]
        return np.frombuffer(_kernel.piece_counts(self.lab.faces.shape[1], *self._k_arrays, self.lab.inside), np.int64)

    def star_pieces(self, v: int) -> tuple[np.ndarray, np.ndarray]:
        """The cells of v's star and each one's piece (same label, joined through faces at v).

        What :meth:`pieces` gives for one vertex, from its star alone.
        """
        lab = self.lab
        cells = self.star(v)
        key = (v, lab.inside[cells].tobytes())
        hit = self._pieces.get(key)
        if hit is not None:
            return hit
        if _kernel is not None and lab.inside.flags.c_contiguous:
            comp = np.frombuffer(
                _kernel.star_pieces(v, lab.faces.shape[1], *self._k_arrays, lab.inside),
                np.int64,
            )
        else:
            comp = self._star_pieces_py(v, cells)
        comp.flags.writeable = False  # shared by every later call with the same star labels
        self._pieces[key] = (cells, comp)
        return cells, comp

    def _star_pieces_py(self, v: int, cells: np.ndarray) -> np.ndarray:
        """:meth:`star_pieces` in Python: the reference of the compiled kernel's union-find."""
        lab = self.lab
        fs = self.faces_of(cells)
        fs = fs[(lab.faces[fs] == v).any(axis=1)]
        fs = fs[lab.inside[lab.a[fs]] == lab.inside[lab.b[fs]]]
        # a star has a few dozen cells: a plain union-find beats building a sparse graph
        pos = {c: i for i, c in enumerate(cells.tolist())}
        parent = list(range(len(cells)))

        def root(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for a, b in zip(lab.a[fs].tolist(), lab.b[fs].tolist(), strict=True):
            ra, rb = root(pos[a]), root(pos[b])
            if ra != rb:
                parent[ra] = rb
        _, comp = np.unique(np.array([root(i) for i in range(len(cells))], np.int64), return_inverse=True)
        return comp.reshape(-1).astype(np.int64)

    def flip(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Give ``cells`` the other label: the faces (ids into ``lab.faces``) M_S loses and gains."""
        lab = self.lab
        lab.inside[cells] = ~lab.inside[cells]
        fs = self.faces_of(cells)
        now = lab.inside[lab.a[fs]] != lab.inside[lab.b[fs]]
        removed, added = fs[self.cut[fs] & ~now], fs[~self.cut[fs] & now]
        self.cut[fs] = now
        return removed, added

    def repair(self) -> list[tuple[int, np.ndarray, np.ndarray, np.ndarray]]:
        """``repair-vertex`` until no vertex pinches: (vertex, flipped cells, removed, added) per step.

        One pass over every star finds the pinched vertices; after that only
        the vertices of flipped cells can change, so each round looks at
        those (and at the pinched ones an earlier flip of the round touched)
        with :meth:`star_pieces`.
        """
        lab = self.lab
        self.cut = lab.cut()
        steps = []
        todo = np.flatnonzero(self.piece_counts() > 2).tolist()
        # cells this rule has flipped there and back twice (PING_PONG): two neighbours undo each other's
        # repair (the turbine blade at 0.3 h: four cells, 30 rounds).  From then on their piece is kept
        # and the rule flips the star's other pieces instead
        flips = np.zeros(lab.m, np.int8)
        for _ in range(REPAIR_ROUNDS):
            if not todo:
                break
            touched = np.zeros(lab.m, bool)
            again: set[int] = set()
            for v in todo:
                cells, piece = self.star_pieces(v)
                if piece.max(initial=-1) + 1 <= 2:
                    continue
                if touched[cells].any():
                    again.add(v)  # its star changed in this round: the next round looks again
                    continue
                flipped = self._minor_pieces(cells, piece, flips)
                if len(flipped) == 0:
                    continue
                flips[flipped] += 1
                touched[cells] = True
                steps.append((v, flipped, *self.flip(flipped)))
                near = np.unique(lab.simplices[flipped])
                again.update(int(u) for u in near[near < lab.n].tolist())
            todo = sorted(again)
        return steps

    def repair_ridges(
        self, cancel: object | None = None
    ) -> list[tuple[tuple[int, ...], np.ndarray, np.ndarray, np.ndarray]]:
        """``repair-vertex`` where M_S pinches in R^k, k >= 4, unseen by star pieces: (place, cells, removed, added).

        In R^3 a pinch always shows at a vertex: the link of a vertex is a 2-sphere, and two pieces of one
        label that touch at a point of it are two pieces.  In R^k, k >= 4, the link is a (k-1)-sphere, and
        the vertex test can pass where M_S is no manifold:

        * around a ridge (a (k-2)-face in more than two faces of M_S: in and out alternate around it) the
          pieces touch while joined elsewhere in the star.  The cells around the ridge form a ring; as at
          a vertex, the most confident run of each label stays and the other runs take the other label;
        * at a vertex whose star has one piece of each label but whose link in M_S (their interface) is no
          sphere.  Its star takes the label of its more confident side, so it leaves M_S, and
          ``sculpt-sample`` brings it back through one cell (Boissonnat's rule, which keeps a manifold).

        Rounds of both, with the vertex repair (:meth:`repair`) after each, until nothing pinches or
        :data:`REPAIR_ROUNDS` rounds have run; a cell flipped :data:`PING_PONG` times around ridges keeps its
        label from then on, as in :meth:`repair` (S^3 at 6 % noise: two rings undid each other's repair).
        """
        lab = self.lab
        steps: list[tuple[tuple[int, ...], np.ndarray, np.ndarray, np.ndarray]] = []
        flips = np.zeros(lab.m, np.int8)
        for _ in range(REPAIR_ROUNDS):
            check_cancel(cancel)
            faces = lab.faces[self.cut]
            if len(faces) == 0 or faces.shape[1] < 4:
                break
            # the rows are sorted, so each ridge (a column dropped) is too
            ridges = np.concatenate([np.delete(faces, j, axis=1) for j in range(faces.shape[1])])
            uniq, inverse = unique_rows(ridges)
            bad = uniq[np.bincount(inverse.ravel(), minlength=len(uniq)) > 2]
            before = len(steps)
            touched = np.zeros(lab.m, bool)
            for r in bad.tolist():
                cells = self.star(r[0])
                for v in r[1:]:
                    cells = np.intersect1d(cells, self.star(v), assume_unique=True)
                if touched[cells].any():
                    continue  # its ring changed in this round: looked at again in the next
                flipped = self._minor_pieces(cells, self._ring_pieces(cells), flips)
                if len(flipped):
                    flips[flipped] += 1
                    touched[cells] = True
                    steps.append((tuple(r), flipped, *self.flip(flipped)))
            if len(bad) == 0:
                for v in singular_vertices(faces, all_faces(faces)).tolist():
                    cells = self.star(v)
                    cells = cells[~lab.outside[cells]]
                    side = lab.inside[cells]
                    if touched[cells].any() or side.all() or not side.any():
                        continue
                    conf = lab.confidence[cells]
                    flipped = cells[side != (conf[side].sum() >= conf[~side].sum())]
                    touched[cells] = True
                    steps.append(((int(v),), flipped, *self.flip(flipped)))
            if len(steps) == before:
                break
            steps.extend(((int(v),), c, rem, add) for v, c, rem, add in self.repair())
        return steps

    def _minor_pieces(self, cells: np.ndarray, piece: np.ndarray, flips: np.ndarray) -> np.ndarray:
        """The cells to flip where ``cells`` (a star, or a ring around a ridge) hold more than one piece of a label.

        The most confident piece of each label stays (confidence summed over the piece; a piece with a cell
        flipped :data:`PING_PONG` times counts as the most confident), every other piece's cells go, but for
        the fixed outside cells and those already flipped PING_PONG times.
        """
        lab = self.lab
        n_p = int(piece.max()) + 1
        is_in = np.zeros(n_p, bool)
        is_in[piece] = lab.inside[cells]
        weight = np.bincount(piece, weights=lab.confidence[cells], minlength=n_p)
        pinned = flips[cells] >= PING_PONG
        if pinned.any():
            weight += np.bincount(piece, weights=pinned * (1.0 + weight.sum()), minlength=n_p)
        keep = [int(c[np.argmax(weight[c])]) for c in (np.flatnonzero(is_in), np.flatnonzero(~is_in)) if len(c)]
        flipped = cells[~np.isin(piece, keep)]
        return flipped[~lab.outside[flipped] & (flips[flipped] < PING_PONG)]

    def _ring_pieces(self, cells: np.ndarray) -> np.ndarray:
        """The runs of one label among the cells around a ridge (joined through the faces they share)."""
        lab = self.lab
        fs = self.faces_of(cells)
        fs = fs[np.isin(lab.a[fs], cells) & np.isin(lab.b[fs], cells)]
        fs = fs[lab.inside[lab.a[fs]] == lab.inside[lab.b[fs]]]
        pos = np.searchsorted(cells, np.r_[lab.a[fs], lab.b[fs]])
        g = coo_matrix((np.ones(len(fs), np.int8), (pos[: len(fs)], pos[len(fs) :])), shape=(len(cells),) * 2)
        return connected_components(g, directed=False)[1].astype(np.int64)

    def _fits(self, v: int, c: int, unit: np.ndarray) -> bool:
        """Whether cell ``c``'s faces through sample ``v`` are at most SIZE_MAX local spacings (``unit``).

        A k-cell has k faces through each of its vertices (three triangles in R^3).
        """
        lab = self.lab
        rest = [int(u) for u in lab.simplices[c].tolist() if u != v]
        through = np.array([[v, *other] for other in combinations(rest, len(rest) - 1)], dtype=np.int64)
        return bool((face_sizes(lab.points, unit, through) <= SIZE_MAX).all())

    def _star_fits(self, vs: list[int], unit: np.ndarray) -> dict[tuple[int, int], bool]:
        """:meth:`_fits` for every inside-or-outside (not fixed) cell of the stars of ``vs``: {(v, cell): fits}."""
        lab = self.lab
        if not vs:
            return {}
        v = np.asarray(vs, np.int64)
        cells, count = _gather(self.star_ptr, self.star_cells, v)
        owner = np.repeat(v, count)
        keep = ~lab.outside[cells]
        cells, owner = cells[keep], owner[keep]
        if len(cells) == 0:
            return {}
        simp = lab.simplices[cells]
        w = simp.shape[1]
        # each cell's other vertices in their order (v is a vertex of each once), and its faces through v as
        # _fits lists them: v, then each (w - 2)-subset of the others, in combinations' order
        rest = simp[simp != owner[:, None]].reshape(len(cells), w - 1)
        subsets = list(combinations(range(w - 1), w - 2))
        through = np.concatenate(
            [np.broadcast_to(owner[:, None, None], (len(cells), len(subsets), 1)), rest[:, subsets]], axis=2
        ).reshape(-1, w - 1)
        ok = (face_sizes(lab.points, unit, through) <= SIZE_MAX).reshape(len(cells), -1).all(axis=1)
        return dict(zip(zip(owner.tolist(), cells.tolist()), ok.tolist()))

    def _opposite_on_cut(self, v: int, cells: np.ndarray) -> list[int]:
        """The cells of ``cells`` (v's star) with exactly one face on M_S, the face opposite ``v``; in order."""
        if len(cells) == 0:
            return []
        fs, count = _gather(self.cell_ptr, self.cell_faces, cells)
        owner = np.repeat(np.arange(len(cells)), count)
        on = self.cut[fs]
        on_count = np.bincount(owner[on], minlength=len(cells))
        # of a cell with one face on M_S, that face; whether it has v as a vertex
        through_v = np.zeros(len(cells), bool)
        through_v[owner[on]] = (self.lab.faces[fs[on]] == v).any(axis=1)
        return cells[(on_count == 1) & ~through_v].tolist()

    def _unit(self) -> np.ndarray:
        """Each sample's spacing for :meth:`_fits`.

        The larger of its nearest-neighbour distance and the largest enclosing radius of the faces of M_S
        at it (the sampling radius across long thin triangles).
        """
        lab = self.lab
        faces = lab.faces[self.cut]
        faces = faces[(faces < lab.n).all(axis=1)]
        cover = enclosing_cover(lab.points, faces) if len(faces) else np.zeros(lab.n)
        return np.maximum(lab.spacing, cover)

    def sculpt(self, free: frozenset = frozenset()) -> list[tuple[int, np.ndarray, np.ndarray, np.ndarray]]:
        """``sculpt-sample`` for every sample that is no vertex: (sample, flipped cell, removed, added).

        The samples in ``free`` are sculpted without the size bound (the least confident cell, as Boissonnat's
        rule has it): those that ``insert-sample`` could not take in a first run (:func:`.cells.extract_by_labels`).
        The samples the bound kept from every cell are left in :attr:`held` for that run to look at.
        """
        lab = self.lab
        self.cut = lab.cut()
        self.held: set[int] = set()
        steps = []
        for _ in range(SCULPT_ROUNDS):
            fv = lab.faces[self.cut].ravel()
            on = np.zeros(lab.n, bool)
            on[fv[fv < lab.n]] = True
            touched = np.zeros(lab.m, bool)
            done = 0
            unit = self._unit() if not on.all() else lab.spacing
            # the size bound depends on the cells' shapes and this round's unit only: measured for every star
            # cell of every sample off M_S at once (the same values as one cell at a time)
            fit = self._star_fits([v for v in np.flatnonzero(~on).tolist() if v not in free], unit)
            for v in np.flatnonzero(~on).tolist():
                cells = self.star(v)
                cells = cells[~lab.outside[cells]]
                if len(cells) == 0 or touched[cells].any():
                    continue
                # exactly one face on M_S, the one opposite v (Boissonnat's rule), and new faces the
                # sample supports (no medial ball carved out)
                able = self._opposite_on_cut(v, cells)
                if not able:
                    continue
                fits = [True] * len(able) if v in free else [fit[v, c] for c in able]
                best, best_conf = -1, np.inf
                for c, ok in zip(able, fits, strict=True):
                    if lab.confidence[c] < best_conf:
                        if ok:
                            best, best_conf = c, float(lab.confidence[c])
                        else:
                            self.held.add(v)
                if best < 0:
                    continue
                self.held.discard(v)
                touched[self.star(v)] = True
                steps.append((v, np.array([best]), *self.flip(np.array([best]))))
                done += 1
            if not done:
                break
        return steps


def _gather(ptr: np.ndarray, data: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The entries of CSR ``rows`` (``data[ptr[r]:ptr[r + 1]]`` for each r, concatenated) and each row's count."""
    lo = ptr[rows]
    count = ptr[rows + 1] - lo
    return data[np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count - lo, count)], count


def face_sizes(points: np.ndarray, spacing: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Circumradius of each triangle over the mean of its vertices' ``spacing``.

    :func:`.grow.size_ratio`'s measure when ``spacing`` is the nearest-neighbour distance; ``sculpt-sample``
    passes its own unit (:meth:`LabelEditor._unit`, never below that distance), so a few triangles are
    measured without the whole sample's nearest-neighbour pass.
    """
    return circumradii(points, triangles) / np.maximum(spacing[triangles].mean(axis=1), 1e-300)
