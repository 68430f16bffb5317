"""The complex that the robust extension's last phase edits: M_S as dictionaries.

:class:`EditableComplex` holds the simplices, the vertex stars and the
(d-1)-faces with their simplices, so that ``fill-hole``
(:mod:`.fill_hole`), ``drop-stray`` (:mod:`.drop_stray`) and
``insert-sample`` (:mod:`.insert_sample`) can add and remove simplices one
at a time, outside the Delaunay triangulation where no Delaunay face fits.
:class:`~.patcher.Patcher` puts the rules and this complex together.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ..paper.facets import facet_structure

#: A closing simplex may meet its neighbours at phi > 60 deg (creases up to 120 deg).
COS_FILL = 0.5

Simplex = tuple[int, ...]


def _facets(s: Simplex) -> list[Simplex]:
    return [s[:a] + s[a + 1 :] for a in range(len(s))]


_MUTABLE = (list, set, dict, np.ndarray)


def _copied(value: object, depth: int) -> object:
    """``value`` with its lists, sets, dicts and arrays copied ``depth`` levels down (see ``trial_copy``).

    Tuples, frozensets, numbers, strings and None are immutable and shared; anything else is refused, and
    so is a container nested deeper than ``depth``: a copy that could share state is a bug to see.
    """
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, _MUTABLE):
        if depth == 0:
            raise TypeError(f"trial_copy: a {type(value).__name__} nested deeper than the complex keeps one")
        if isinstance(value, list):
            return [_copied(v, depth - 1) if isinstance(v, _MUTABLE) else v for v in value]
        if isinstance(value, set):
            return set(value)  # its items are hashable: immutable
        return {k: _copied(v, depth - 1) if isinstance(v, _MUTABLE) else v for k, v in value.items()}
    if value is None or isinstance(value, (int, float, str, tuple, frozenset, np.generic)):
        return value
    raise TypeError(f"trial_copy: no rule to copy a {type(value).__name__}")


class EditableComplex:
    """A d-complex as dictionaries, for local edits.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    simplices : list of sorted tuples
        The current complex.
    delaunay : ndarray of shape (f, d + 1)
        Sorted Delaunay d-faces, preferred for closing holes.
    spacing : float
        Median nearest-neighbour distance.
    """

    def __init__(
        self,
        points: np.ndarray,
        simplices: list[Simplex],
        delaunay: np.ndarray,
        spacing: float,
        orient: list[int] | None = None,
        orientable: bool = False,
    ) -> None:
        self.points = points
        #: +1/-1 per simplex (relative to its sorted vertex order); 0 when unknown
        self.orient: list[int] = []
        #: codimension 1: refuse every addition that would make M_S non-orientable
        self.orientable = orientable
        self.spacing = float(spacing)
        self.simp: list[Simplex] = []
        self.alive: list[bool] = []
        self.fmap: dict[Simplex, list[int]] = {}
        self.bset: set[Simplex] = set()  # facets with exactly one simplex
        self.index: dict[Simplex, int] = {}  # alive simplex -> id
        self.star: dict[int, set[int]] = {}  # vertex -> alive simplex ids (see _star)
        self._star_ptr: np.ndarray | None = None
        self._star_own = np.empty(0, dtype=np.int64)
        self._used0 = np.zeros(len(points), dtype=bool)
        #: vertices whose star changed since the last :meth:`unpinch_all` (where pinches can appear)
        self.suspects: set[int] = set()
        self.log: list[tuple[str, Simplex, tuple[int, ...], tuple[int, ...], float, str]] = []
        #: the initial simplices as an array (rows of :attr:`simp` below its length never change)
        self.initial = np.zeros((0, 0), np.int64)
        self._bulk_insert(simplices, orient)
        self.delaunay = delaunay

    # -- lookups built on first use (most runs never need them) ---------------
    @cached_property
    def nn(self) -> np.ndarray:
        """Distance from each sample to its nearest other sample."""
        from ..util.nearest import nearest_distances

        return nearest_distances(self.points)

    @cached_property
    def _vstar(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR of the Delaunay faces at each vertex: (pointer, face ids)."""
        flat = self.delaunay.ravel()
        order = np.argsort(flat, kind="stable")
        vptr = np.concatenate([[0], np.cumsum(np.bincount(flat, minlength=len(self.points)))])
        return vptr, (order // self.delaunay.shape[1] if self.delaunay.size else order)

    @property
    def vptr(self) -> np.ndarray:
        return self._vstar[0]

    @property
    def vfaces(self) -> np.ndarray:
        return self._vstar[1]

    def _ids(self, f: Simplex) -> list[int]:
        """The alive simplices at (d-1)-face f, ascending; built from the stars on first use."""
        ids = self.fmap.get(f)
        if ids is None:
            simp = self.simp
            ids = sorted(i for i in self._star(f[0]) if all(v in simp[i] for v in f[1:]))
            self.fmap[f] = ids
        return ids

    def trial_copy(self) -> EditableComplex:
        """An independent copy to try an edit on (what ``copy.deepcopy`` gives, at a fraction of its cost).

        The complex and its rules keep lists, sets and dicts whose items are ints, tuples of ints, strings or
        frozensets, and whose dict values are such items or lists and sets of them: each container is copied
        to that depth and each array is copied, so no edit of the copy reaches this complex.  The samples and
        the Delaunay faces, which no rule writes, are shared.  ``copy.deepcopy`` walked every tuple of every
        simplex, star and log entry: 3.0 of 3.8 s in ``cut-loop`` over the core tests' grown surfaces.
        """
        new = object.__new__(type(self))
        for key, value in self.__dict__.items():
            if key in ("points", "delaunay"):
                new.__dict__[key] = value
            else:
                new.__dict__[key] = _copied(value, 2)
        return new

    # -- editing ------------------------------------------------------------
    def _bulk_insert(self, simplices: list[Simplex], orient: list[int] | None) -> None:
        """The state :meth:`_insert` would build for ``simplices``, built with array operations."""
        m = len(simplices)
        self.simp = list(simplices)
        self.alive = [True] * m
        self.orient = list(orient) if orient is not None else [0] * m
        self.index = {t: i for i, t in enumerate(self.simp)}
        if m == 0:
            return
        arr = np.array(self.simp, dtype=np.int64)
        self.initial = arr
        facets, _, ptr, _ = facet_structure(arr)
        # the facet -> simplices map is filled lazily by _ids (from the stars)
        self.bset = set(map(tuple, facets[np.diff(ptr) == 1].tolist()))
        # vertex stars as CSR; a vertex's set in self.star is made on first use (see _star)
        flat = arr.ravel()
        order = np.argsort(flat, kind="stable")
        self._star_ptr = np.concatenate([[0], np.cumsum(np.bincount(flat, minlength=len(self.points)))])
        self._star_own = order // arr.shape[1]
        self._used0 = np.zeros(len(self.points), dtype=bool)
        self._used0[flat] = True

    def _star(self, v: int) -> set[int]:
        """The alive simplices at vertex v (made from the initial complex on first use, then kept)."""
        st = self.star.get(v)
        if st is None:
            if self._star_ptr is not None and v < len(self._star_ptr) - 1:
                st = set(self._star_own[self._star_ptr[v] : self._star_ptr[v + 1]].tolist())
            else:
                st = set()
            self.star[v] = st
        return st

    def _insert(self, s: Simplex, orient: int = 0) -> int:
        i = len(self.simp)
        self.simp.append(s)
        self.orient.append(orient)
        self.alive.append(False)
        self._revive(i)
        return i

    def _delete(self, i: int) -> None:
        self._link(i, False)

    def _revive(self, i: int) -> None:
        """Link simplex ``i`` (a row of :attr:`simp`) into the complex: a new row, or one :meth:`_delete` removed."""
        self._link(i, True)

    def _link(self, i: int, alive: bool) -> None:
        """Add simplex ``i`` to (or take it from) the index, its vertices' stars and its facets' lists."""
        self.alive[i] = alive
        s = self.simp[i]
        at = [(f, self._ids(f)) for f in _facets(s)]  # before i joins or leaves the stars
        if alive:
            self.index[s] = i
        else:
            del self.index[s]
        for v in s:
            (self._star(v).add if alive else self._star(v).discard)(i)
        self.suspects.update(s)
        for f, ids in at:
            (ids.append if alive else ids.remove)(i)
            self._mark(f, ids)

    def _mark(self, f: Simplex, ids: list[int]) -> None:
        if len(ids) == 1:
            self.bset.add(f)
        else:
            self.bset.discard(f)

    def at(self, f: Simplex) -> list[int]:
        return self._ids(f)

    def boundary(self) -> list[Simplex]:
        return sorted(self.bset)

    def boundary_near(self, vs: set[int]) -> list[Simplex]:
        """The boundary faces with a vertex in ``vs``, in :meth:`boundary`'s order.

        A boundary face at v lies in the one simplex of v's star that has it,
        so the stars of ``vs`` hold them all: no pass over the whole boundary.
        """
        out = set()
        bset, simp = self.bset, self.simp
        for v in vs:
            for i in self._star(v):
                for f in _facets(simp[i]):
                    if f in bset and v in f:
                        out.add(f)
        return sorted(out)

    def rows(self, ids: np.ndarray) -> np.ndarray:
        """The simplices ``ids`` (ascending) as an array: the initial ones sliced, the added ones converted."""
        m0 = len(self.initial)
        late = ids[ids >= m0].tolist()
        if not late:
            return self.initial[ids]
        added = np.array([self.simp[i] for i in late], dtype=np.int64).reshape(len(late), -1)
        return np.vstack([self.initial[ids[ids < m0]], added]) if m0 else added

    def used(self) -> np.ndarray:
        mask = self._used0.copy()
        for v, ids in self.star.items():  # the stars made so far are the ones that changed
            mask[v] = bool(ids)
        return mask

    # -- geometry -----------------------------------------------------------
    def _u(self, s: Simplex, f: Simplex) -> np.ndarray:
        """Unit vector from aff(f) to the vertex of s opposite f."""
        (apex,) = set(s) - set(f)
        p = self.points
        v = p[apex] - p[f[0]]
        if len(f) == 2:  # an edge: one projection (what QR does, without its overhead)
            e = p[f[1]] - p[f[0]]
            v = v - (float(v @ e) / max(float(e @ e), 1e-300)) * e
        elif len(f) > 2:
            q, _ = np.linalg.qr((p[list(f[1:])] - p[f[0]]).T)
            v = v - q @ (q.T @ v)
        return v / max(float(np.linalg.norm(v)), 1e-300)

    def fits(self, s: Simplex) -> tuple[bool, float]:
        """Whether ``s`` can be added: every facet in at most one simplex, none folded.

        Returns (ok, largest cos phi with an existing neighbour).
        """
        if s in self.index or not self.consistent(s):
            return False, 2.0
        worst = -1.0
        touching = 0
        for f in _facets(s):
            ids = self.at(f)
            if len(ids) >= 2:
                return False, 2.0
            if ids:
                touching += 1
                c = float(self._u(s, f) @ self._u(self.simp[ids[0]], f))
                worst = max(worst, c)
        return touching > 0 and worst < COS_FILL, worst

    def induced(self, s: Simplex) -> set[int]:
        """Orientations that the neighbours of ``s`` (across its facets) ask it to take."""
        out = set()
        for a, f in enumerate(_facets(s)):
            ids = self.at(f)
            if len(ids) == 1 and self.orient[ids[0]]:
                t = self.simp[ids[0]]
                (apex,) = set(t) - set(f)
                b = t.index(apex)
                out.add(-self.orient[ids[0]] * (-1 if (a + b) % 2 else 1))
        return out

    def consistent(self, s: Simplex) -> bool:
        """Whether ``s`` can be oriented to agree with all its neighbours (or need not)."""
        return not self.orientable or len(self.induced(s)) <= 1

    def add(self, s: Simplex, rule: str, tau: Simplex, angle: float, why: str) -> None:
        ind = self.induced(s)
        i = self._insert(s, ind.pop() if len(ind) == 1 else 0)
        self.log.append((rule, tau, (i,), (), angle, why))
