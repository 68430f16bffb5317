"""Rule ``fill-hole``: closing small holes and slits, and unpinching (the robust extension's last phase).

A hole (boundary (d-1)-faces connected through their vertices) with at most
:data:`FILL_MAX_FACES` faces and a span of at most :data:`FILL_MAX_SPAN`
sample spacings is an undersampling gap.  It is closed first with Delaunay
d-faces among its own vertices (flattest first, creases up to 120 deg
allowed), then -- for d = 2 -- by clipping ears off each boundary loop
(triangles need not be Delaunay, :mod:`.polygons`), for d = 1 by joining its
two ends.  Larger holes are real boundary and stay open, except a *slit*
(surfaces): one long rim loop only a few spacings wide, the unfinished edge
of a thin plate sampled on both sides, which is closed by ears alone (see
:meth:`FillHole._slit_width`).  A vertex where M_S pinches (its simplices
form several fans) keeps only its largest fan, so that the hole left can be
closed; those steps are ``fill-hole`` steps too.

The methods here are mixed into :class:`~.patcher.Patcher`, whose
:class:`~.complex.EditableComplex` they edit.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial.distance import pdist

from .complex import Simplex, _facets
from .fill_cone import parts_sharing
from .polygons import is_ear, min_angle, orientation, plane_polygon

#: Largest hole, in boundary (d-1)-faces, that ``fill-hole`` closes.
FILL_MAX_FACES = 50
#: Largest hole span, in median sample spacings, that ``fill-hole`` closes.
FILL_MAX_SPAN = 18.0
#: A longer hole is still closed when it is a slit (surfaces only): a single rim loop of at most
#: SLIT_MAX_FACES edges whose median width, measured to rim vertices SLIT_HOPS or more steps away,
#: is at most SLIT_MAX_WIDTH local spacings.  The real cuts of the open scans measure 7.9-12.
SLIT_MAX_FACES = 400
SLIT_HOPS = 8
SLIT_MAX_WIDTH = 4.0
#: An ear may meet its neighbours at phi > 25 deg: a hole's rim leaves no other choice.
COS_EAR = 0.9


def gap_span(points: np.ndarray, verts: list[int], nn: np.ndarray, spacing: float) -> tuple[float, float]:
    """A hole's span as ``fill-hole`` measures it: the largest distance between two of its samples, and its unit.

    The unit is the larger of the samples' mean nearest-neighbour distance (``nn`` of every sample) and the
    sample's median one (``spacing``); a hole is a gap when the span is at most FILL_MAX_SPAN units.
    """
    span = float(pdist(points[verts]).max()) if len(verts) > 1 else 0.0  # compiled: holes of hundreds of vertices
    return span, max(float(nn[verts].mean()), spacing)


class FillHole:
    """``fill-hole`` for :class:`~.patcher.Patcher` (see the module docstring)."""

    # -- holes --------------------------------------------------------------
    def holes(self) -> list[list[Simplex]]:
        """Boundary facets grouped by shared vertices (for curves: all ends in one group)."""
        bnd = self.boundary()
        if bnd and len(bnd[0]) == 1:
            return [bnd]
        return sorted(parts_sharing(bnd, 1), key=len)

    #: Boundary faces of real openings that no rule may close (``open-cap`` leaves them).
    keep_open: frozenset = frozenset()

    def fill(self, hole: list[Simplex]) -> bool:
        """Close one hole if it is small and not a real opening; True when it was closed."""
        opening = bool(self.keep_open) and any(f in self.keep_open for f in hole)
        if opening and len(hole[0]) != 2:
            return False
        verts = sorted({v for f in hole for v in f})
        span, local = gap_span(self.points, verts, self.nn, self.spacing)
        if len(hole[0]) == 1:  # curves: the ends of all paths, joined in pairs below
            self._join_ends(hole, "gap between two ends of the curve")
            return all(len(self.at(f)) != 1 for f in hole)
        why = f"hole of {len(hole)} boundary faces spanning {span / local:.1f} local spacings"
        # an opening that open-cap left is closed only as a slit: the rim of a thin part whose two
        # sides the labelling kept apart (an ear), never by Delaunay faces or ears across it
        if opening or len(hole) > FILL_MAX_FACES or span > FILL_MAX_SPAN * local:
            width = self._slit_width(hole, local) if len(hole[0]) == 2 and len(hole) <= SLIT_MAX_FACES else None
            if width is None or width > SLIT_MAX_WIDTH:
                return False
            why = (
                f"slit of {len(hole)} boundary faces, {span / local:.1f} local spacings long but only "
                f"{width:.1f} wide (a thin part sampled on both sides)"
            )
            # ears only: a disc across the slit, never Delaunay faces between far parts of its
            # rim or erosion of its sides (both split long rims into pinched pieces)
            self._ear_clip(hole, why, zip_3d=True)
            return all(len(self.at(f)) != 1 for f in hole)
        self._fill_delaunay(set(verts), why)
        rest = [f for f in hole if len(self.at(f)) == 1]
        dp1 = len(hole[0]) + 1
        if rest and dp1 > 3:
            # the hole as it is now: the Delaunay faces just added have open faces of their own
            self._fill_cone_or_erode(self._open_around(rest, set(verts)), why)
            rest = [f for f in self._open_around(hole, set(verts)) if len(self.at(f)) == 1]
        if rest and dp1 == 3:
            for attempt in range(3):
                for _ in range(3):
                    if self._loops(rest) is not None:
                        break
                    rest = self._unpinch(rest, why)
                self._ear_clip(rest, why)
                rest = [f for f in rest if len(self.at(f)) == 1]
                if not rest or attempt == 2:
                    break
                rest = self._erode(rest, why)
        elif rest and dp1 == 2:
            self._join_ends(rest, why)
            rest = [f for f in rest if len(self.at(f)) == 1]
        return not rest

    def _slit_width(self, hole: list[Simplex], local: float) -> float | None:
        """Median distance, in local spacings, from each rim vertex across the hole; None if not one loop.

        Across means to the nearest rim vertex at least :data:`SLIT_HOPS`
        steps away along the rim.  Along a real boundary (the cut of an open
        scan) that vertex is itself about SLIT_HOPS spacings away; across a
        slit, the rim of a thin plate whose two sides were grown but not its
        edge, it is the other side, one or two spacings away.
        """
        loops = self._loops(hole)
        if loops is None or len(loops) != 1 or len(loops[0]) <= 2 * SLIT_HOPS:
            return None
        loop = loops[0]
        m = len(loop)
        q = self.points[loop]
        dist = np.sqrt(((q[:, None] - q[None]) ** 2).sum(-1))
        hop = np.abs(np.arange(m)[:, None] - np.arange(m)[None])
        dist[np.minimum(hop, m - hop) < SLIT_HOPS] = np.inf
        return float(np.median(dist.min(axis=1))) / local

    def _erode(self, edges: list[Simplex], why: str) -> list[Simplex]:
        """Remove the simplices on the hole's rim (they block every ear); returns the new rim."""
        rim = sorted({ids[0] for f in edges for ids in [self.at(f)] if len(ids) == 1})
        touched = {v for i in rim for v in self.simp[i]}
        for i in rim:
            self._delete(i)
        self.log.append(
            (
                "fill-hole",
                edges[0],
                (),
                tuple(rim),
                float("nan"),
                f"{why}: no {'ear' if len(edges[0]) == 2 else 'cone'} fits, so the {len(rim)} simplices on its rim "
                "were removed and the wider hole is closed again",
            )
        )
        return self.boundary_near(touched)

    def _unpinch(self, edges: list[Simplex], why: str) -> list[Simplex]:
        """At each vertex where the hole's boundary pinches, drop all but the largest fan.

        Returns the hole's boundary edges afterwards.
        """
        deg: dict[int, int] = {}
        for e in edges:
            for v in e:
                deg[v] = deg.get(v, 0) + 1
        touched = set(v for e in edges for v in e)
        for v in [v for v, c in deg.items() if c > 2]:
            fans = self.fans(v)
            if len(fans) < 2:
                continue
            for fan in sorted(fans, key=len)[:-1]:
                for i in fan:
                    touched.update(self.simp[i])
                    self._delete(i)
                self.log.append(
                    (
                        "fill-hole",
                        (v,),
                        (),
                        tuple(fan),
                        float("nan"),
                        f"{why}: its boundary pinches at sample {v}; removed the smaller fan of "
                        f"{len(fan)} simplices there so the hole has a simple rim",
                    )
                )
        return self.boundary_near(touched)

    def _fill_delaunay(self, verts: set[int], why: str) -> None:
        cand = set()
        for v in verts:
            for fi in self.vfaces[self.vptr[v] : self.vptr[v + 1]]:
                row = tuple(int(x) for x in self.delaunay[fi])
                if all(x in verts for x in row):
                    cand.add(row)
        cand = {s for s in cand if s not in self.index}
        known: dict[Simplex, tuple[bool, float]] = {}  # fits() only changes when a facet gains a simplex
        while cand:
            best = None
            for s in cand:
                got = known.get(s)
                if got is None:
                    got = known[s] = self.fits(s)
                ok, worst = got
                if ok and (best is None or worst < best[0]):
                    best = (worst, s)
            if best is None:
                return
            worst, s = best
            cand.discard(s)
            touched = set(_facets(s))
            known = {t: got for t, got in known.items() if touched.isdisjoint(_facets(t))}
            tau = next(f for f in _facets(s) if len(self.at(f)) == 1)
            self.add(
                s, "fill-hole", tau, float(np.arccos(np.clip(worst, -1, 1))), f"closing a {why} with a Delaunay face"
            )

    def _loops(self, edges: list[Simplex]) -> list[list[int]] | None:
        """Boundary edges as simple cycles, or None when a vertex is pinched."""
        nbr: dict[int, list[int]] = {}
        for a, b in edges:
            nbr.setdefault(a, []).append(b)
            nbr.setdefault(b, []).append(a)
        if any(len(x) != 2 for x in nbr.values()):
            return None
        loops, seen = [], set()
        for start in nbr:
            if start in seen:
                continue
            loop, prev, cur = [start], None, start
            seen.add(start)
            while True:
                nxt = nbr[cur][0] if nbr[cur][0] != prev else nbr[cur][1]
                if nxt == start:
                    break
                loop.append(nxt)
                seen.add(nxt)
                prev, cur = cur, nxt
            loops.append(loop)
        return loops

    def _ear_clip(self, edges: list[Simplex], why: str, zip_3d: bool = False) -> None:
        """Triangulate each simple boundary loop by ear clipping in its best-fit plane.

        The loop is projected to the plane of its two main directions; if the
        projected polygon is simple, ear clipping there always succeeds (two
        ears theorem), and the lifted triangles cannot overlap each other.
        Among the valid ears the best-shaped (largest smallest angle) goes
        first.  Loops whose projection crosses itself are left alone, unless
        ``zip_3d`` (slits, see :meth:`_zip`).
        """
        loops = self._loops(edges)
        if loops is None:
            return
        for loop in loops:
            q = plane_polygon(self.points[loop])
            if q is None:
                if zip_3d:
                    self._zip(loop, why)
                continue
            idx = list(range(len(loop)))
            # a valid ear stays valid while no ear next to it is clipped (clipping only removes
            # a vertex that could lie inside it); an invalid one may become valid, so it is re-tested
            valid: dict[tuple[int, int, int], float] = {}
            while len(idx) >= 3:
                best = None
                m = len(idx)
                sign = orientation(q[idx])  # once per round: the same for every ear of it
                for t in range(m):
                    a, b, c = idx[t - 1], idx[t], idx[(t + 1) % m]
                    shape = valid.get((a, b, c)) if m > 3 else None
                    if shape is None:
                        if not is_ear(q, idx, t, sign):
                            continue
                        tri = tuple(sorted((loop[a], loop[b], loop[c])))
                        diag = tuple(sorted((loop[a], loop[c])))
                        if m > 3 and self.at(diag):
                            continue  # the diagonal is already an edge of M_S elsewhere
                        if tri in self.index or any(len(self.at(f)) >= 2 for f in _facets(tri)):
                            continue
                        if not self.consistent(tri):
                            continue
                        shape = valid[(a, b, c)] = min_angle(q[a], q[b], q[c])
                    if best is None or shape > best[0]:
                        best = (shape, t, tuple(sorted((loop[a], loop[b], loop[c]))))
                if best is None:
                    break
                _, t, tri = best
                near = (idx[t - 1], idx[(t + 1) % m])
                valid = {k: v for k, v in valid.items() if near[0] not in k and near[1] not in k}
                self.add(
                    tri,
                    "fill-hole",
                    tuple(sorted((loop[idx[t - 1]], loop[idx[t]]))),
                    float("nan"),
                    f"closing a {why}: ear at sample {loop[idx[t]]} clipped in the hole's plane "
                    "(need not be a Delaunay face)",
                )
                idx.pop(t)
                if len(idx) < 3:
                    break

    def _zip(self, loop: list[int], why: str) -> None:
        """Close a slit whose rim has no simple planar projection by ears chosen in space.

        A thin plate's rim curls (a lip, an ear's edge), so its best-fit
        plane can fold it over itself.  Across a slit only a spacing or two
        wide the ears are the teeth of a zipper: each ear must not fold onto
        the surface at its two rim edges (phi > 25 deg there,
        :data:`COS_EAR`), must keep the orientation, and its diagonal must
        not be an edge of M_S already; the best-shaped ear in space goes
        first.
        """
        idx = list(range(len(loop)))
        # an ear's verdict changes only when an ear next to it is clipped
        known: dict[tuple[int, int, int], float | None] = {}
        while len(idx) >= 3:
            best = None
            m = len(idx)
            for t in range(m):
                key = (loop[idx[t - 1]], loop[idx[t]], loop[idx[(t + 1) % m]])
                if key not in known or m == 3:
                    known[key] = self._zip_ear(*key, closing=m == 3)
                shape = known[key]
                if shape is not None and (best is None or shape > best[0]):
                    best = (shape, t, tuple(sorted(key)))
            if best is None:
                return
            _, t, tri = best
            a, c = loop[idx[t - 1]], loop[idx[(t + 1) % m]]
            known = {k: v for k, v in known.items() if a not in k and c not in k}
            self.add(
                tri,
                "fill-hole",
                tuple(sorted((loop[idx[t - 1]], loop[idx[t]]))),
                float("nan"),
                f"closing a {why}: ear at sample {loop[idx[t]]} chosen in space (the rim has no "
                "simple planar projection; need not be a Delaunay face)",
            )
            idx.pop(t)

    def _zip_ear(self, a: int, b: int, c: int, closing: bool) -> float | None:
        """Shape (smallest angle) of the ear (a, b, c) of :meth:`_zip`, or None if it may not be clipped."""
        tri = tuple(sorted((a, b, c)))
        if not closing and self.at(tuple(sorted((a, c)))):
            return None
        if tri in self.index or any(len(self.at(f)) >= 2 for f in _facets(tri)):
            return None
        if not self.consistent(tri):
            return None
        for rim in (tuple(sorted((a, b))), tuple(sorted((b, c)))):
            ids = self.at(rim)
            if ids and float(self._u(tri, rim) @ self._u(self.simp[ids[0]], rim)) >= COS_EAR:
                return None
        p = self.points
        return min_angle(p[a], p[b], p[c])

    def _join_ends(self, ends: list[Simplex], why: str) -> None:
        """Join curve ends in pairs, closest first, up to FILL_MAX_SPAN local spacings apart."""
        pts = [f[0] for f in ends]
        pairs = sorted(
            (float(np.linalg.norm(self.points[a] - self.points[b])), a, b) for a, b in itertools.combinations(pts, 2)
        )
        done: set[int] = set()
        for dist, a, b in pairs:
            if a in done or b in done:
                continue
            local = max(float(self.nn[[a, b]].mean()), self.spacing)
            if dist > FILL_MAX_SPAN * local:
                break
            s = (min(a, b), max(a, b))
            if s in self.index:
                continue
            self.add(
                s,
                "fill-hole",
                (a,),
                float("nan"),
                f"closing a {why}: joined ends {a} and {b}, {dist / local:.1f} local spacings apart",
            )
            done.update((a, b))

    # -- pinched vertices -----------------------------------------------------
    def fans(self, v: int) -> list[list[int]]:
        """The simplices at vertex v, grouped by connection through (d-1)-faces at v."""
        tris = sorted(self._star(v))
        parent = {i: i for i in tris}

        def find(a: int) -> int:
            while parent[a] != a:
                a = parent[a]
            return a

        for i in tris:
            for f in _facets(self.simp[i]):
                ids = self._ids(f)
                if v in f and len(ids) == 2:
                    parent[find(ids[0])] = find(ids[1])
        groups: dict[int, list[int]] = {}
        for i in tris:
            groups.setdefault(find(i), []).append(i)
        return list(groups.values())

    def unpinch_all(self) -> int:
        """Drop all but the largest fan at every suspect vertex with several; returns how many.

        Suspects are the vertices whose star changed since the last call
        (initially the ones the caller names in :attr:`suspects`).
        """
        fixed = 0
        suspects, self.suspects = sorted(self.suspects), set()
        for v in suspects:
            fans = self.fans(v)
            if len(fans) < 2:
                continue
            fixed += 1
            for fan in sorted(fans, key=len)[:-1]:
                for i in fan:
                    self._delete(i)
                self.log.append(
                    (
                        "fill-hole",
                        (v,),
                        (),
                        tuple(fan),
                        float("nan"),
                        f"M_S pinches at sample {v} (its simplices form {len(fans)} fans); removed "
                        f"a fan of {len(fan)} so the hole it leaves can be closed",
                    )
                )
        return fixed
