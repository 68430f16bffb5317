"""How far apart the sheets of a surface lie across it: a hole where they are closer than the sample resolves.

Two sheets of a surface at distance g have a local feature size of at most g / 2 between them (the medial
axis passes midway), so an eps < 1 sample resolves them only where its spacing is under g / 2: sheets closer
than :data:`~.features.GAP_MIN` = 2 spacings are not resolved, whether material lies between them (a thin
part: an ear, a fin) or air (two parts that nearly touch).  The components' bound measures the second case
between pieces of M_S; this module measures it across one surface, at the rim of a hole.

Under scanner noise (0.3 times the spacing) a part thinner than the noise (the two sides of the camel head's
ear lie 0.56 of a spacing apart) cannot be told from one noisy sheet: the labelling opens holes through it
that are as wide as a scanner's openings (14.8 spacings across), and their rims lie where M_S has two sheets
0.6-1.8 spacings apart.  Every real opening of the public open scans, clean and noisy, has no second sheet
within 4 spacings of most of its rim (``benchmarks/bench_scans.py``; docs/algorithm.md).

The measure, at a rim vertex p with M_S's normal n_p there (each triangle's normal, consistently oriented,
summed over p's triangles with their areas as weights): the distance to the nearest vertex q of M_S that
faces the other way (n_q . n_p < 0) and lies across the surface from p (within 60 degrees of p's normal
line: |(q - p) . n_p| >= |q - p| / 2), in p's spacing (the components' unit: the larger of its
nearest-neighbour distance and its sampling radius).  A neighbour along the same sheet faces the same
way, so noise that moves it off the tangent plane does not count.  Only vertices of p's own *piece* count
(triangles joined through edges in exactly two triangles, :func:`~.topology.oriented_pieces`): the two
orientations of another piece, or of pieces meeting at a vertex or at an edge of three triangles, are equally
good, so their facing says nothing (parts that nearly touch are the components' measure).  A non-orientable
piece's vertices face no way and are never measured.  Over a rim, the median: the rim mostly lies where the
sheets are that close.  Only for surfaces in R^3 (a normal line needs codimension 1).  Noise folds of one
sheet (a noisy flat sheet folded back on itself within a spacing) count as two sheets: they too are closer
than the sample resolves.

Cost: the orientation of M_S, its vertex normals and a k-d tree over its vertices, where a result has a hole
sure by its size: about 0.08 s on the 50,000-sample hand (``features`` 0.18-0.20 -> 0.27 s there).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .topology import oriented_pieces

#: A vertex across the surface lies within 60 degrees of the normal line (cos 60 = 1/2).
ACROSS_COS = 0.5


def vertex_normals(points: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals of a surface in R^3 at its vertices, each on one piece of the surface, and that piece.

    A piece is a class of triangles joined through edges in exactly two triangles
    (:func:`~.topology.oriented_pieces`); each orientable piece takes one of its two orientations.  A
    vertex's normal is the sum of its piece's triangles' normals there (their edge vectors' cross products,
    as long as twice their areas); a vertex where pieces meet takes the piece of the most triangles there
    (the lowest id among equals).  Zero on the vertices of a non-orientable piece and on vertices in no
    triangle, whose piece is -1: such a vertex faces no way.

    Returns
    -------
    normals : ndarray of shape (n, 3)
    piece : ndarray of shape (n,) of int64
    """
    n = len(points)
    tri = np.sort(np.asarray(triangles, dtype=np.int64).reshape(-1, 3), axis=1)
    normals, vpiece = np.zeros((n, 3)), np.full(n, -1, np.int64)
    if len(tri) == 0:
        return normals, vpiece
    sign, piece = oriented_pieces(tri)
    tri[sign < 0] = tri[sign < 0][:, [1, 0, 2]]
    # each vertex's piece: the one with the most of its triangles (ties: the lowest id)
    span = np.int64(piece.max()) + 1
    key, cnt = np.unique(tri.ravel() * span + np.repeat(piece, 3), return_counts=True)
    v, pc = key // span, key % span
    order = np.lexsort((pc, -cnt, v))  # per vertex: most triangles first, then the lowest piece
    first = order[np.r_[True, v[order][1:] != v[order][:-1]]]
    vpiece[v[first]] = pc[first]
    p = points[tri]
    fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) * (sign != 0)[:, None]
    for j in range(3):
        mine = vpiece[tri[:, j]] == piece
        for c in range(3):
            normals[:, c] += np.bincount(tri[mine, j], weights=fn[mine, c], minlength=n)
    norm = np.linalg.norm(normals, axis=1)
    normals /= np.where(norm > 0, norm, 1.0)[:, None]
    vpiece[norm == 0] = -1
    return normals, vpiece


def sheet_gaps(
    points: np.ndarray, triangles: np.ndarray, rims: list[np.ndarray], h: np.ndarray, reach: float
) -> list[float] | None:
    """Per rim, the median distance across the surface to a sheet facing the other way, in local spacings.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    triangles : ndarray of shape (f, 3)
        M_S.
    rims : list of ndarray of int
        Each hole's rim vertices.
    h : ndarray of shape (n,)
        The unit per sample (:func:`~.features.features` gives the components' unit: the larger of the
        nearest-neighbour distance and the local sampling radius).
    reach : float
        How far to look, in local spacings: a vertex with no such sheet within it counts as ``inf``.

    Returns
    -------
    list of float, or None
        One median per rim; None where M_S is not a surface in R^3.
    """
    if points.shape[1] != 3 or not rims:
        return None
    normals, piece = vertex_normals(points, triangles)
    used = np.flatnonzero(piece >= 0)
    tree = cKDTree(points[used])
    every = np.concatenate(rims)
    near = tree.query_ball_point(points[every], r=reach * h[every])
    gap = np.full(len(every), np.inf)
    for i, (v, found) in enumerate(zip(every.tolist(), near, strict=True)):
        if piece[v] < 0:
            continue  # faces no way (a non-orientable piece's vertex)
        q = used[np.asarray(found, dtype=np.int64)]
        way = points[q] - points[v]
        dist = np.linalg.norm(way, axis=1)
        across = (normals[q] @ normals[v] < 0) & (np.abs(way @ normals[v]) >= ACROSS_COS * dist)
        across &= piece[q] == piece[v]
        if across.any():
            gap[i] = float(dist[across].min()) / float(h[v])
    out, start = [], 0
    for rim in rims:
        out.append(float(np.median(gap[start : start + len(rim)])))
        start += len(rim)
    return out
