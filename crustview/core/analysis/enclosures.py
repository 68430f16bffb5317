"""Closed surfaces of M_S that hold two enclosures of the sample: objects joined where they touch.

Why
---
Two objects closer than the sample spacing can come out of the robust
extraction as one closed surface that runs across the gap (two spheres, a
sphere and a torus, two tori one spacing apart under noise of 0.3 h:
``benchmarks/bench_objects.py``).  Where the faces across the gap stand across
the surface, :mod:`.contacts` flags them; under noise the faces of the whole
surface tilt as much and that test is blind.

The sample itself says how many closed surfaces it holds, without a scale
chosen in advance: a closed surface encloses a
region, and the union of balls of radius r around its samples encloses that
region as a *void* (a bounded component of the complement) from the radius
at which the balls cover the surface until the radius at which they fill the
region.  The voids and their lifetimes are the 2-dimensional persistent
homology of the alpha complex, which duality in R^3 turns into the
0-dimensional persistence of the Delaunay tetrahedra joined across triangles,
read from the largest radius down (the elder rule, ``_components.merges``).

A void's birth says how it was closed.  Covering a surface closes it at the
sample's own spacing: the last gap of the surface to be covered is a
triangle of the sample about one spacing across.  A void can also be born by
the splitting of another, when a narrow passage between two chambers fills
(a dumbbell's neck): then the birth radius is the passage's radius.  A
passage of at least GAP_MIN = 2 local spacings in radius has a rim of at
least 4 pi spacings, a loop the sample resolves (the features'
LOOP_SUPPORTED), so the chamber behind it is part of the same object.  An
*enclosure* is a persistent void born below that, by a face lying in the
surface: a passage narrower than that fills with faces standing across it,
at the passage's middle, where a covering face lies in the surface.  By the Jordan-Brouwer
theorem a closed surface bounds one region, so a component of M_S that holds
the samples of two enclosures joined two surfaces, or closed a passage
narrower than the sample resolves: either way the sample does not decide it.
Either test alone flags right results: by the lie of the face alone, a tube
meeting a ball at a right angle (the triangles across its mouth lie in the
ball's surface, and a straight tube fills everywhere at once); by the
radius alone, neptune's ankles (1.7 local spacings, its base a chamber of its
own: uncertain under LOOP_SUPPORTED, but its faces stand across the leg).

The rule
--------
Only for closed M_S that are not the paper's own result (robust mode): surfaces
in R^3 (:func:`joined_enclosures`) and curves in the plane (:func:`joined_loops`,
with persistent 1-cycles and edges for voids and triangles).  A void is persistent when it lives
from radius r to at least :data:`~.alpha.PERSISTENT` r (the curve rule's bound: an
eps-sample with eps <= 1/2 keeps its enclosure from eps lfs to about lfs),
and an enclosure when it is born below GAP_MIN times the largest local
spacing (:func:`~.radii.local_spacing` on M_S) at its birth triangle and that
triangle lies in the surface: its normal within :data:`~.contacts.STAND_ANGLE`
= 2 theta of the approximate normal (Algorithm 1) at one of its vertices.  Each
enclosure is the set of samples around its region at its birth, and belongs
to a component of M_S when that component holds all of them (a region
between two nested surfaces, a hollow ball's shell, is bounded by both and
belongs to neither).  A component that holds two
or more enclosures gets an *uncertain* ``component`` feature for each
enclosure but the largest: at the closest approach of its samples to the
other enclosures' samples, with that gap in local spacings.  The check never
changes M_S.
"""

from __future__ import annotations

import math
from concurrent.futures import Future

import numpy as np
from scipy.spatial import cKDTree

from ..delaunay.adjacency import cell_adjacency
from ..util.vectors import squared_distances
from .alpha import ATTACH_TOL, PERSISTENT, AlphaLadder, dual_merges, merge_regions
from .contacts import STAND_ANGLE
from .cotree import triangle_edges
from .features import GAP_MIN, Feature
from .radii import local_spacing
from .topology import graph_components


