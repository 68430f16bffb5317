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
way, so noise that moves it off the tangent plane does not count.  Only vertices of p's own piece of M_S
count: the two orientations of another piece are equally good, so its facing says nothing (parts that nearly
touch are the components' measure).  Over a rim, the median: the rim mostly lies where the sheets are that
close.  Only for surfaces in R^3 (a normal line needs codimension 1) whose M_S has a consistent orientation.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .topology import graph_components, orientation

#: A vertex across the surface lies within 60 degrees of the normal line (cos 60 = 1/2).
ACROSS_COS = 0.5


def vertex_normals(points: np.ndarray, triangles: np.ndarray) -> np.ndarray | None:
    """Unit normals of a surface in R^3 at its vertices, from a consistent orientation (None: it has none).

    Each triangle's normal (its edge vectors' cross product, as long as twice its area) is summed at its
    three vertices; each piece of the surface takes one of its two orientations, so a vertex's normal points
    to the same side as its neighbours' on that piece.
    """
    tri = np.sort(np.asarray(triangles, dtype=np.int64), axis=1)
    sign = orientation(tri)
    if sign is None:
        return None
    tri[sign < 0] = tri[sign < 0][:, [1, 0, 2]]
    p = points[tri]
    fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    vn = np.zeros((len(points), 3))
    for j in range(3):
        np.add.at(vn, tri[:, j], fn)
    norm = np.linalg.norm(vn, axis=1)
    return vn / np.where(norm > 0, norm, 1.0)[:, None]


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
        One median per rim; None where M_S is not a surface in R^3 with a consistent orientation.
    """
    if points.shape[1] != 3 or not rims:
        return None
    normals = vertex_normals(points, triangles)
    if normals is None:
        return None
    tri = np.asarray(triangles, dtype=np.int64)
    used = np.unique(tri)
    _, piece = graph_components(len(points), np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]]]))
    tree = cKDTree(points[used])
    every = np.concatenate(rims)
    near = tree.query_ball_point(points[every], r=reach * h[every])
    gap = np.full(len(every), np.inf)
    for i, (v, found) in enumerate(zip(every.tolist(), near, strict=True)):
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
