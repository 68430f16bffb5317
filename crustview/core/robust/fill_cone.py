"""``fill-hole`` in d >= 3: a hole of a d-manifold closed by a cone from one of its vertices.

Surfaces clip ears in a hole's plane (:mod:`.fill_hole`); a 3-manifold has no ears.  Where the Delaunay
faces among a hole's vertices leave it open (their fold limit refuses every closing simplex where noise
folded the complex: S^3 in R^4 with noise of 1 % of its size), the hole is coned from one of its vertices,
after checking that its faces make a sphere; where no cone fits, the rim is eroded and the wider hole
closed again, and a try that does not close is undone, rows and log.  The methods are mixed into
:class:`crustview.core.robust.patcher.Patcher` beside :class:`.fill_hole.FillHole`, which calls
:meth:`ConeFill._fill_cone_or_erode`.
"""

from __future__ import annotations

import itertools
import math

from .complex import Simplex, _facets

#: Erosions of a hole's rim before a cone is given up in d >= 3 (:meth:`ConeFill._fill_cone_or_erode`);
#: each widens the hole by one layer of simplices, and a failed try is undone.  Two, as for surfaces
#: (whose ear clipping gets an unpinch, an erosion and a second erosion: ``fill``).
ERODE_ROUNDS = 2


def parts_sharing(faces: list[Simplex], size: int) -> list[list[Simplex]]:
    """The faces grouped into parts connected through shared sub-faces of ``size`` vertices, in first-face order.

    ``size = 1``: through shared vertices (``fill-hole``'s holes); ``size = d - 1``: through shared
    (d-2)-faces (two holes meeting at a vertex are two parts).
    """
    parent = list(range(len(faces)))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    first: dict[Simplex, int] = {}
    for i, f in enumerate(faces):
        for r in itertools.combinations(f, size):
            if r in first:
                parent[find(i)] = find(first[r])
            else:
                first[r] = i
    parts: dict[int, list[Simplex]] = {}
    for i, f in enumerate(faces):
        parts.setdefault(find(i), []).append(f)
    return list(parts.values())


def _is_sphere(faces: list[Simplex]) -> bool:
    """Whether (d-1)-simplices make a connected closed pseudo-manifold with the Euler characteristic of S^(d-1).

    Every (d-2)-face in exactly two of them, one component through shared (d-2)-faces, and
    V - E + F - ... = 1 + (-1)^(d-1) (2 for the triangles round a hole of a 3-manifold).  Not a proof of a
    sphere in every dimension, but it refuses the torus, two holes at once and pinched rims.
    """
    if not faces:
        return False
    k = len(faces[0])
    ridges: dict[Simplex, list[int]] = {}
    for i, f in enumerate(faces):
        for r in itertools.combinations(f, k - 1):
            ridges.setdefault(r, []).append(i)
    if any(len(ids) != 2 for ids in ridges.values()):
        return False
    if len(parts_sharing(faces, k - 1)) != 1:
        return False
    chi = sum((-1) ** j * len({c for f in faces for c in itertools.combinations(f, j + 1)}) for j in range(k))
    return chi == 1 + (-1) ** (k - 1)