def _triangle_balls(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and squared radius of each triangle's circumcircle (its smallest circumscribing ball)."""
    a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    axb = np.cross(a, b)
    den = 2 * np.einsum("ij,ij->i", axb, axb)
    num = np.cross(np.einsum("ij,ij->i", a, a)[:, None] * b - np.einsum("ij,ij->i", b, b)[:, None] * a, axb)
    with np.errstate(divide="ignore", invalid="ignore"):
        off = num / den[:, None]
    r2 = np.einsum("ij,ij->i", off, off)
    r2[~np.isfinite(r2)] = np.inf
    return p[:, 0] + np.where(np.isfinite(off), off, 0.0), r2


def enclosure_voids(
    dpts: np.ndarray,
    simplices: np.ndarray,
    centres: np.ndarray,
    n: int,
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> list[tuple[float, float, np.ndarray, np.ndarray]]:
    """The persistent voids of the samples' alpha filtration.

    Parameters
    ----------
    dpts : ndarray of shape (N, 3)
        The Delaunay vertices: the n samples first, then bounding points (whose cells are outside).
    simplices : ndarray of shape (m, 4)
        The Delaunay tetrahedra over ``dpts``.
    centres : ndarray of shape (m, 3)
        Their circumcentres.
    n : int
        Number of samples.

    Returns
    -------
    list of (birth, death, triangle, samples)
        Per persistent void: its birth and death radii, the birth triangle (three sample ids) and the
        samples of the tetrahedra of its region at birth, less the regions of the persistent voids inside
        it (a hollow ball's cavity is not part of its shell's region).
    """
    simplices = np.asarray(simplices)
    m = len(simplices)
    if m == 0:
        return []
    tet_r2 = squared_distances(centres, None, dpts, simplices[:, 0])
    outside_tet = (simplices >= n).any(axis=1)
    a, b, faces = cell_adjacency(simplices) if adjacency is None else adjacency
    both_out = outside_tet[a] & outside_tet[b]  # between two outside cells: never a wall of a void
    a, b, faces = a[~both_out], b[~both_out], faces[~both_out]
    real = (faces < n).all(axis=1)
    centre, r2 = _triangle_balls(dpts[faces[real]])
    t_r2 = np.full(len(faces), np.inf)
    t_r2[real] = r2
    # a flat tetrahedron (its vertices on one circle) fills with its last face
    flat = ~np.isfinite(tet_r2)
    if flat.any():
        fix = np.zeros(m)
        fin = np.where(np.isfinite(t_r2), t_r2, 0.0)
        np.maximum.at(fix, a, fin)
        np.maximum.at(fix, b, fin)
        tet_r2 = np.where(flat, fix, tet_r2)
    # a face whose smallest ball holds the opposite vertex of a tetrahedron is attached to it and enters
    # with it (the first of the two to enter); otherwise with its own ball (a vertex on the sphere: see
    # alpha.ATTACH_TOL)
    ids = np.flatnonzero(real)
    face_sum = faces[real].sum(axis=1, dtype=np.int64)
    via = np.full(len(faces), np.inf)
    for side in (a, b):
        opp = simplices[side[real]].sum(axis=1, dtype=np.int64) - face_sum  # the vertex not on the face
        hit = ids[((dpts[opp] - centre) ** 2).sum(axis=1) <= r2 * (1 + ATTACH_TOL)]
        via[hit] = np.minimum(via[hit], tet_r2[side[hit]])
    alpha = np.where(np.isfinite(via), via, t_r2)
    node = np.where(outside_tet, m, np.arange(m))
    born = np.r_[np.where(outside_tet, np.inf, tet_r2), np.inf]
    edge, young, elder = dual_merges(born, node[a], node[b], alpha)
    if len(edge) == 0:
        return []
    birth2, death2 = alpha[edge], born[young]
    keep = np.flatnonzero((death2 > birth2) & (death2 >= PERSISTENT**2 * birth2) & real[edge])
    if len(keep) == 0:
        return []
    region = merge_regions(m + 1, young, elder, young[keep])[:m]
    out = []
    for i in keep.tolist():
        cells = np.flatnonzero((region == young[i]) & ~outside_tet)
        samples = np.unique(simplices[cells].ravel())
        out.append((math.sqrt(birth2[i]), math.sqrt(death2[i]), faces[edge[i]], samples[samples < n]))
    return out


def _named(known: list[Feature] | None, mine: np.ndarray, others: np.ndarray) -> bool:
    """Whether an uncertain component feature already joins these samples to the others'."""
    for f in known or []:
        if f.kind == "component" and f.uncertain:
            v = np.asarray(f.vertices, np.int64)
            if np.isin(v, mine).any() and np.isin(v, others).any():
                return True
    return False


def joined_enclosures(
    points: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    cells: tuple[np.ndarray, np.ndarray, np.ndarray],
    known: list[Feature] | None = None,
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    voids: Future | None = None,
) -> list[Feature]:
    """Uncertain ``component`` features where one closed component of M_S holds two enclosures.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
        The samples.
    triangles : ndarray of shape (f, 3)
        M_S (a closed surface).
    normals : ndarray of shape (n, 3)
        Algorithm 1's normal line at each sample.
    cells : (delaunay_points, simplices, centres)
        The Delaunay tetrahedra of the samples and the bounding points, with their circumcentres.
    known : list of Feature, optional
        Features already reported: a contact that an uncertain ``component`` feature already names (one
        of its samples in this enclosure, one in another) is not reported again.
    adjacency : (a, b, faces), optional
        The tetrahedra's shared faces (:func:`~crustview.core.delaunay.adjacency.cell_adjacency` of
        ``cells``'s simplices), if already known (the labelling's).
    voids : Future, optional
        :func:`enclosure_voids` of ``cells`` (with ``adjacency``) begun by the caller on another thread.
    """
    tri = np.asarray(triangles, np.int64)
    # a begun search is always waited for, so its thread never outlives the call
    regions = voids.result() if voids is not None else None
    if len(tri) == 0:
        return []
    if regions is None:
        regions = enclosure_voids(*cells, len(points), adjacency)
    if len(regions) < 2:
        return []
    return _report(points, tri, normals, [(b, f, s) for b, _d, f, s in regions], known, "surface")


def joined_loops(
    points: np.ndarray, edges: np.ndarray, normals: np.ndarray, known: list[Feature] | None = None
) -> list[Feature]:
    """The plane's version of :func:`joined_enclosures`: closed curves of M_S holding two enclosed regions.

    The regions are the persistent 1-cycles of the samples' alpha filtration
    (:meth:`~.alpha.AlphaLadder.loops`), born below GAP_MIN local spacings by an edge lying along the
    curve (the edge's normal within STAND_ANGLE of the approximate normal at one of its ends); by the
    Jordan curve theorem a closed curve bounds one.

    Parameters
    ----------
    points : ndarray of shape (n, 2)
    edges : ndarray of shape (e, 2)
        M_S (closed curves).
    normals : ndarray of shape (n, 2)
        Algorithm 1's normal line at each sample.
    known : list of Feature, optional
        As for :func:`joined_enclosures`.
    """
    edges = np.asarray(edges, np.int64)
    if len(edges) < 3 or len(points) < 4:
        return []
    ladder = AlphaLadder(points)
    pairs = ladder.loops()
    keep = np.flatnonzero(pairs[:, 1] >= PERSISTENT * pairs[:, 0])
    if len(keep) < 2:
        return []
    regions = ladder.loop_samples(keep)
    cycles = [(pairs[i, 0], pairs[i, 2:4].astype(np.int64), s) for i, s in zip(keep.tolist(), regions, strict=True)]
    return _report(points, edges, normals, cycles, known, "curve")


def joined_objects(
    points: np.ndarray,
    simplices: np.ndarray,
    normals: np.ndarray,
    cells: tuple[np.ndarray, np.ndarray, np.ndarray],
    known: list[Feature] | None = None,
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    voids: Future | None = None,
) -> list[Feature]:
    """:func:`joined_enclosures` for a surface in R^3, :func:`joined_loops` for a curve in the plane, else none.

    ``voids``: :func:`enclosure_voids` of ``cells`` begun by the caller on another thread (surfaces in R^3).
    """
    simplices = np.asarray(simplices, np.int64)
    if simplices.ndim != 2 or simplices.shape[1] != points.shape[1]:
        return []
    if points.shape[1] == 3:
        return joined_enclosures(points, simplices, normals, cells, known, adjacency, voids)
    if points.shape[1] == 2:
        return joined_loops(points, simplices, normals, known)
    return []


def _lying(points: np.ndarray, face: np.ndarray, unit: np.ndarray) -> bool:
    """Whether a face (an edge in the plane, a triangle in space) lies within STAND_ANGLE of a vertex's normal."""
    p = points[face]
    if len(face) == 2:
        d = p[1] - p[0]
        fn = np.array([-d[1], d[0]])
    else:
        fn = np.cross(p[1] - p[0], p[2] - p[0])
    fn = fn / max(float(np.linalg.norm(fn)), 1e-300)
    return bool((np.abs(unit[face] @ fn) >= math.cos(STAND_ANGLE)).any())


def _report(
    points: np.ndarray,
    simplices: np.ndarray,
    normals: np.ndarray,
    regions: list[tuple[float, np.ndarray, np.ndarray]],
    known: list[Feature] | None,
    what: str,
) -> list[Feature]:
    """The features of :func:`joined_enclosures` and :func:`joined_loops` from their regions.

    ``regions`` holds, per persistent region, its birth radius, its birth face and its samples.
    """
    n = len(points)
    h = local_spacing(points, simplices)
    edges = triangle_edges(simplices)[0] if simplices.shape[1] == 3 else simplices
    _, comp = graph_components(n, edges)
    used = np.zeros(n, bool)
    used[simplices.ravel()] = True
    unit = normals / np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    found = []  # (component, samples)
    for birth, face, samples in regions:
        if birth >= GAP_MIN * float(h[face].max()):
            continue  # closed across a passage wider than the sample resolves: a chamber split off
        if not _lying(points, face, unit):
            continue  # closed by a face standing across the surface: a narrower passage filled
        mine = samples[used[samples]]
        if len(mine) == 0 or (comp[mine] != comp[mine[0]]).any():
            continue  # bounded by two components (between nested ones): no component's own region
        found.append((int(comp[mine[0]]), mine))
    out: list[Feature] = []
    for c in sorted({c for c, _ in found}):
        here = sorted((s for cc, s in found if cc == c), key=len, reverse=True)
        if len(here) < 2:
            continue
        for j, own in enumerate(here[1:], start=1):
            others = np.setdiff1d(np.concatenate([s for i, s in enumerate(here) if i != j]), own)
            mine = np.setdiff1d(own, others)
            if len(mine) == 0 or len(others) == 0 or _named(known, mine, others):
                continue
            dist, idx = cKDTree(points[others]).query(points[mine])
            k = int(np.argmin(dist))
            p, q = int(mine[k]), int(others[idx[k]])
            gap = float(dist[k]) / max(float(min(h[p], h[q])), 1e-300)
            out.append(
                Feature(
                    "component",
                    (points[p] + points[q]) / 2,
                    gap,
                    True,
                    np.array([p, q], np.int64),
                    f"enclosures: this closed {what} of M_S holds the samples of {len(here)} regions the "
                    f"sample encloses on its own (persistent in the union of balls, closed by a face lying "
                    f"along the {what}), and a closed {what} bounds one: two objects joined here, "
                    f"{gap:.2f} local spacings apart",
                )
            )
    return out
