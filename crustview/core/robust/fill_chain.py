"""``fill-hole`` in d >= 3: a hole closed by a chain of Delaunay d-faces on its own samples that it bounds.

Why
---
A hole of a d-manifold is a (d - 1)-cycle of boundary faces.  The cone of :mod:`.fill_cone` closes it from
one of its vertices when its faces form a sphere and no edge from that vertex across the hole exists
already.  Under noise neither always holds: S^3 in R^4 with noise of 3 % of its reach (2,000 samples,
0.15 spacings) left holes of 8-26 faces, 2.6-6 spacings across, some of them two spheres sharing an edge
(not one sphere, so no cone) and some spheres whose every apex already had an edge across the hole; the
result was open with b_2 = 10.

The rule
--------
Where the cone fails, the hole is closed by Delaunay d-faces spanned by its own samples, exactly when they
can bound it: a set X of them whose boundary (mod 2) is the hole.  Over Z/2 this is the linear system
"each hole face lies in an odd number of the chosen simplices, every other face of a candidate in an even
number", solved by Gaussian elimination (each face's row a Python integer, a bit per candidate).  A
candidate may only use faces that are the hole's own (each in one simplex of M_S now) or in no simplex of
M_S; among the system's solutions (the particular one plus up to :data:`CHAIN_KERNEL` independent closed
chains of candidates) the smallest that gives each new inner face exactly two simplices, adds no inner
edge the complex already has (a second ring of simplices around it), keeps every simplex orientable with
its neighbours (codimension 1) and every sample's link unpinched is kept; if none does, nothing is added.
No fold limit applies: the hole must be one that ``fill-hole`` takes for a gap (at most FILL_MAX_FACES
faces and FILL_MAX_SPAN spacings, checked again here since an erosion widens holes, and no opening
``open-cap`` kept), and the Delaunay faces on its own samples are the restricted-Delaunay answer there,
as the surfaces' first try (:meth:`.fill_hole.FillHole._fill_delaunay`) is.  Its steps are ``fill-hole``
steps; the methods are mixed into :class:`crustview.core.robust.patcher.Patcher`.
"""

from __future__ import annotations

import itertools
import math

from .complex import Simplex, _facets
from .fill_hole import FILL_MAX_FACES, FILL_MAX_SPAN, gap_span

#: Largest number of candidate simplices for the Z/2 system (a hole of at most FILL_MAX_FACES = 50 faces
#: has far fewer Delaunay d-faces on its samples; a bound on the work, not a tuned value).
CHAIN_MAX = 400
#: Independent closed chains of candidates combined with the particular solution: 2^8 = 256 tries at most
#: (a bound on the work, no tuned value).  A closed chain on a hole's own samples is a whole small sphere of
#: Delaunay faces (the five tetrahedra of a 4-simplex's boundary); an octahedral hole of 6 samples already has
#: 5 of them, and a try that fails the face counts costs a few dictionary lookups.
CHAIN_KERNEL = 8


def _solve_gf2(rows: list[int], rhs: list[int], ncols: int) -> tuple[int, list[int]] | None:
    """A solution x (bit j = column j) of rows . x = rhs over Z/2, and a basis of the kernel; None if none.

    ``rows[i]`` has bit j set when column j enters equation i.
    """
    pivots: list[tuple[int, int, int]] = []  # (pivot column, row, rhs), in elimination order
    for r, b in zip(rows, rhs, strict=True):
        for col, prow, pb in pivots:
            if r >> col & 1:
                r ^= prow
                b ^= pb
        if r == 0:
            if b:
                return None  # inconsistent: the hole bounds no chain of these candidates
            continue
        col = r.bit_length() - 1
        # keep earlier pivot rows reduced in the new pivot column (reduced echelon form)
        pivots = [(c, pr ^ r, pb ^ b) if pr >> col & 1 else (c, pr, pb) for c, pr, pb in pivots]
        pivots.append((col, r, b))
    x = 0
    for col, _, b in pivots:
        if b:
            x |= 1 << col
    pivot_cols = {c for c, _, _ in pivots}
    kernel = []
    for free in range(ncols):
        if free in pivot_cols:
            continue
        v = 1 << free
        for col, prow, _ in pivots:
            if prow >> free & 1:
                v |= 1 << col
        kernel.append(v)
    return x, kernel


