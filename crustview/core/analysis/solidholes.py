"""Holes of a reconstructed d-manifold, d >= 3 (S^3 in R^4): the surfaces' hole rule in any dimension.

:mod:`.features` measures a surface's holes by their rim loops; a 3-manifold's hole has a rim that is a
2-sphere of boundary faces instead, and the same span and bounds apply (see :func:`holes_of_solids`).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..util.rows import unique_rows
from .features import HOLE_SUPPORTED, LOOP_MIN, Feature


def holes_of_solids(points: np.ndarray, simplices: np.ndarray, h: np.ndarray) -> list[Feature]:
    """The holes of a d-complex, d >= 3: its boundary (d - 1)-faces, grouped by shared vertices, and their span.

    The surfaces' rule (:func:`_holes`) in any dimension: a hole's rim is here a (d - 1)-sphere of faces
    in one d-simplex each instead of a loop of edges, and its span (twice the largest distance of a rim
    sample from the rim's mean) over the median local spacing of the rim's samples is measured against
    the same bounds.  A span below LOOP_MIN / pi = 2 spacings is one missing sample; below
    :data:`HOLE_SUPPORTED` = 4 only a sample coarser than eps = 1/2 resolves it, and the hole is
    uncertain.  (S^3 in R^4 with noise of 3 % of its reach: four holes of 8-24 faces, 2-3 spacings
    across, left where ``fill-hole`` found no cone: the result was open and listed nothing.)
    """
    simplices = np.asarray(simplices, dtype=np.int64)
    w = simplices.shape[1]
    n = len(points)
    if len(simplices) == 0 or w < 4:
        return []
    rim = rim_faces(simplices)
    if len(rim) == 0:
        return []
    # the faces of one hole share vertices: each face's vertices joined to its first
    a = np.repeat(rim[:, 0], w - 2)
    b = rim[:, 1:].ravel()
    g = coo_matrix((np.ones(len(a), np.int8), (a, b)), shape=(n, n))
    _, label = connected_components(g, directed=False)
    lab = label[rim[:, 0]]
    result = []
    for c in np.unique(lab).tolist():
        vs = np.unique(rim[lab == c])
        p = points[vs]
        span = float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)) * 2)
        size = span / float(np.median(h[vs]))
        unc = size < HOLE_SUPPORTED
        reason = f"hole with {int((lab == c).sum())} boundary faces, {size:.3g} spacings across" + (
            " (as wide as one missing sample: may be a gap)"
            if size < LOOP_MIN / math.pi
            else " (narrower than 4 spacings: only a sample coarser than eps = 1/2 resolves it, so it may be a gap)"
            if unc
            else ""
        )
        result.append(Feature("hole", p.mean(axis=0), size, unc, vs, reason))
    return result


def rim_faces(simplices: np.ndarray) -> np.ndarray:
    """The (d - 1)-faces in exactly one simplex of a pure d-complex, as sorted rows."""
    srt = np.sort(np.asarray(simplices, dtype=np.int64), axis=1)
    w = srt.shape[1]
    faces, inverse = unique_rows(np.concatenate([np.delete(srt, j, axis=1) for j in range(w)]))
    return faces[np.bincount(inverse, minlength=len(faces)) == 1]


def pinched_rim_vertices(simplices: np.ndarray) -> np.ndarray:
    """The samples on the boundary of a d-complex, d >= 3, whose link is not a disc: where it is no manifold.

    A boundary vertex of a d-manifold has a (d - 1)-disc for its link.  The topology report counts pinched
    vertices only on complexes without boundary; an open result of a 3-manifold can still have rim samples
    whose link is an annulus or a pair of pants (S^3 at 3 % of its reach: 9 such samples), and it is then no
    manifold with boundary.  Tested here: the link connected through its ridges, every ridge in at most two
    of its faces, Euler characteristic 1, and (d = 3) its boundary edges one cycle: for d = 3 exactly the
    disc.  For d >= 4 these are necessary conditions only (a cone over an annulus passes them).
    """
    simplices = np.sort(np.asarray(simplices, dtype=np.int64), axis=1)  # the link tests compare sorted rows
    w = simplices.shape[1] if simplices.ndim == 2 else 0
    if len(simplices) == 0 or w < 4:
        return np.zeros(0, np.int64)
    rim = rim_faces(simplices)
    # each vertex's simplices, from one sort of all their vertex slots (not a scan per rim vertex)
    flat = simplices.ravel()
    order = np.argsort(flat, kind="stable")
    verts = np.unique(rim)
    lo = np.searchsorted(flat[order], verts, side="left")
    hi = np.searchsorted(flat[order], verts, side="right")
    bad = []
    for v, a, b in zip(verts.tolist(), lo.tolist(), hi.tolist(), strict=True):
        star = simplices[order[a:b] // w].tolist()
        if not _is_disc([tuple(x for x in s if x != v) for s in star]):
            bad.append(v)
    return np.asarray(bad, dtype=np.int64)


def _is_disc(link: list[tuple[int, ...]]) -> bool:
    """Whether a pure (d - 1)-complex (d >= 3) passes the disc tests of :func:`pinched_rim_vertices`."""
    k = len(link[0])
    ridges: dict[tuple[int, ...], list[int]] = {}
    for i, f in enumerate(link):
        for r in itertools.combinations(f, k - 1):
            ridges.setdefault(r, []).append(i)
    if any(len(ids) > 2 for ids in ridges.values()):
        return False
    # connected through shared ridges
    seen, todo = {0}, [0]
    while todo:
        i = todo.pop()
        for r in itertools.combinations(link[i], k - 1):
            for j in ridges[r]:
                if j not in seen:
                    seen.add(j)
                    todo.append(j)
    if len(seen) != len(link):
        return False
    chi = sum((-1) ** j * len({c for f in link for c in itertools.combinations(f, j + 1)}) for j in range(k))
    if chi != 1:
        return False
    if k == 3:  # a disc's boundary is one cycle: every boundary vertex on two boundary edges, all joined
        edges = [r for r, ids in ridges.items() if len(ids) == 1]
        deg: dict[int, list[int]] = {}
        for a, b in edges:
            deg.setdefault(a, []).append(b)
            deg.setdefault(b, []).append(a)
        if not edges or any(len(x) != 2 for x in deg.values()):
            return False
        start = edges[0][0]
        walk, prev, cur = 1, None, start
        while True:
            nxt = deg[cur][0] if deg[cur][0] != prev else deg[cur][1]
            if nxt == start:
                break
            prev, cur, walk = cur, nxt, walk + 1
        return walk == len(deg)
    return True
