"""A surface's holes (its boundary loops), each with its span and what the sample says of it.

The bounds are the features' (:mod:`.features`, whose module text says why): a hole narrower than
HOLE_SUPPORTED spacings, or closer than GAP_MIN to another hole, or whose rim lies on two sheets of M_S
closer than GAP_MIN (:mod:`.sheets`), is uncertain.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..util.nearest import nearest_distances
from ..util.vectors import edge_lengths
from .features import GAP_MIN, HOLE_SUPPORTED, LOOP_MIN, Feature
from .sheets import sheet_gaps


def holes_of_surface(
    points: np.ndarray, edges: np.ndarray, count: np.ndarray, h: np.ndarray, triangles: np.ndarray
) -> list[Feature]:
    """Boundary loops (edges in one triangle), their span, and the sheets across their rim (:mod:`.sheets`)."""
    rim = edges[count == 1]
    if len(rim) == 0:
        return []
    n = len(points)
    g = coo_matrix((np.ones(len(rim), np.int8), (rim[:, 0], rim[:, 1])), shape=(n, n))
    _, label = connected_components(g, directed=False)
    lab = label[rim[:, 0]]
    holes = np.unique(lab).tolist()
    strip = strips(points, edges, rim, lab, h) if len(holes) > 1 else {}
    verts = {c: np.unique(rim[lab == c]) for c in holes}
    size = {}
    for c in holes:
        p = points[verts[c]]
        span = float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)) * 2)
        size[c] = span / float(np.median(h[verts[c]]))
    # the holes wide enough to be sure by their size: is their rim on a part of M_S thinner than resolved?
    wide = [c for c in holes if size[c] >= HOLE_SUPPORTED and strip.get(c, np.inf) >= GAP_MIN]
    sheet: dict[int, float] = {}
    if wide:  # in the components' unit (GAP_MIN's): the larger of the nearest-neighbour distance and h
        unit = np.maximum(nearest_distances(points), h)
        gaps = sheet_gaps(points, triangles, [verts[c] for c in wide], unit, GAP_MIN)
        sheet = dict(zip(wide, gaps, strict=True)) if gaps is not None else {}
    result = []
    for c in holes:
        narrow = strip.get(c, np.inf) < GAP_MIN
        thin = sheet.get(c, np.inf) < GAP_MIN
        unc = size[c] < HOLE_SUPPORTED or narrow or thin
        reason = f"hole with {int((lab == c).sum())} rim edges, {size[c]:.3g} spacings across" + (
            " (as wide as one missing sample: may be a gap)"
            if size[c] < LOOP_MIN / math.pi
            else " (its rim is shorter than 4 pi spacings: only a sample coarser than eps = 1/2 resolves it, "
            "so it may be a gap)"
            if size[c] < HOLE_SUPPORTED
            else f" (a strip of {strip[c]:.2g} spacings from another hole, narrower than the sample can "
            "separate: may be one opening)"
            if narrow
            else f" (its rim lies where M_S has two sheets {sheet[c]:.2g} spacings apart facing opposite ways, a thin "
            "part or a fold, closer than the sample resolves: may be a hole noise opened through it)"
            if thin
            else ""
        )
        result.append(Feature("hole", points[verts[c]].mean(axis=0), size[c], unc, verts[c], reason))
    return result


def strips(points: np.ndarray, edges: np.ndarray, rim: np.ndarray, lab: np.ndarray, h: np.ndarray) -> dict[int, float]:
    """Per hole, the narrowest strip of M_S between its rim and another hole's, in local spacings.

    The strip's width is the shortest path along the edges of M_S from one rim to the other (two
    holes that face each other across empty space are not a strip: the surface between them goes
    the long way round).  The unit is the one of the components' gaps, the larger of the
    nearest-neighbour distance and h, at the far rim's vertex.  Two holes closer than GAP_MIN may be
    one opening with a ribbon of faces left across it (the labelling's cap split in two), or a thin
    strip of surface: the sample does not tell them apart.
    """
    from scipy.sparse.csgraph import dijkstra

    n = len(points)
    verts = np.unique(rim)
    hole_of = np.full(n, -1, np.int64)
    hole_of[rim[:, 0]] = lab
    hole_of[rim[:, 1]] = lab
    unit = np.zeros(n)
    unit[verts] = np.maximum(nearest_distances(points)[verts], h[verts])
    length = edge_lengths(points, edges)
    graph = coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    limit = GAP_MIN * float(unit[verts].max())
    out: dict[int, float] = {}
    for c in np.unique(lab).tolist():
        mine = verts[hole_of[verts] == c]
        dist = dijkstra(graph, directed=False, indices=mine, min_only=True, limit=limit)
        far = verts[(hole_of[verts] != c) & np.isfinite(dist[verts])]
        out[c] = float((dist[far] / unit[far]).min()) if len(far) else np.inf
    return out
