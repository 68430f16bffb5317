"""Caps that are walls: ``open-cap``'s patches of big faces that join two rims instead of covering one.

``open-cap`` (:mod:`.cells`) takes a patch of big faces more than CAP_SURE times its ring for the cap the
labelling put over an open scan's opening, and removes it.  Such a cap covers one opening: it is a disc,
bounded by one rim.  A patch bounded by two rims or more, each long enough to be one a sample shows (at least
:data:`~crustview.core.analysis.features.LOOP_MIN` local spacings, the shortest loop an eps < 1 sample
resolves), is a band between them: the side wall of a solid whose mesh has vertices only on the wall's two
edges, as CAD tools tessellate a prism or a cylinder (a gear's rim and its two faces, sampled only on the
faces), or an unscanned belt between two scanned parts.  The sample has no point on it either way, so it does
not tell the two apart, and the big faces measure the distance between the rims, not an opening: a band is no
evidence that the sample is an open scan's.  The labelling's closed answer, the theory's (Algorithm 3
reconstructs closed manifolds), is kept, and the possible opening is named: an uncertain ``hole`` at the band
and, where removing the band would cut its part in two, an uncertain ``component`` (two pieces, or one object).

A small loop inside an opening (a few stray samples there, whose own faces the cap surrounds) is usually shorter
than LOOP_MIN (a loop of k evenly spaced samples measures about k of their spacings: six or fewer), so a cap with
such islands is still a disc to this rule.  Loops are the connected pieces of the patch's boundary edges: two
rims that share a sample count as one (a wall pinched there is taken for a cap, as before this rule), and
islands that touch at a sample add up.  On the public scans, their noisy copies and
the 5 % holes of ``bench_reshaped.py`` (draw 43) no patch of a right result has two such rims; the CAD gears and
the octopus (several objects, wrong either way) have some; a held-out CAD pinion (two faces sampled, its rim
38 spacings tall) came out as two flat rings, open, until this rule (session 46, ``docs/history.md``).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..analysis.features import LOOP_MIN, Feature


def _edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every face's three edges (sorted rows, three per face) and the face each belongs to."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [0, 2]]]), axis=1)
    return edges, np.tile(np.arange(len(faces)), 3)


def _rims(
    faces: np.ndarray, patch: np.ndarray, points: np.ndarray, nn: np.ndarray
) -> list[tuple[float, float, np.ndarray]]:
    """The boundary loops of ``faces[patch]``: (length in its samples' spacing, length, samples), longest first."""
    edges, _ = _edges(faces[patch])
    rows, count = np.unique(edges, axis=0, return_counts=True)
    rim = rows[count == 1]
    if len(rim) == 0:
        return []
    verts, ends = np.unique(rim, return_inverse=True)
    ends = ends.reshape(-1, 2)
    graph = coo_matrix((np.ones(len(rim)), (ends[:, 0], ends[:, 1])), shape=(len(verts), len(verts)))
    loops, label = connected_components(graph, directed=False)
    length = np.linalg.norm(points[rim[:, 0]] - points[rim[:, 1]], axis=1)
    loop_of_edge = label[ends[:, 0]]
    out = []
    for c in range(loops):
        on = verts[label == c]
        unit = float(np.median(nn[on]))
        total = float(length[loop_of_edge == c].sum())
        out.append((total / unit if unit > 0 else np.inf, total, on))
    return sorted(out, key=lambda r: -r[1])


def rim_lengths(faces: np.ndarray, patch: np.ndarray, points: np.ndarray, nn: np.ndarray) -> list[float]:
    """The lengths of the boundary loops of the triangles ``faces[patch]``, each in its samples' spacing.

    A loop's length is the sum of its edges over the median nearest-neighbour distance ``nn`` of its samples
    (the rim's own spacing: the patch's big faces would inflate any spacing measured on M_S).  Longest first.
    """
    return [r for r, _, _ in _rims(faces, patch, points, nn)]


def is_wall(faces: np.ndarray, patch: np.ndarray, points: np.ndarray, nn: np.ndarray) -> bool:
    """Whether the patch is a side between two rims of at least LOOP_MIN spacings, at most as far apart as one is long.

    The height is the median distance from the shortest such rim's samples to the other rims' nearest.  A band
    taller than its shortest rim is long is a tube reaching across a gap, what the labelling spans between
    separate parts (the public octopus: rims of 7 and 46 spacings 600 spacings apart); a solid's side sampled
    only along its edges is wider than tall unless the solid is a pin (the held-out pinion: rims 237 spacings
    long, 38 apart; the CAD tube of ``tests/test_core_planar.py``: 96 and 96, 26 apart).  A pin stays opened.
    """
    rims = [r for r in _rims(faces, patch, points, nn) if r[0] >= LOOP_MIN]
    if len(rims) < 2:
        return False
    _, length, shortest = rims[-1]
    others = np.concatenate([on for _, _, on in rims[:-1]])
    height = float(np.median(cKDTree(points[others]).query(points[shortest])[0]))
    return height <= length


def pieces_without(faces: np.ndarray, patch: np.ndarray) -> list[np.ndarray]:
    """The parts that the patch's own part of ``faces`` falls into without it (face indices; one if it holds).

    Parts are edge-connected: two faces sharing an edge are in one part.
    """
    f = len(faces)
    keep = np.ones(f, bool)
    keep[patch] = False
    _, part = connected_components(_shared_edges(faces, np.arange(f)), directed=False)
    mine = keep & (part == part[patch[0]])
    # the kept faces' own shared edges (an edge of three faces or more still joins the kept ones among them)
    _, piece = connected_components(_shared_edges(faces, np.flatnonzero(keep)), directed=False)
    return [np.flatnonzero(mine & (piece == p)) for p in np.unique(piece[mine])]


def _shared_edges(faces: np.ndarray, rows: np.ndarray) -> coo_matrix:
    """The graph on all faces in which ``faces[rows]`` sharing an edge are joined."""
    edges, owner = _edges(faces[rows])
    owner = rows[owner]
    key = edges[:, 0].astype(np.int64) * (int(faces.max()) + 1) + edges[:, 1]
    order = np.argsort(key, kind="stable")
    same = np.flatnonzero(key[order][1:] == key[order][:-1])
    a, b = owner[order[same]], owner[order[same + 1]]
    return coo_matrix((np.ones(len(a)), (a, b)), shape=(len(faces), len(faces)))


def kept_walls(points: np.ndarray, faces: np.ndarray, walls: list[tuple[np.ndarray, np.ndarray, float]]) -> list:
    """The walls ``open-cap`` kept closed, as uncertain removed features: a ``hole``, and a ``component`` if it splits.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    faces : ndarray of shape (f, 3)
        M_S when ``open-cap`` looked at it (the walls' patches index it).
    walls : list of (ndarray of int, ndarray of int, float)
        Each wall's patch (rows of ``faces``), its samples and its ratio to its ring (:func:`.cells.cap_ratios`).
    """
    from ..util.nearest import nearest_distances
    from .cap_holes import cap_hole

    if not walls:
        return []
    nn = nearest_distances(points)
    out = []
    for patch, vs, q in walls:
        rims = [r for r in rim_lengths(faces, patch, points, nn) if r >= LOOP_MIN]
        said = f"{len(rims)} rims (" + ", ".join(f"{r:.0f}" for r in rims[:4]) + (" ..." if len(rims) > 4 else "")
        out.append(
            cap_hole(
                points,
                vs,
                nn,
                lambda size, vs=vs, q=q, said=said: (
                    f"a wall kept closed (rule open-cap): {len(vs)} samples on {said} spacings long) "
                    f"joined by faces {q:.2g} times the size of those around them, with no sample on them: a solid's "
                    "side sampled only along its edges (as CAD meshes are), or openings between scanned parts; the "
                    "sample does not tell which"
                ),
            )
        )
        parts = pieces_without(faces, patch)
        if len(parts) > 1 and len(np.setdiff1d(faces[np.concatenate(parts)], faces[min(parts, key=len)])):
            out.append(_joined_part(points, faces, parts, nn))
    return out


def _joined_part(points: np.ndarray, faces: np.ndarray, parts: list[np.ndarray], nn: np.ndarray) -> Feature:
    """The smallest of the parts a wall joins, as an uncertain removed ``component``: its gap to the others."""
    small = min(parts, key=len)
    on = np.unique(faces[small])
    rest = np.setdiff1d(np.unique(np.concatenate([faces[p].ravel() for p in parts])), on)
    gap, near = cKDTree(points[rest]).query(points[on])
    i = int(np.argmin(gap))
    unit = float(np.median(nn[on]))
    size = float(gap[i]) / unit if unit > 0 else np.inf
    return Feature(
        "component",
        (points[on[i]] + points[rest[near[i]]]) / 2,
        size,
        True,
        np.array([on[i], rest[near[i]]], np.int64),
        f"joined by a wall kept closed (rule open-cap): a part of {len(on)} samples, {size:.3g} spacings from the "
        "rest, held to it only by faces no sample supports; one object whose wall the sample has no points on, "
        "or separate pieces",
        removed=True,
    )
