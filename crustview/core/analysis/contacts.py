"""Parts of M_S joined only through faces that stand across the samples' normals: contacts the sample does not decide.

Why
---
Two objects closer than the sample spacing (two bones at a joint, a tail
lying on a body, two objects side by side in one scan) can come out of the
labelling as one closed surface: the cells of the gap take the inside label
and M_S runs across the gap.  No rule was involved, so nothing else says so
(``benchmarks/bench_objects.py``: two spheres, a sphere and a torus, two tori
one median spacing apart gave one closed surface without a flag).

Where M_S crosses such a gap its faces stand across the surface: the face
normal is far from the approximate normal (Algorithm 1) of each of its
vertices, which belong to the two objects and are roughly parallel.  A face
of T_S has its dual Voronoi edge within the paper's theta = pi/8 of the
approximate normal plane at one of its vertices; a face more than
:data:`STAND_ANGLE` = 2 theta from the normal line at *every* vertex is one no
candidate test at twice the paper's angle admits (the same doubling as the
features' LOOP_SUPPORTED = 2 LOOP_MIN).  Such faces also appear alone, where
noise or a thin part's rim turns the surface; what marks a contact is that
taking them out cuts a component of M_S into two large parts.

The rule
--------
The standing faces are set aside and the rest of each component of M_S is
split into face-connected parts.  A component that falls into two or more
parts of at least :data:`MIN_PART_FACES` faces each is reported with an
*uncertain* ``component`` feature for every such part but the largest: at its
closest approach (between its vertices and the other parts', the standing
faces' vertices aside) and with that gap in sampling radii.  Where the two sides
touch twice and belong to one component already, the contacts make a handle
instead: on a closed M_S, a handle loop whose Z/2 class the faces that do not
stand cannot carry (outside the image of their H_1; :func:`bridged_handles`)
is made uncertain with the reason :data:`BRIDGED`.  MIN_PART_FACES is
the size of the smallest closed surface an eps = 1/4 sample resolves: a
sphere of radius R sampled at sampling radius r = R / 4 in an even triangle
mesh (spacing sqrt(3) r, faces of area 3 sqrt(3) r^2 / 4) has about
16 pi / (3 sqrt(3)) * 4^2 = 155 faces; anything smaller is a fragment that noise
or a thin rim cuts off, not an object.  The check never changes M_S.
Measured (docs/history.md, session 19): the right results of the public scans, clean
and at 0.1 h, leave fragments of at most 33 faces; under 0.3 h noise
7-10 % of all faces stand across and the cut finds nothing, fused or not.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.spatial import cKDTree

from .cotree import triangle_edges
from .features import Feature
from .radii import local_spacing
from .topology import graph_components

#: A face of M_S stands across the surface when its normal is more than this from the approximate
#: normal (Algorithm 1) at every one of its vertices: twice the paper's candidate angle theta = pi/8.
STAND_ANGLE = 2 * (math.pi / 8)
#: What a handle feature's reason gains when only standing faces carry its loop (:func:`bridged_handles`).
BRIDGED = (
    "rule contact: only faces farther than the paper's candidate angle (22.5 degrees) from every vertex's "
    "normal carry this loop, a bridge over a gap between two sheets: contacts the sample does not decide"
)
#: The handles' version: a loop must be carried by faces within the paper's own candidate angle theta = pi/8
#: of the normal at one of their vertices.  Noise puts faces beyond theta everywhere (7-10 % beyond 2 theta at
#: 0.3 h), enough to cut parts of 155 faces off right results at theta, so parts are cut at 2 theta; but
#: scattered faces carry no homology class, and at theta no loop of a right result's handle was found carried
#: by them alone (the 18 noisy and 7 clean scans with handles measured in session 19), where the feline's false
#: bridge at 0.1 h (draw 27, 85 % subset) was.
HANDLE_ANGLE = math.pi / 8
#: Fewest faces of a part that counts as an object: the smallest closed surface an eps = 1/4 sample
#: resolves, a sphere of radius R at sampling radius R / 4 in an even mesh, 16 pi / (3 sqrt 3) * 16.
MIN_PART_FACES = math.ceil(16 * math.pi / (3 * math.sqrt(3)) * 4**2)


def standing_faces(
    points: np.ndarray, triangles: np.ndarray, normals: np.ndarray, angle: float = STAND_ANGLE
) -> np.ndarray:
    """Per triangle, whether its normal is more than ``angle`` (STAND_ANGLE) from every vertex's normal line.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    triangles : ndarray of shape (f, 3)
        Sample indices.
    normals : ndarray of shape (n, 3)
        A normal direction per sample (sign free; Algorithm 1's normal line).
    """
    if len(triangles) == 0:
        return np.zeros(0, bool)
    p = points[triangles]
    fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    fl = np.linalg.norm(fn, axis=1)
    nl = np.linalg.norm(normals, axis=1)
    has = np.isfinite(nl) & (nl > 0)
    unit = np.where(has[:, None], normals / np.where(has, nl, 1.0)[:, None], 0.0)
    cos = np.abs(np.einsum("fj,fvj->fv", fn, unit[triangles])) / np.where(fl > 0, fl, 1.0)[:, None]
    # judged on the vertices that have a normal (at least one); a degenerate face is never standing
    valid = has[triangles]
    near = (cos >= math.cos(angle)) & valid
    return ~near.any(axis=1) & valid.any(axis=1) & (fl > 0)


def _face_parts(triangles: np.ndarray) -> np.ndarray:
    """Face-connected parts (through shared edges) of a list of triangles: a part id per triangle."""
    if len(triangles) == 0:
        return np.zeros(0, np.int64)
    _, tri_edges = triangle_edges(triangles)
    e = tri_edges.ravel()
    order = np.argsort(e, kind="stable")
    owner = np.repeat(np.arange(len(triangles)), 3)[order]
    same = np.flatnonzero(e[order][1:] == e[order][:-1])  # consecutive triangles of one edge
    return graph_components(len(triangles), np.stack([owner[same], owner[same + 1]], axis=1))[1]


def _already_flagged(known: list[Feature] | None, vp: np.ndarray, comp_of: np.ndarray, big: np.ndarray) -> set:
    """The large parts an uncertain component feature already names.

    Its samples touch that part and another large part of the same component: a join or a dispute at
    this contact.
    """
    done: set = set()
    bigset = set(big.tolist())
    for f in known or []:
        if f.kind != "component" or not f.uncertain:
            continue
        touched = {int(q) for q in vp[np.isin(vp[:, 0], np.asarray(f.vertices, np.int64)), 1] if int(q) in bigset}
        for q in touched:
            if any(r != q and comp_of[r] == comp_of[q] for r in touched):
                done.add(q)
    return done


def hidden_parts(
    points: np.ndarray, triangles: np.ndarray, normals: np.ndarray, known: list[Feature] | None = None
) -> list[Feature]:
    """Uncertain ``component`` features where M_S holds two large parts together only by standing faces.

    Parameters
    ----------
    points : ndarray of shape (n, 3)
        The samples.
    triangles : ndarray of shape (f, 3)
        M_S.
    normals : ndarray of shape (n, 3)
        Algorithm 1's normal line at each sample.
    known : list of Feature, optional
        Features already reported; a part that an uncertain component feature already names (its
        samples touch this part and another large part of the same component: a join, a dispute at
        this contact) is not reported again.

    Returns
    -------
    list of Feature
        One per part beyond the largest of each component (see the module docstring); empty when none.
    """
    tri = np.asarray(triangles, dtype=np.int64)
    n = len(points)
    if len(tri) < 2 * MIN_PART_FACES:
        return []
    stand = standing_faces(points, tri, normals)
    if not stand.any():
        return []
    kept = np.flatnonzero(~stand)
    part = _face_parts(tri[kept])
    size = np.bincount(part)
    big = np.flatnonzero(size >= MIN_PART_FACES)
    if len(big) < 2:
        return []
    whole = _face_parts(tri)
    kt = tri[kept]
    first = np.unique(part, return_index=True)[1]
    comp_of = whole[kept][first]  # a part is face-connected, so it lies in one component
    # every (vertex, part) incidence of the kept faces; a vertex off the rim is in one part only
    vp = np.unique(np.stack([kt.ravel(), np.repeat(part, 3)], axis=1), axis=0)
    rim = np.zeros(n, bool)
    rim[tri[stand].ravel()] = True
    inner = vp[~rim[vp[:, 0]] & np.isin(vp[:, 1], big)]
    h = local_spacing(points, tri)
    done = _already_flagged(known, vp, comp_of, big)
    out: list[Feature] = []
    for comp in np.unique(comp_of[big]):
        mine = big[comp_of[big] == comp]
        if len(mine) < 2:
            continue
        mine = mine[np.argsort(-size[mine], kind="stable")]
        here = inner[np.isin(inner[:, 1], mine)]
        tree = cKDTree(points[here[:, 0]])
        k = min(32, len(here))
        for p in mine[1:]:
            if p in done:
                continue
            own = here[here[:, 1] == p, 0]
            if len(own) == 0:
                continue
            dist, idx = tree.query(points[own], k=k)
            dist, idx = dist.reshape(len(own), k), idx.reshape(len(own), k)
            other = here[idx, 1] != p  # the nearest samples of another part among the k nearest
            if not other.any():
                continue
            j = np.argmax(other, axis=1)
            d = np.where(other.any(axis=1), dist[np.arange(len(own)), j], np.inf)
            i = int(np.argmin(d))
            a, b = int(own[i]), int(here[idx[i, j[i]], 0])
            gap = float(d[i]) / max(float(min(h[a], h[b])), 1e-300)
            out.append(
                Feature(
                    "component",
                    (points[a] + points[b]) / 2,
                    gap,
                    True,
                    np.array([a, b]),
                    f"a part of {int((vp[:, 1] == p).sum())} samples held to the rest of its component only by "
                    f"faces that stand across the samples' normals (more than {math.degrees(STAND_ANGLE):.0f} "
                    f"degrees from each vertex's), {gap:.2g} sampling radii from it: two objects that touch, or a "
                    "contact the sample does not decide",
                )
            )
    return out


def bridged_handles(points: np.ndarray, triangles: np.ndarray, normals: np.ndarray, handles: list[Feature]) -> set:
    """Indices (into ``handles``) of the handle loops whose class only standing faces carry.

    On a closed M_S: the classes the rest of M_S carries are the image of H_1(K) in H_1(M_S), K the
    complex of the faces that do not stand across (every cycle of K's edge graph maps into it, and
    those cycles span H_1(K)); a handle loop whose class is outside that span passes a bridge of
    standing faces, where M_S crosses a gap between two sheets (the fused-contact case of
    :func:`hidden_parts`, when the two sides belong to one object already: a false handle).

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    triangles : ndarray of shape (f, 3)
        M_S, a surface, closed or with boundary (then capped as :func:`.loops.capped` does, session 28:
        the hand decimated to half at 0.3 h, an open scan, had a false handle across two fingers that
        only standing faces carry, and the check, closed surfaces only, never looked).
    normals : ndarray of shape (n, 3)
        Algorithm 1's normal line at each sample.
    handles : list of Feature
        The result's handle features (their ``vertices`` a closed walk on M_S's edges).

    Returns
    -------
    set of int
        Empty when no face stands or no loop is carried by standing faces alone.
    """
    from scipy.sparse.csgraph import breadth_first_order

    from .loops import _path_masks, capped, short_basis
    from .necks import _as_int, _echelon, _reduce, walk_class

    tri = np.asarray(triangles, dtype=np.int64)
    n = len(points)
    todo = [
        i
        for i, f in enumerate(handles)
        if f.kind == "handle" and not f.removed and not f.disputed and len(f.vertices) > 2
    ]
    if not todo or len(tri) == 0:
        return set()
    stand = standing_faces(points, tri, normals, HANDLE_ANGLE)
    if not stand.any():
        return set()
    edges, tri_edges = triangle_edges(tri)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    if (count > 2).any():  # a manifold only
        return set()
    # an open surface's handle classes live on its capped form (features._basis searches its loops there):
    # every hole gets a cone from an apex of its own, whose faces are bookkeeping, not faces that stand
    points, tri, edges, tri_edges, count, n = capped(points, tri, edges, tri_edges, count)
    stand = np.r_[stand, np.zeros(len(tri) - len(stand), bool)]
    cocycles: dict = {}
    basis = short_basis(points, tri, edges, tri_edges, count, n, cocycles=cocycles, cocycles_only=True)
    if isinstance(basis, int) or "mask" not in cocycles:  # too many loops to class, or none at all (genus 0)
        return set()
    mask = cocycles["mask"]
    # a spanning forest of K's edge graph, the XOR of the masks up it, and each other edge's cycle
    k_edges = np.unique(tri_edges[~stand].ravel())
    ke = edges[k_edges]
    g = coo_matrix((np.ones(len(ke), np.int8), (ke[:, 0], ke[:, 1])), shape=(n, n)).tocsr()
    g = g + g.T
    pred = np.full(n, -9999, np.int32)
    _, label = graph_components(n, ke)
    used = np.unique(ke)
    for r in used[np.unique(label[used], return_index=True)[1]].tolist():  # one root per component
        order, p = breadth_first_order(g, r, directed=False, return_predecessors=True)
        pred[order] = p[order]
    hot = np.flatnonzero(mask[k_edges].any(axis=1))
    pot = _path_masks(pred, ke[hot], mask[k_edges[hot]])
    tree = (pred[ke[:, 0]] == ke[:, 1]) | (pred[ke[:, 1]] == ke[:, 0])
    cyc = pot[ke[~tree, 0]] ^ pot[ke[~tree, 1]] ^ mask[k_edges[~tree]]
    cyc = np.unique(cyc[cyc.any(axis=1)], axis=0)
    span = _echelon(list(cyc))
    # only walks along M_S's edges have a class here (a disputed feature marks the other result's loop)
    keys = np.sort(edges[:, 0] * n + edges[:, 1])  # sorted once: each walk is looked up by bisection

    def on_surface(walk: np.ndarray) -> bool:
        w = np.asarray(walk, np.int64)
        nxt = np.roll(w, -1)
        step = w != nxt
        lo, hi = np.minimum(w, nxt)[step], np.maximum(w, nxt)[step]
        if not len(lo):
            return False
        want = lo * n + hi
        at = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
        return bool((keys[at] == want).all())

    return {
        i
        for i in todo
        if on_surface(handles[i].vertices) and _reduce(_as_int(walk_class(handles[i].vertices, cocycles)), span)
    }
