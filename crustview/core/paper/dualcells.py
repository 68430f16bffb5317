"""Edges and polygons of the dual Voronoi cells, and minima over them.

A Delaunay d-face sigma is dual to a (k-d)-dimensional Voronoi cell whose
vertices are the circumcentres of the Delaunay simplices containing sigma.
In codimension 2 and 3 the cell's real edges and (in codimension 3)
polygons are read off those simplices, so the cocone minimum over the cell
boundary needs no enumeration of vertex subsets.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .conemin import dot_rows, segment_min, span_min3

try:  # compiled edge listing of two-dimensional cells (setup.py builds it; numpy does the same without it)
    from ..delaunay import _cellpass as _native
except ImportError:  # pragma: no cover - depends on the build
    _native = None


def cell_structure(face: np.ndarray, simp_rows: np.ndarray, n_all: int, m: int) -> tuple[np.ndarray, tuple]:
    """Edges (and, in codimension 3, polygons) of 2- or 3-dimensional dual cells.

    Edges join two cell simplices sharing a facet (both contain sigma);
    polygons are dual to the cofaces ``sigma + w``: their vertices are the
    cell simplices containing ``w`` (three of them span the polygon's plane).

    Parameters
    ----------
    face : ndarray of shape (F, d + 1)
    simp_rows : ndarray of shape (F, nv, r + 1)
        Vertex rows of each cell's simplices.

    Returns
    -------
    edges : ndarray of shape (E, 3)
        ``(face, i, j)``: cell vertices i and j are joined by an edge.
    polygons : (ndarray of shape (P, 6), ndarray)
        Rows ``(face, i, j, l, start, size)``: three vertices spanning one
        polygon, and the slice ``members[start:start + size]`` of the member
        array listing all its vertices (empty unless m = 3).
    """
    f_count, nv, _ = simp_rows.shape
    in_face = (simp_rows[..., None] == face[:, None, None, :]).any(axis=3)
    others = np.sort(simp_rows[~in_face].reshape(f_count, nv, m), axis=2)
    fidx = np.broadcast_to(np.arange(f_count, dtype=np.int64)[:, None], (f_count, nv))
    vidx = np.broadcast_to(np.arange(nv)[None, :], (f_count, nv))
    base = np.int64(n_all)
    keys = []
    for q in range(m):
        rest = np.delete(others, q, axis=2)
        key_q = fidx.copy()
        for c in range(m - 1):
            key_q = key_q * base + rest[..., c]
        keys.append(key_q.ravel())
    key = np.concatenate(keys)
    fe, ve = np.tile(fidx.ravel(), m), np.tile(vidx.ravel(), m)
    order = np.argsort(key, kind="stable")
    key, fe, ve = key[order], fe[order], ve[order]
    pair = np.flatnonzero(key[1:] == key[:-1])
    edges = np.stack([fe[pair], ve[pair], ve[pair + 1]], axis=1)
    if m != 3:
        return edges, (np.empty((0, 6), np.int64), np.empty(0, np.int64))
    pkey = (fidx[..., None] * base + others).ravel()
    pf, pv = np.repeat(fidx.ravel(), m), np.repeat(vidx.ravel(), m)
    order = np.argsort(pkey, kind="stable")
    pkey, pf, pv = pkey[order], pf[order], pv[order]
    start = np.flatnonzero(np.concatenate([[True], pkey[1:] != pkey[:-1]]))
    size = np.diff(np.concatenate([start, [len(pkey)]]))
    polygons = np.stack([pf[start], pv[start], pv[start + 1], pv[start + 2], start, size], axis=1)
    # member list (pv) is kept so bounds can use every vertex of a polygon
    return edges, (polygons[size >= 3], pv)


class CellFaces:
    """Edges and polygons of one bucket's cells, built for the faces that need them.

    Most faces are settled before the boundary is needed; the structure is
    built for just the requested batch, or once for the whole bucket when a
    batch covers a third of it or more (later batches then reuse it).  The
    cells' simplex rows are gathered the same way, only for the faces asked
    about (a gather from the whole triangulation is mostly cache misses).

    Parameters
    ----------
    face : ndarray of shape (F, d + 1)
    simplices : ndarray of shape (t, r + 1)
        The Delaunay simplices.
    cell_ids : ndarray of shape (F, nv)
        Each face's cell simplices (rows of ``simplices``).
    n_all, m : int
        Delaunay vertices; the codimension.
    once : bool
        Asked for one batch only: build the structure for just that batch,
        however large it is.
    """

    def __init__(
        self, face: np.ndarray, simplices: np.ndarray, cell_ids: np.ndarray, n_all: int, m: int, once: bool = False
    ) -> None:
        self.face, self.simplices, self.cell_ids, self.n_all, self.m = face, simplices, cell_ids, n_all, m
        self.whole: tuple | None = None
        self.once = once

    def _rows(self, idx: np.ndarray | None = None) -> np.ndarray:
        ids = self.cell_ids if idx is None else self.cell_ids[idx]
        return np.take(self.simplices, ids, axis=0)

    def for_batch(self, idx: np.ndarray) -> tuple[np.ndarray, tuple]:
        """Structure with face column renumbered to positions in ``idx`` (sorted)."""
        if self.m == 2 and _native is not None and self.simplices.dtype == np.int32:
            # each face's edges depend on that face alone: the batch's are the whole bucket's, renumbered
            return native_edges(self.face[idx], self.simplices, self.cell_ids[idx]), _NO_POLYGONS
        if self.whole is None and (self.once or 3 * len(idx) < len(self.face)):
            return cell_structure(self.face[idx], self._rows(idx), self.n_all, self.m)
        if self.whole is None:
            self.whole = cell_structure(self.face, self._rows(), self.n_all, self.m)
        edges, (polygons, members) = self.whole
        pos = np.full(len(self.face), -1)
        pos[idx] = np.arange(len(idx))
        e = edges[pos[edges[:, 0]] >= 0]
        pg = polygons[pos[polygons[:, 0]] >= 0]
        return np.c_[pos[e[:, 0]], e[:, 1:]], (np.c_[pos[pg[:, 0]], pg[:, 1:]], members)


#: Codimension 2 has no polygons (the cell itself is the one polygon).
_NO_POLYGONS = (np.empty((0, 6), np.int64), np.empty(0, np.int64))


def native_edges(face: np.ndarray, simplices: np.ndarray, cell_ids: np.ndarray) -> np.ndarray:
    """:func:`cell_structure`'s edges of two-dimensional cells (m = 2), compiled: the same rows in the same order.

    ``simplices`` must be int32 (the backends' tables).
    """
    face = np.ascontiguousarray(face, dtype=np.int64)
    cell_ids = np.ascontiguousarray(cell_ids, dtype=np.int64)
    raw = _native.cell_edges(
        face, np.ascontiguousarray(simplices), cell_ids, face.shape[1], simplices.shape[1], cell_ids.shape[1]
    )
    return np.frombuffer(raw, dtype=np.int64).reshape(-1, 3)


def sorted_group_min(out: np.ndarray, group: np.ndarray, values: np.ndarray) -> None:
    """``out[g] = min(out[g], values[group == g])`` for a non-decreasing ``group``."""
    if len(group) == 0:
        return
    start = np.flatnonzero(np.concatenate([[True], group[1:] != group[:-1]]))
    g = group[start]
    out[g] = np.minimum(out[g], np.minimum.reduceat(values, start))


def cell_boundary_min(
    x: np.ndarray,
    nrm: np.ndarray,
    s: np.ndarray,
    edges: np.ndarray,
    polygons: np.ndarray,
    cap: np.ndarray,
    tree: cKDTree,
) -> np.ndarray:
    """Exact minimum of sin^2 angle over the edges and polygons of dual cells.

    Each edge is a segment (closed form).  On each polygon the minimiser
    over its plane is accepted when the Voronoi criterion puts it inside (no
    Delaunay vertex closer to it than s).  Edges and polygons whose vertices
    all lean to one normal side by more than ``sqrt(cap)`` are skipped: they
    cannot go below ``cap``.

    Parameters
    ----------
    x : ndarray of shape (F, nv, r)
        Cell vertices minus s.
    nrm : ndarray of shape (F, r, m)
    s : ndarray of shape (F, r)
    edges, polygons
        From :func:`cell_structure`, with face indices into this batch.
    cap : ndarray of shape (F,)
        Values at or above it are of no interest.

    Returns
    -------
    ndarray of shape (F,), inf where nothing below ``cap`` was found.
    """
    out = np.full(len(x), np.inf)
    xn = x @ nrm
    unit = xn / np.maximum(np.linalg.norm(x, axis=2), 1e-300)[..., None]
    nu = np.einsum("fvm->fm", unit)
    nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
    dots = dot_rows(unit, nu)

    def wanted(f: np.ndarray, cols: list[np.ndarray]) -> np.ndarray:
        lb = np.min([dots[f, c] for c in cols], axis=0)
        return (lb <= 0) | (lb**2 < cap[f])

    if len(edges):
        e = edges[wanted(edges[:, 0], [edges[:, 1], edges[:, 2]])]
        val, ins = segment_min(x[e[:, 0], e[:, 1]], x[e[:, 0], e[:, 2]], xn[e[:, 0], e[:, 1]], xn[e[:, 0], e[:, 2]])
        sorted_group_min(out, e[:, 0], np.where(ins, val, np.inf))
    polygons, members = polygons
    if len(polygons):
        # bound over every vertex of the polygon (member slices)
        sizes, starts = polygons[:, 5], polygons[:, 4]
        offs = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        idx = np.arange(sizes.sum()) + np.repeat(starts - offs, sizes)
        pf_all = np.repeat(polygons[:, 0], sizes)
        lb = np.minimum.reduceat(dots[pf_all, members[idx]], offs)
        want = (lb <= 0) | (lb**2 < cap[polygons[:, 0]])
        if not want.any():
            return out
        p = polygons[want]
        gf = p[:, 0]
        gens = np.stack([x[gf, p[:, 1 + i]] for i in range(3)], axis=1)  # (P, 3, r)
        val, lam, ok = span_min3(gens, nrm[gf])
        tot = lam.sum(axis=1)
        # only a value below the cap and below the edges' minimum matters
        ok &= (np.abs(tot) > 1e-12 * np.abs(lam).max(axis=1)) & (val < np.minimum(cap, out)[gf])
        xy = np.einsum("pj,pjr->pr", lam / np.where(ok, tot, 1.0)[:, None], gens)
        # a point outside the bounding box of the polygon's vertices is outside it
        mem = np.repeat(want, sizes)
        pts = x[pf_all[mem], members[idx[mem]]]
        o = np.concatenate([[0], np.cumsum(sizes[want])[:-1]])
        lo, hi = np.minimum.reduceat(pts, o, axis=0), np.maximum.reduceat(pts, o, axis=0)
        slack = 1e-9 * (np.maximum(-lo, hi).max(axis=1) + np.abs(xy).max(axis=1))[:, None]
        ask = np.flatnonzero(ok & ((xy >= lo - slack) & (xy <= hi + slack)).all(axis=1))
        inside = np.zeros(len(p), dtype=bool)
        if len(ask):
            radius = np.linalg.norm(xy[ask], axis=1)
            dist, _ = tree.query(s[gf[ask]] + xy[ask])
            inside[ask] = dist >= radius * (1 - 1e-9) - 1e-12
            # report the value actually reached at the accepted point (equal to
            # the eigenvalue up to rounding; never below what the polygon has)
            nxy = np.einsum("pr,prm->pm", xy[ask], nrm[gf[ask]])
            val[ask] = (nxy**2).sum(axis=1) / np.maximum(radius**2, 1e-300)
        sorted_group_min(out, gf, np.where(inside, val, np.inf))
    return out
