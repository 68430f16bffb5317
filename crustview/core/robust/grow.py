"""Growing a manifold over the Delaunay d-faces (the robust extension's main phase).

See :mod:`crustview.core.robust.driver` for the rules and why they exist.  This
module holds the mechanics: a priority queue of (boundary face, candidate
simplex) pairs, validity tests that keep the complex a manifold with
boundary, and seeding of new components.

All per-candidate arrays are laid out in the CSR order of
:func:`~crustview.core.paper.facets.facet_structure`: entry ``j`` pairs facet
``fg[j]`` with simplex ``inc[j]``, whose vertex opposite that facet is
``apex[j]`` and whose unit vector from the facet to that vertex is ``ucsr[j]``.
"""

from __future__ import annotations

import heapq
import math
from array import array
from collections.abc import Callable

import numpy as np

from ..errors import Cancelled
from ..paper.facets import facet_structure
from .handles import HandleGuard

#: Largest size ratio (circumradius over the local spacing) of a grown simplex.
SIZE_MAX = 3.0
#: cos(phi) limits at a boundary face: the paper's line 4 (phi > pi/2), then a
#: relaxed pass for creases of real scans (phi > pi/3).
COS_PAPER = 0.0
COS_CREASE = 0.5
#: weight of the candidate score (radians) in the growing order
COST_SCORE = 1.0


def size_ratio(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Circumradius of each face over the mean nearest-neighbour distance of its vertices.

    About 0.6-1 for the simplices of a well-spaced sample; large for faces
    that span a gap (between the hooves of a scanned horse, across a real
    hole of an open scan).

    Parameters
    ----------
    points : ndarray of shape (n, k)
    faces : ndarray of shape (f, d + 1)

    Returns
    -------
    ndarray of shape (f,)
    """
    from ..util.nearest import nearest_distances

    if len(faces) == 0:
        return np.zeros(0)
    nn = nearest_distances(points)
    return circumradii(points, faces) / np.maximum(nn[faces].mean(axis=1), 1e-300)


def circumradii(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Circumradius of each simplex ``faces`` (f, d + 1) of ``points``; triangles in closed form."""
    p = points[faces]
    if faces.shape[1] == 3:  # triangles: R = abc / (4 area), in closed form
        a = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
        b = np.linalg.norm(p[:, 0] - p[:, 2], axis=1)
        c = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
        s = 0.5 * (a + b + c)
        area4 = 4.0 * np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0.0))
        radius = a * b * c / np.maximum(area4, 1e-300)
    else:
        a = p[:, 1:] - p[:, :1]  # (f, d, k)
        gram = a @ np.swapaxes(a, 1, 2)
        rhs = 0.5 * np.einsum("fdd->fd", gram)
        reg = 1e-12 * np.maximum(np.einsum("fdd->f", gram), 1e-300)[:, None, None] * np.eye(gram.shape[1])
        lam = np.linalg.solve(gram + reg, rhs[..., None])[..., 0]
        radius = np.linalg.norm(np.einsum("fd,fdk->fk", lam, a), axis=1)
    return radius


def unit_normals_to_facets(points: np.ndarray, simplices: np.ndarray) -> np.ndarray:
    """Unit vectors from each facet's affine hull to the opposite vertex.

    The same quantity as :func:`crustview.core.paper.facets.opposite_vectors`,
    computed by vectorised Gram-Schmidt instead of batched QR (several times
    faster on hundreds of thousands of simplices).

    Returns
    -------
    ndarray of shape (c, d + 1, k)
    """
    c, dp1 = simplices.shape
    if dp1 == 3:  # triangles: one projection per edge, on whole columns
        corner = [points[simplices[:, a]] for a in range(3)]
        out = np.empty((c, 3, points.shape[1]))
        for a, (b, e) in enumerate(((1, 2), (0, 2), (0, 1))):
            edge = corner[e] - corner[b]
            v = corner[a] - corner[b]
            t = np.einsum("ij,ij->i", v, edge) / np.maximum(np.einsum("ij,ij->i", edge, edge), 1e-300)
            v -= t[:, None] * edge
            v /= np.maximum(np.sqrt(np.einsum("ij,ij->i", v, v)), 1e-300)[:, None]
            out[:, a] = v
        return out
    p = points[simplices]
    out = np.empty((c, dp1, points.shape[1]))
    for a in range(dp1):
        rest = [b for b in range(dp1) if b != a]
        v = p[:, a] - p[:, rest[0]]
        basis: list[np.ndarray] = []
        for b in rest[1:]:
            e = p[:, b] - p[:, rest[0]]
            for q in basis:
                e = e - (e * q).sum(axis=1, keepdims=True) * q
            e = e / np.maximum(np.linalg.norm(e, axis=1, keepdims=True), 1e-300)
            basis.append(e)
        for q in basis:
            v = v - (v * q).sum(axis=1, keepdims=True) * q
        out[:, a] = v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)
    return out


