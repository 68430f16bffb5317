"""Telling a handle across an undersampling gap from a real one, during the walk.

A gluing move of :class:`crustview.core.robust.grow.Grower` joins the growing
surface to itself at a far boundary vertex c.  Within one boundary component
that only splits the component; between two pieces it joins them.  Between
two boundary components of one piece it makes a handle (for d > 2, another
new cycle).  Real handles are closed that way too -- the last seam of a
noisy torus is two long boundary components side by side -- but when either
component is a hole that ``fill-hole`` (:mod:`crustview.core.robust.fill_hole`) would
close, the handle bridges an undersampling gap: on a decimated figure, arm
to torso.  The walk refuses such moves and leaves the hole to be filled.

The methods here are mixed into the Grower: pieces are kept in a
union-find over vertices (pieces only ever merge while growing), and the
boundary component through a vertex is searched over the grown simplices at
each vertex, stopping beyond the size of a fillable hole.
"""

from __future__ import annotations

import numpy as np

from .fill_hole import FILL_MAX_FACES, FILL_MAX_SPAN


class HandleGuard:
    """Gap-handle test for :class:`~crustview.core.robust.grow.Grower` (see the module docstring)."""

    def _find(self, v: int) -> int:
        uf = self._uf
        while uf[v] != v:
            uf[v] = uf[uf[v]]
            v = uf[v]
        return v

    def _union(self, verts) -> None:  # noqa: ANN001 - a sequence of vertex ids
        r0 = self._find(verts[0])
        for v in verts[1:]:
            rv = self._find(v)
            if rv != r0:
                self._uf[rv] = r0

    def _alive_star(self) -> list[list[int]]:
        """The grown simplices at each vertex; built on first use, then kept by :meth:`add`."""
        if self._vstar is None:
            alive = np.flatnonzero(np.frombuffer(bytes(self.alive), dtype=np.uint8))
            flat = self.faces[alive].ravel()
            order = np.argsort(flat, kind="stable")
            ptr = np.concatenate([[0], np.cumsum(np.bincount(flat, minlength=self.n))]).tolist()
            own = alive[order // self.dp1].tolist()
            self._vstar = [own[ptr[v] : ptr[v + 1]] for v in range(self.n)]
        return self._vstar

    def boundary_component(self, v: int, cap: int | None = None) -> tuple[set[int], bool]:
        """Vertices of the boundary component through boundary vertex ``v``.

        Boundary (d-1)-faces sharing a vertex belong to one component (a
        manifold with boundary has no pinched boundary vertex).  The search
        stops after ``cap`` vertices; the flag says whether it saw them all.
        """
        cache = self._bc_cache
        if cap == FILL_MAX_FACES and v in cache:
            return cache[v]
        star = self._alive_star()
        d, dp1 = self.dp1 - 1, self.dp1
        count, fo, fv, verts = self.count, self._fo, self._fverts, self._verts
        seen = {v}
        todo = [v]
        while todo:
            if cap is not None and len(seen) > cap:
                if cap == FILL_MAX_FACES:  # a component over cap vertices is over cap seen from any of them
                    for w in seen:
                        cache[w] = (seen, False)
                return seen, False
            x = todo.pop()
            for f in star[x]:
                base = f * dp1
                for q in range(dp1):
                    if verts[base + q] == x:
                        continue  # the facet opposite x does not contain it
                    h = fo[base + q]
                    if count[h] != 1:
                        continue
                    for w in fv[h * d : (h + 1) * d]:
                        if w not in seen:
                            seen.add(w)
                            todo.append(w)
        if cap == FILL_MAX_FACES:  # the whole component: the same answer from each of its vertices
            for w in seen:
                cache[w] = (seen, True)
        return seen, True

    def _closable(self, verts: set[int]) -> bool:
        """Whether a boundary component is a hole that ``fill-hole`` closes (its size limits)."""
        from ..util.nearest import nearest_distances

        if len(verts) > FILL_MAX_FACES:
            return False
        if self._nn is None:
            self._nn = nearest_distances(self.points)
            self._spacing = float(np.median(self._nn))
        ids = np.fromiter(verts, dtype=np.int64)
        p = self.points[ids]
        span = float(np.sqrt(((p[:, None] - p[None]) ** 2).sum(-1).max())) if len(ids) > 1 else 0.0
        local = max(float(self._nn[ids].mean()), self._spacing)
        return span <= FILL_MAX_SPAN * local

    def makes_gap_handle(self, g: int, c: int) -> bool:
        """Whether gluing at boundary facet ``g`` to vertex ``c`` bridges a hole that would be filled.

        True only between two boundary components of one piece, one of them a
        hole within fill-hole's limits (see the module docstring).
        """
        a = self._fverts[g * (self.dp1 - 1)]
        if self._find(a) != self._find(c):
            return False
        # only holes of at most FILL_MAX_FACES faces can be closed by fill-hole, so the
        # searches stop beyond that: two larger components are left to join (a real seam)
        for start, other in ((a, c), (c, a)):
            comp, whole = self.boundary_component(start, cap=FILL_MAX_FACES)
            if whole:
                if other in comp:
                    return False  # both ends on one component: the move only splits it
                if self._closable(comp):
                    return True  # a handle onto a hole that fill-hole would close
        return False
