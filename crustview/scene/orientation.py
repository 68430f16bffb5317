"""Seeing non-orientability: a loop on a closed surface along which the normal comes back flipped (Qt-free).

On a non-orientable surface (the Klein bottle, the projective plane) the
triangles cannot all be oriented consistently.  Orienting them outwards from
one triangle, across edges, meets a triangle that would need both
orientations: the two paths back to the start, closed by that edge, are a
loop of triangles along which the orientation (the normal) reverses once.  Its
triangles form a Möbius band.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from . import geometry as geo


def _direction(tri: np.ndarray, u: int, v: int) -> int:
    """+1 when the edge u -> v runs along the stored cyclic order of ``tri``, else -1."""
    i = int(np.flatnonzero(tri == u)[0])
    return 1 if tri[(i + 1) % 3] == v else -1


def one_sided_loop(triangles: np.ndarray) -> np.ndarray:
    """Rows of ``triangles`` along an orientation-reversing loop, in order (empty when orientable).

    Parameters
    ----------
    triangles : ndarray of shape (m, 3)
        A closed (or open) triangulated surface; edges in more than two
        triangles are ignored.
    """
    tris = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    m = len(tris)
    if m == 0:
        return np.zeros(0, dtype=np.int64)
    faces, inc = geo.facets(tris)
    # the (at most two) triangles at each edge
    owners = np.full((len(faces), 2), -1, dtype=np.int64)
    count = np.zeros(len(faces), dtype=np.int64)
    for t in range(m):
        for e in inc[t]:
            if count[e] < 2:
                owners[e, count[e]] = t
            count[e] += 1
    sign = np.zeros(m, dtype=np.int8)
    parent = np.full(m, -1, dtype=np.int64)
    for root in range(m):
        if sign[root]:
            continue
        sign[root] = 1
        queue = deque([root])
        while queue:
            t = queue.popleft()
            for e in inc[t]:
                if count[e] != 2:
                    continue
                n = int(owners[e, 0] if owners[e, 1] == t else owners[e, 1])
                u, v = (int(x) for x in faces[e])
                want = -sign[t] * _direction(tris[t], u, v) * _direction(tris[n], u, v)
                if sign[n] == 0:
                    sign[n] = want
                    parent[n] = t
                    queue.append(n)
                elif sign[n] != want:
                    return _close(parent, t, n)
    return np.zeros(0, dtype=np.int64)


def _close(parent: np.ndarray, a: int, b: int) -> np.ndarray:
    """The tree paths from ``a`` and ``b`` up to their common ancestor, joined: a loop a ... lca ... b."""
    up_a = [a]
    while parent[up_a[-1]] >= 0:
        up_a.append(int(parent[up_a[-1]]))
    up_b = [b]
    while parent[up_b[-1]] >= 0:
        up_b.append(int(parent[up_b[-1]]))
    seen = {t: i for i, t in enumerate(up_a)}
    j = next(i for i, t in enumerate(up_b) if t in seen)
    lca = up_b[j]
    return np.array(up_a[: seen[lca] + 1] + up_b[:j][::-1], dtype=np.int64)


def loop_polyline(points: np.ndarray, triangles: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Points in R^k of the loop: each triangle's centroid, then the midpoint of the edge to the next (closed)."""
    tris = np.asarray(triangles, dtype=np.int64)[loop]
    if len(tris) == 0:
        return np.zeros((0, points.shape[1]))
    out = []
    for i, t in enumerate(tris):
        nxt = tris[(i + 1) % len(tris)]
        out.append(points[t].mean(axis=0))
        shared = np.intersect1d(t, nxt)
        if len(shared) == 2:
            out.append(points[shared].mean(axis=0))
    return np.asarray(out)