class ChainFill:
    """The Z/2 chain of ``fill-hole`` for :class:`~crustview.core.robust.patcher.Patcher` (module docstring)."""

    def _chain(self, faces: list[Simplex], why: str) -> bool:
        """Close the hole ``faces`` by Delaunay d-faces on its samples that bound it; False if none fits."""
        verts = {v for f in faces for v in f}
        hole = set(faces)
        # only a hole fill-hole itself takes for a gap (the erosion widens holes past its bounds), never
        # an opening open-cap kept (the module docstring's reason for no fold limit holds only there)
        if len(faces) > FILL_MAX_FACES or (self.keep_open and not hole.isdisjoint(self.keep_open)):
            return False
        span, local = gap_span(self.points, sorted(verts), self.nn, self.spacing)
        if span > FILL_MAX_SPAN * local:
            return False
        cand: set[Simplex] = set()
        for v in verts:
            for fi in self.vfaces[self.vptr[v] : self.vptr[v + 1]]:
                row = tuple(int(x) for x in self.delaunay[fi])
                if verts.issuperset(row) and row not in self.index:
                    cand.add(row)
        usable = [s for s in sorted(cand) if all(len(self.at(f)) == (1 if f in hole else 0) for f in _facets(s))]
        if not usable or len(usable) > CHAIN_MAX:
            return False
        row_of: dict[Simplex, int] = {}
        for s in usable:
            for f in _facets(s):
                row_of.setdefault(f, len(row_of))
        if not hole.issubset(row_of):
            return False
        rows = [0] * len(row_of)
        for j, s in enumerate(usable):
            for f in _facets(s):
                rows[row_of[f]] |= 1 << j
        rhs = [0] * len(row_of)
        for f in faces:
            rhs[row_of[f]] = 1
        solved = _solve_gf2(rows, rhs, len(usable))
        if solved is None:
            return False
        x, kernel = solved
        tries = set()
        for pick in itertools.product((0, 1), repeat=min(len(kernel), CHAIN_KERNEL)):
            y = x
            for use, k in zip(pick, kernel, strict=False):
                if use:
                    y ^= k
            if y:
                tries.add(y)
        for y in sorted(tries, key=lambda y: (bin(y).count("1"), y)):
            chosen = [s for j, s in enumerate(usable) if y >> j & 1]
            if self._add_chain(chosen, hole, verts, why):
                return True
        return False

    def _add_chain(self, chosen: list[Simplex], hole: set[Simplex], verts: set[int], why: str) -> bool:
        """Add ``chosen`` (from the hole inwards) if each new inner face gets two simplices; undone otherwise."""
        count: dict[Simplex, int] = {}
        for s in chosen:
            for f in _facets(s):
                count[f] = count.get(f, 0) + 1
        if any(c != (1 if f in hole else 2) for f, c in count.items()):
            return False
        # a new edge inside the chain (on no hole face) that the complex already has would get a second ring
        # of simplices around it, pinching its ends (the cone refuses the same, fill_cone.py)
        rim_edges = {e for f in hole for e in itertools.combinations(f, 2)}
        inner = {e for s in chosen for e in itertools.combinations(s, 2)} - rim_edges
        for a, b in inner:
            if any(b in self.simp[i] for i in self._star(a)):
                return False
        mark = len(self.log)
        left = list(chosen)
        while left:  # each simplex next to one already there: orientations propagate from the rim
            nxt = next((s for s in left if any(self.at(f) for f in _facets(s))), left[0])
            if not self.consistent(nxt):
                self._undo_to(mark)
                return False
            tau = next((f for f in _facets(nxt) if len(self.at(f)) == 1), _facets(nxt)[0])
            self.add(
                nxt,
                "fill-hole",
                tau,
                math.nan,
                f"closing a {why} by {len(chosen)} Delaunay faces on its own samples that bound it",
            )
            left.remove(nxt)
        if all(self._link_unpinched(u) for u in verts):
            return True
        self._undo_to(mark)
        return False