def _scalars(a: np.ndarray) -> array:
    """A flat :class:`array.array` copy of ``a`` (int64, or float64 for floats, bytes for bools)."""
    a = np.ascontiguousarray(a).ravel()
    code = "d" if a.dtype.kind == "f" else ("b" if a.dtype.kind == "b" else "q")
    out = array(code)
    out.frombytes(a.astype({"d": np.float64, "b": np.int8, "q": np.int64}[code], copy=False).tobytes())
    return out


class Grower(HandleGuard):
    """Adds Delaunay d-faces across the boundary, one per step, keeping a manifold.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    faces : ndarray of shape (f, d + 1)
        Sorted rows; T_S first (``tier == 0``).
    scores : ndarray of shape (f,)
        Candidate-test angles.
    tier : ndarray of shape (f,)
        0 for faces of T_S, 1 for the other Delaunay faces.
    """

    def __init__(
        self,
        points: np.ndarray,
        faces: np.ndarray,
        scores: np.ndarray,
        tier: np.ndarray,
        size: np.ndarray | None = None,
    ) -> None:
        self.points = points
        self.faces = faces
        self.scores = scores
        self.tier = tier.astype(np.int8)
        self.n = len(points)
        self.dp1 = faces.shape[1]
        self.size = size_ratio(points, faces) if size is None else size
        #: priority of each face (smaller first): its size, doubled outside T_S and
        #: raised with its candidate score (see module docstring of ``robust``)
        self.cost = self.size * (1.0 + self.tier) * (1.0 + COST_SCORE * np.minimum(scores, np.pi / 2))
        self.facets, self.facet_of, self.ptr, order = facet_structure(faces, positions=True)
        #: incidences (face * (d + 1) + position) grouped by facet, by face id within each
        self.by_facet = order
        self.inc = order // self.dp1
        pos = order % self.dp1
        self.u = unit_normals_to_facets(points, faces)
        self.ucsr = self.u[self.inc, pos]
        self.apex = faces[self.inc, pos]
        self.fg = np.repeat(np.arange(len(self.facets)), np.diff(self.ptr))
        f = len(faces)
        # the hot loop runs on Python lists: scalar access to them is several times
        # cheaper than to numpy arrays
        # (array.array: as cheap to index as a list, made by one copy of the buffer)
        self._ptr = _scalars(self.ptr)
        self._inc = _scalars(self.inc)
        self._fg = _scalars(self.fg)
        self._apex = _scalars(self.apex)
        # flat sequences: row i of an (r, m) array is items [i * m, (i + 1) * m)
        self._fo = _scalars(self.facet_of)
        self._fverts = _scalars(self.facets)
        self._verts = _scalars(faces)
        self._fits = _scalars(self.size <= SIZE_MAX)
        self._in_ts = _scalars(self.tier == 0)
        self._cost = _scalars(self.cost)
        self.alive = bytearray(f)
        self.count = [0] * len(self.facets)
        self.xor = [0] * len(self.facets)  # xor of (id + 1) of the alive simplices at each facet
        self.vcount = [0] * self.n
        self.vfront = [0] * self.n
        #: vertex pieces of the grown complex (union-find; pieces only ever merge)
        self._uf = list(range(self.n))
        self._vstar: list[list[int]] | None = None
        #: boundary components found since the last addition (see boundary_component)
        self._bc_cache: dict[int, tuple[set[int], bool]] = {}
        self._nn: np.ndarray | None = None
        #: gluing moves refused because they would join two boundary components of one piece
        #: around a hole that ``fill-hole`` closes (a handle across an undersampling gap)
        self.refused_handles = 0
        self.heap: list[tuple[int, float, int, float]] = []
        self.cos_limit = COS_PAPER
        #: apexes of gluing moves: the only vertices where the grown complex can pinch
        self.glued: list[int] = []
        #: candidate entries found invalid at each boundary facet (under the current angle limit)
        self.rejected: dict[int, set[int]] = {}
        #: orientation (+1/-1 relative to the sorted vertex order) of each grown simplex
        self.orient = [0] * f
        #: codimension 1: every closed hypersurface is orientable, so no move may
        #: join two simplices with opposite orientations
        self.orientable = points.shape[1] - (self.dp1 - 1) == 1
        #: (face id, rule, facet id or -1, angle) per step, in order
        self.log: list[tuple[int, str, int, float]] = []

    # -- bookkeeping --------------------------------------------------------
    def owner(self, g: int) -> int:
        """The one alive simplex at a boundary facet."""
        return self.xor[g] - 1

    def _facets_of(self, f: int) -> list[int]:
        dp1 = self.dp1
        return self._fo[f * dp1 : (f + 1) * dp1]

    def _u_at(self, f: int, h: int) -> np.ndarray:
        return self.u[f, self._facets_of(f).index(h)]

    def _induced_orientation(self, f: int, g: int) -> int:
        """Orientation simplex f must take to agree with the owner of facet g."""
        s = self.xor[g] - 1
        a = self._facets_of(f).index(g)
        b = self._facets_of(s).index(g)
        return -self.orient[s] * (-1 if (a + b) % 2 else 1)

    def add(self, f: int, rule: str, g: int, angle: float) -> None:
        self.alive[f] = 1
        self.orient[f] = self._induced_orientation(f, g) if g >= 0 else 1
        count, xor, vfront = self.count, self.xor, self.vfront
        d, dp1 = self.dp1 - 1, self.dp1
        hs = self._fo[f * dp1 : (f + 1) * dp1]
        for h in hs:
            count[h] += 1
            xor[h] ^= f + 1
            delta = 1 if count[h] == 1 else -1
            for v in self._fverts[h * d : (h + 1) * d]:
                vfront[v] += delta
        vs = self._verts[f * dp1 : (f + 1) * dp1]
        for v in vs:
            self.vcount[v] += 1
        self._union(vs)
        if self._bc_cache:
            self._bc_cache = {}
        if self._vstar is not None:
            for v in vs:
                self._vstar[v].append(f)
        self.log.append((f, rule, g, angle))
        for h in hs:
            if count[h] == 1:
                self.push_front(h)

    def add_bulk(self, ids: np.ndarray, orient: np.ndarray, rule: str) -> None:
        """Add many simplices to the empty complex at once (the manifold core).

        Leaves the state :meth:`add` would leave after adding them one by one;
        ``ids`` must form a manifold with boundary (see
        :func:`crustview.core.robust.seed_core.manifold_core`).
        """
        if len(ids) == 0:
            return
        if any(self.alive):
            raise ValueError("add_bulk starts a growth: the complex must be empty")
        ids = np.asarray(ids, dtype=np.int64)
        for i, o in zip(ids.tolist(), np.asarray(orient).tolist()):
            self.alive[i] = 1
            self.orient[i] = int(o)
        fo = self.facet_of[ids].ravel()
        cnt = np.bincount(fo, minlength=len(self.facets))
        xor = np.zeros(len(self.facets), dtype=np.int64)
        np.bitwise_xor.at(xor, fo, np.repeat(ids + 1, self.dp1))
        self.count = cnt.tolist()
        self.xor = xor.tolist()
        self.vcount = np.bincount(self.faces[ids].ravel(), minlength=self.n).tolist()
        self.vfront = np.bincount(self.facets[cnt == 1].ravel(), minlength=self.n).tolist()
        # pieces of the core: components of its vertex graph, each vertex pointing at one root
        from ..analysis.topology import graph_components

        rows = self.faces[ids]
        edges = np.concatenate([rows[:, [0, a]] for a in range(1, self.dp1)])
        _, label = graph_components(self.n, edges)
        root = np.full(int(label.max()) + 1, self.n, dtype=np.int64)
        np.minimum.at(root, label, np.arange(self.n))  # the smallest vertex of each component
        used = np.unique(rows)
        uf = np.arange(self.n)
        uf[used] = root[label[used]]
        self._uf = uf.tolist()
        m = len(ids)
        self.log.extend(zip(ids.tolist(), [rule] * m, [-1] * m, [math.nan] * m))

    # -- candidates ---------------------------------------------------------
    def push_front(self, g: int) -> None:
        """Queue the best admissible simplex across boundary facet ``g``.

        Only the best (gluing last, then smallest cost) is queued; when it
        turns out to be taken or invalid, :meth:`grow` asks again, so the next
        best is queued then.  Validity only ever gets stricter as the surface
        grows, so this pops the same candidates as queueing them all, with a
        third of the heap traffic.
        """
        lo, hi = self._ptr[g], self._ptr[g + 1]
        cand = self._inc[lo:hi]
        s = self.xor[g] - 1
        u = self.ucsr[lo:hi]
        cos = (u @ u[cand.index(s)]).tolist()
        lim = self.cos_limit
        alive, fits, fo, count = self.alive, self._fits, self._fo, self.count
        vcount, vfront, apex = self.vcount, self.vfront, self._apex
        dp1 = self.dp1
        rejected = self.rejected.get(g, ())
        best = None
        for t, c_t in enumerate(cos):
            if c_t >= lim:  # folded onto the owner (the owner itself, at cos 1, too)
                continue
            f = cand[t]
            if alive[f] or not fits[f] or lo + t in rejected:
                continue
            closing = False
            full = False
            for h in fo[f * dp1 : (f + 1) * dp1]:
                if h != g:
                    ch = count[h]
                    if ch >= 2:
                        full = True
                        break
                    if ch == 1:
                        closing = True
            if full:
                continue
            c = apex[lo + t]
            used = vcount[c] > 0
            if used and vfront[c] == 0:
                continue  # c is inside the surface
            glue = used and not closing
            if glue and not self._in_ts[f]:
                continue  # handles only where T_S vouches for them
            key = (int(glue), self._cost[f], lo + t, c_t)
            if best is None or key < best:
                best = key
        if best is not None:
            heapq.heappush(self.heap, best)

    def valid(self, j: int, cos: float) -> tuple[bool, bool, float]:
        """(valid, gluing, cos phi at the facet) of candidate entry ``j`` now.

        ``cos`` was computed when ``j`` was queued; it is still exact, because a
        boundary facet keeps its one simplex until a second one closes it.
        """
        f, g = self._inc[j], self._fg[j]
        if self.alive[f] or self.count[g] != 1:
            return False, False, 1.0
        if cos >= self.cos_limit:
            return False, False, cos
        c = self._apex[j]
        if self.vcount[c] > 0 and self.vfront[c] == 0:
            return False, False, cos
        closing = False
        for h in self._facets_of(f):
            if h == g:
                continue
            if self.count[h] >= 2:
                return False, False, cos
            if self.count[h] == 1:
                closing = True
                if float(self._u_at(f, h) @ self._u_at(self.xor[h] - 1, h)) >= self.cos_limit:
                    return False, False, cos  # folded onto an existing simplex
                if self.orientable and self._induced_orientation(f, h) != self._induced_orientation(f, g):
                    return False, False, cos  # would close a Moebius band: impossible in codimension 1
        return True, bool(self.vcount[c] > 0 and not closing), cos

    # -- phases -------------------------------------------------------------
    def seed(self) -> bool:
        """Start a new component at the best T_S face whose vertices are all unused."""
        vcount = np.array(self.vcount)
        alive = np.frombuffer(bytes(self.alive), dtype=np.uint8).astype(bool)
        free = (vcount[self.faces] == 0).all(axis=1) & ~alive & (self.size <= SIZE_MAX)
        cand = np.flatnonzero(free)
        if len(cand) == 0:
            return False
        best = cand[np.lexsort((cand, self.size[cand], self.scores[cand], self.tier[cand]))[0]]
        self.add(int(best), "seed", -1, float(self.scores[best]))
        return True

    def grow(
        self,
        rule_of: Callable[[int, float], str],
        cancel: object | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> None:
        """Pop candidates until none is valid; ``rule_of(face, cos)`` names each step."""
        heap = self.heap
        alive, count, inc, fg = self.alive, self.count, self._inc, self._fg
        while heap:
            glue, cost, j, cos0 = heapq.heappop(heap)
            g = fg[j]
            if count[g] != 1:
                continue  # its boundary face closed since it was queued
            if alive[inc[j]]:
                self.push_front(g)  # taken across another face: queue this face's next best
                continue
            ok, now_glue, cos = self.valid(j, cos0)
            if not ok:
                self.rejected.setdefault(g, set()).add(j)
                self.push_front(g)
                continue
            if now_glue and not glue:  # became a gluing move since it was queued: rank it again
                self.push_front(g)
                continue
            if now_glue and self.makes_gap_handle(g, self._apex[j]):
                self.refused_handles += 1
                self.rejected.setdefault(g, set()).add(j)
                self.push_front(g)
                continue
            f = self._inc[j]
            if now_glue:
                self.glued.append(self._apex[j])
            self.add(f, rule_of(f, cos), self._fg[j], math.acos(max(-1.0, min(1.0, cos))))
            if len(self.log) % 1024 == 0:
                if cancel is not None and cancel.is_set():
                    raise Cancelled("reconstruction cancelled")
                if progress is not None:
                    progress(len(self.log) / max(2 * self.n, 1))

    def requeue_front(self) -> None:
        """Queue every boundary facet again (after the angle limit changed)."""
        self.heap = []
        self.rejected = {}
        for g in np.flatnonzero(np.array(self.count) == 1).tolist():
            self.push_front(g)