class ConeFill:
    """The cone of ``fill-hole`` for :class:`~crustview.core.robust.patcher.Patcher` (see the module docstring)."""

    def _open_around(self, seed: list[Simplex], verts: set[int]) -> list[Simplex]:
        """The open faces at ``verts`` joined (through shared vertices) to the faces of ``seed`` still open."""
        near = [f for f in self.boundary_near(verts) if len(self.at(f)) == 1]
        keep = {v for f in seed if len(self.at(f)) == 1 for v in f}
        grown = True
        out: list[Simplex] = []
        while grown:
            grown = False
            out = [f for f in near if keep.intersection(f)]
            more = {v for f in out for v in f} - keep
            if more:
                keep |= more
                grown = True
        return out

    def _fill_cone_or_erode(self, hole: list[Simplex], why: str) -> list[Simplex]:
        """:meth:`_fill_cone`; where no cone fits, erode the rim (up to ERODE_ROUNDS times), or undo that.

        A cone fails where a face it needs inside the hole is already a face of two simplices (a membrane
        through the hole: noise folded the complex there).  As for surfaces (:meth:`_erode`), the
        simplices on the rim are removed and the wider hole is closed by Delaunay faces and a cone; if it
        still does not close, the erosion and everything after it are undone (rows and log), so a failed
        try never leaves a larger hole.  Returns the hole's faces still open.
        """
        # a hole of several parts may be coned in part: the flaps are sought round the faces still open
        if self._fill_cone(hole, why) or self._unfold([f for f in hole if len(self.at(f)) == 1], why):
            return []
        mark = len(self.log)
        wider = hole
        touched: set[int] = set()
        for _ in range(ERODE_ROUNDS):
            rim = sorted({ids[0] for f in wider for ids in [self.at(f)] if len(ids) == 1})
            touched |= {v for i in rim for v in self.simp[i]}
            wider = self._erode(wider, why)
            self._fill_delaunay({v for f in wider for v in f} | touched, why)
            wider = [f for f in self.boundary_near(touched) if len(self.at(f)) == 1]
            if (not wider or self._fill_cone(wider, why)) and all(self._star(v) for v in touched):
                return []  # closed, and no sample of the eroded rim lost its last simplex
            if not wider:
                break
        self._undo_to(mark)
        return [f for f in hole if len(self.at(f)) == 1]

    def _undo_to(self, mark: int) -> None:
        """Undo the log after entry ``mark``: the rows it added die, the ones it removed come back."""
        for entry in reversed(self.log[mark:]):
            for i in entry[2]:
                if self.alive[i]:
                    self._delete(i)
            for i in entry[3]:
                if not self.alive[i]:
                    self._revive(i)
        del self.log[mark:]

    def _unfold(self, hole: list[Simplex], why: str) -> bool:
        """Remove the flaps folded into a hole, then cone it; undone (rows and log) unless it closes.

        A flap is a simplex with a face on the hole whose vertices all lie on the hole's rim: no sample
        but the rim's supports it, and where noise folded the complex such simplices fill part of the
        hole from the wrong side, so that every cone meets one of their faces (S^3 in R^4 at 1 % noise: a
        hole of 8 triangles on 6 samples, four of whose simplices held half of it).  Without them the hole
        is again a sphere on the same samples, and no sample loses its last simplex (each rim sample has
        simplices outside the hole).  Erosion (:meth:`_fill_cone_or_erode`) removes every simplex on the
        rim instead, which pulls in the samples beyond it.  The test is combinatorial: a sound simplex
        spanned by rim samples goes too, and the cone puts it back or replaces it (the result is kept only
        when the hole closes).  ``hole`` is the faces still open (a cone may have closed part of it).
        """
        if not hole:
            return False
        verts = {v for f in hole for v in f}
        flaps = sorted({i for f in hole for i in self.at(f) if verts.issuperset(self.simp[i])})
        if not flaps:
            return False
        mark = len(self.log)
        for i in flaps:
            self._delete(i)
        self.log.append(
            (
                "fill-hole",
                tuple(hole[0]),
                (),
                tuple(flaps),
                math.nan,
                f"{why}: no cone fits, and {len(flaps)} "
                + (
                    "simplex spanned by the hole's own samples was"
                    if len(flaps) == 1
                    else "simplices spanned by the hole's own samples were"
                )
                + " folded into it: removed, and the hole closed again",
            )
        )
        wider = [f for f in self.boundary_near(verts) if len(self.at(f)) == 1]
        if wider and self._fill_cone(wider, why) and all(self._star(v) for v in verts):
            return True
        self._undo_to(mark)
        return False

    def _fill_cone(self, hole: list[Simplex], why: str) -> bool:
        """Close a hole of a d-manifold, d >= 3, by coning it from one of its vertices (each part all or nothing).

        The hole's faces are a (d-1)-sphere S when it is a hole of a manifold.  For a vertex v of S the
        cone v * (S - star(v)) is a d-ball whose boundary is S, so adding the simplices v + t (t a face of S
        without v) closes the hole.  The smallest hole, the d + 1 faces of one missing simplex, is closed
        by that simplex (the cone from any of its vertices).  Surfaces clip ears in the hole's plane
        instead, and ``fill-hole`` tries the Delaunay faces among the rim first; this runs where those
        left the hole open, because their fold limit (COS_FILL) refuses every closing simplex: in noisy
        3-manifolds (S^3 in R^4 with noise of 1 % of its size) whole holes are one missing simplex, folded.
        A cone is kept only when every new simplex is new, every new interior face lies in exactly the two
        new simplices that share it, no face gets a third simplex and no new interior edge (from the apex to
        a hole sample not next to it on the hole) is an edge the complex already has; the vertex whose cone
        has the fewest simplices is tried first.  The cone from a vertex of a closed surface that is not a sphere (a
        torus) passes those counts but leaves that vertex singular (its link the torus): the hole's faces
        must first be a connected closed pseudo-manifold with a sphere's Euler characteristic
        (:func:`_is_sphere`), and in codimension 1 every new simplex orientable with its neighbours.
        """
        closed = True
        faces = [tuple(f) for f in hole]
        for part in parts_sharing(faces, len(faces[0]) - 1):
            # where no cone fits, the Delaunay faces on the part's own samples that bound it (fill_chain.py)
            done = (_is_sphere(part) and self._cone(part, why)) or self._chain(part, why)
            closed = done and closed
        return closed

    def _cone(self, faces: list[Simplex], why: str) -> bool:
        """The cone of :meth:`_fill_cone` over one sphere of faces; False (nothing added) if none fits."""
        verts = sorted({v for f in faces for v in f})
        for v in sorted(verts, key=lambda x: sum(x in f for f in faces), reverse=True):
            new = [tuple(sorted((v, *f))) for f in faces if v not in f]
            if not new or len(set(new)) != len(new) or any(s in self.index for s in new):
                continue
            if not all(self.consistent(s) for s in new):
                continue
            count: dict[Simplex, int] = {}
            for s in new:
                for f in _facets(s):
                    count[f] = count.get(f, 0) + 1
            hole_set = set(faces)
            ok = True
            for f, c in count.items():
                have = len(self.at(f))
                if f in hole_set:
                    ok = c == 1 and have == 1
                else:  # a new face inside the cone: two new simplices, none before
                    ok = c == 2 and have == 0
                if not ok:
                    break
            if not ok:
                continue
            # a new edge inside the cone (from v to a sample of the hole not next to v on it) must be new too:
            # an edge the complex already has elsewhere would get a second ring of simplices, pinching v
            rim_next = {u for f in faces if v in f for u in f}
            linked = {u for i in self._star(v) for u in self.simp[i]}
            if any(u in linked for u in verts if u not in rim_next):
                continue
            mark = len(self.log)
            for s in new:
                tau = next((f for f in _facets(s) if f in hole_set and len(self.at(f)) == 1), _facets(s)[0])
                self.add(s, "fill-hole", tau, math.nan, f"closing a {why} by a cone from sample {v}")
            if all(self._link_unpinched(u) for u in verts):
                return True
            self._undo_to(mark)  # the counts held, but some sample's link is pinched: the next apex
        return False

    def _link_unpinched(self, u: int) -> bool:
        """Whether sample ``u``'s link is one piece, no ridge of it in three faces, and a sphere where it is closed.

        The face counts of :meth:`_cone` see the hole's own faces; a cone over a hole whose neighbourhood
        noise folded can still give a sample of the rim a link that is closed but not a sphere (S^3 in R^4
        at 1 %: a link with Euler characteristic 1), pinching M_S there.  A link with a boundary (another
        hole at ``u``, not closed yet) passes when it is one piece.
        """
        link = [tuple(w for w in self.simp[i] if w != u) for i in self._star(u)]
        if not link:
            return False
        k = len(link[0])
        ridges: dict[Simplex, int] = {}
        for f in link:
            for r in itertools.combinations(f, k - 1):
                ridges[r] = ridges.get(r, 0) + 1
        if any(c > 2 for c in ridges.values()) or len(parts_sharing(link, k - 1)) != 1:
            return False
        return any(c == 1 for c in ridges.values()) or _is_sphere(link)
