"""Topology of a pure d-complex: manifold checks, Z/2 Betti numbers, orientability.

* **Closed manifold**: every (d-1)-face lies in exactly two d-simplices
  (closed pseudo-manifold) and the link of every vertex is a (d-1)-sphere.
  The link test is: for d = 1, two neighbours; for d >= 2, the link is
  connected and has the Euler characteristic of S^(d-1).  Since the link of a
  closed pseudo-manifold vertex is itself a closed pseudo-manifold, this is
  exact for d <= 3 (a connected closed surface with chi = 2 is S^2); for
  d >= 4 it certifies a homology-sphere-like link.
* **Betti numbers over Z/2** by ranks of the boundary matrices.  rank d_1 comes
  from graph components; for a closed pseudo-manifold rank d_d equals
  #d-simplices minus #components of the dual graph (the only d-cycles are the
  components' fundamental classes); every other rank is computed by column
  reduction over GF(2) (:mod:`.ranks`: compiled, or Python integers as bit sets).
* **Triangle complexes** (d = 2) with no edge in more than two triangles have
  every count of the report (edges, boundary, components, the dual graph's
  closed components, pinched vertices, orientability) from one compiled pass
  per vertex (``_surface.surface_report``), the same integers as the general
  code below (``tests/test_core_topology_compiled.py``), which runs without
  the extension and wherever an edge has three triangles or more.
* **Orientability**: a consistent orientation exists iff the signed dual
  graph has no component containing both orientations of one simplex.
"""

from __future__ import annotations

import hashlib
import itertools
from dataclasses import replace

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..result import TopologyReport
from ..util.memory import release_free_memory
from ..util.rows import dense_ids, unique_rows
from .ranks import boundary_rank_gf2

try:
    from . import _components
except ImportError:  # pragma: no cover - the extension is optional
    _components = None
try:
    from ..util import _surface
except ImportError:  # pragma: no cover - the extension is optional
    _surface = None


def all_faces(simplices: np.ndarray, facets: np.ndarray | None = None) -> list[np.ndarray]:
    """Unique j-faces for j = 0..d as sorted rows (``faces[j]`` has j+1 columns).

    ``facets``: the (d-1)-faces when known already (:func:`_facet_pairs`), shared, not recomputed.
    """
    srt = np.sort(simplices, axis=1)
    dp1 = srt.shape[1]
    out = []
    for j in range(dp1):
        if facets is not None and j == dp1 - 2:
            out.append(facets)
            continue
        if j == 0 and len(srt) and srt.min() >= 0 and dense_ids(int(srt.max()), srt.size):  # sorted, unique, no sort
            present = np.zeros(int(srt.max()) + 1, dtype=bool)
            present[srt.ravel()] = True
            out.append(np.flatnonzero(present).astype(np.int64).reshape(-1, 1))
            continue
        combos = np.array(list(itertools.combinations(range(dp1), j + 1)))
        f = srt[:, combos].reshape(-1, j + 1)
        out.append(unique_rows(f)[0])
    return out


def graph_components(n: int, edges: np.ndarray) -> tuple[int, np.ndarray]:
    """Connected components of an undirected graph on ``n`` nodes.

    Parameters
    ----------
    n : int
    edges : ndarray of shape (e, 2)

    Returns
    -------
    count : int
    labels : ndarray of shape (n,)
        scipy's ``connected_components`` labels (int32): components numbered
        in the order of their smallest node.  The compiled union-find
        (``_components.cpp``) gives the same labels without the sparse matrix.
    """
    if len(edges) == 0:
        return n, np.arange(n)
    if _components is not None and n < 2**31:
        edges = np.asarray(edges)
        count, labels = _components.components(
            n, np.ascontiguousarray(edges[:, 0], dtype=np.int64), np.ascontiguousarray(edges[:, 1], dtype=np.int64)
        )
        return count, np.frombuffer(labels, dtype=np.int32).copy()
    return scipy_components(n, edges)


def scipy_components(n: int, edges: np.ndarray) -> tuple[int, np.ndarray]:
    """:func:`graph_components` by scipy (the reference of the compiled one)."""
    g = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    return connected_components(g, directed=False)


def _facet_pairs(simplices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Facets of a d-complex and how the simplices meet them.

    Returns
    -------
    facets : ndarray of shape (g, d)
        Sorted unique rows.
    inv : ndarray of shape (c * (d + 1),)
        Facet of entry ``i * (d + 1) + a``: simplex ``i`` without its ``a``-th
        (sorted) vertex.
    counts : ndarray of shape (g,)
        Simplices at each facet.
    order : ndarray of shape (c * (d + 1),)
        Entries grouped by facet (stable); ``order // (d + 1)`` is the
        simplex, ``order % (d + 1)`` the position of the vertex opposite.
    """
    srt = np.sort(simplices, axis=1)
    dp1 = srt.shape[1]
    # entry i * dp1 + a: row i without its a-th column (one gather)
    keep = np.array([[b for b in range(dp1) if b != a] for a in range(dp1)], dtype=np.intp).reshape(1, -1)
    allf = np.take_along_axis(srt, np.broadcast_to(keep, (len(srt), keep.shape[1])), axis=1).reshape(-1, dp1 - 1)
    del srt
    facets, inv = unique_rows(allf)
    del allf
    order = np.argsort(inv, kind="stable").astype(np.int32 if len(inv) < 2**31 else np.int64)
    return facets, inv, np.bincount(inv, minlength=len(facets)), order


def _shared_facets(pairs: tuple, dp1: int, exactly: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Facets in ``exactly`` two simplices: their ids and both (simplex, opposite position) entries."""
    _, _, counts, order = pairs
    starts = np.cumsum(counts) - counts
    two = np.flatnonzero(counts == exactly)
    return two, order[starts[two]], order[starts[two] + 1]


def orientable(simplices: np.ndarray, pairs: tuple | None = None) -> bool:
    """Whether a pure complex without non-manifold faces admits a consistent orientation.

    Every facet in two simplices asks them to induce opposite orientations on it; a facet in one simplex
    (boundary) asks nothing, so a disc or an annulus is orientable and a Moebius band is not.
    """
    return orientation(simplices, pairs) is not None


def orientation(simplices: np.ndarray, pairs: tuple | None = None) -> np.ndarray | None:
    """A consistent orientation of a pure complex, or None where it has none (see :func:`orientable`).

    Returns
    -------
    ndarray of shape (c,) of int8, or None
        +1 where simplex i keeps the order of its sorted vertices, -1 where it takes the other; each
        piece's overall sign is arbitrary (:func:`oriented_pieces`).
    """
    sign, _ = oriented_pieces(simplices, pairs)
    return None if (sign == 0).any() else sign


def oriented_pieces(simplices: np.ndarray, pairs: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each simplex's piece and its orientation within the piece.

    A *piece* is a class of simplices joined through facets in exactly two simplices (facets in more ask
    nothing: the simplices around them may face any way), the unit on which an orientation is defined.

    Returns
    -------
    sign : ndarray of shape (c,) of int8
        +1 where simplex i keeps the order of its sorted vertices, -1 where it takes the other, consistent
        within each piece (whose overall sign is arbitrary); 0 on the simplices of a piece that has no
        consistent orientation (a Moebius band).
    piece : ndarray of shape (c,) of int64
        The piece of each simplex (equal ids, equal pieces).
    """
    c, dp1 = simplices.shape
    if c == 0:
        return np.zeros(0, np.int8), np.zeros(0, np.int64)
    pairs = pairs if pairs is not None else _facet_pairs(simplices)
    _, e1, e2 = _shared_facets(pairs, dp1)
    s1, s2 = (e1 // dp1).astype(np.int64), (e2 // dp1).astype(np.int64)  # 2 s + 1 below: no int32 wrap
    same = ((e1 % dp1) + (e2 % dp1)) % 2 == 1
    del e1, e2
    # node 2s is simplex s with orientation +1, 2s + 1 with -1; o2 = -o1 * (-1)^(a1 + a2)
    plus1, plus2 = 2 * s1, 2 * s2
    del s1, s2
    e = np.concatenate(
        [
            np.stack([plus1, np.where(same, plus2, plus2 + 1)], axis=1),
            np.stack([plus1 + 1, np.where(same, plus2 + 1, plus2)], axis=1),
        ]
    )
    del plus1, plus2, same
    _, labels = graph_components(2 * c, e)
    a, b = labels[0::2].astype(np.int64), labels[1::2].astype(np.int64)
    # an orientable piece's double cover has two components, one holding every simplex's +1 or its -1: the
    # one of the smaller label is taken, the same choice for every simplex of the piece; a non-orientable
    # piece's double cover is one component, holding both of every simplex
    return np.where(a == b, 0, np.where(a < b, 1, -1)).astype(np.int8), np.minimum(a, b)


def singular_vertices(simplices: np.ndarray, faces: list[np.ndarray], pairs: tuple | None = None) -> np.ndarray:
    """Vertices whose link is not a (d-1)-sphere (see module docstring)."""
    srt = np.sort(simplices, axis=1)
    c, dp1 = srt.shape
    d = dp1 - 1
    verts = faces[0][:, 0]
    n = int(verts.max()) + 1 if len(verts) else 0
    if d == 1:
        deg = np.bincount(srt.ravel(), minlength=n)
        return verts[deg[verts] != 2]
    # link Euler characteristic: #j-faces of link(v) = #(j+1)-faces of M containing v
    chi = np.zeros(n, dtype=np.int64)
    for j in range(d):
        cnt = np.bincount(faces[j + 1].ravel(), minlength=n)
        chi += (-1) ** j * cnt
    want = 1 + (-1) ** (d - 1)
    bad = chi[verts] != want
    # link connectivity: node i * dp1 + p is vertex p of simplex i; across a
    # shared facet its vertices' nodes are joined.  The facet opposite
    # position q holds the sorted vertices at positions != q, so its a-th
    # vertex sits at position a + (a >= q) in either simplex.
    pairs = pairs if pairs is not None else _facet_pairs(srt)
    _, e1, e2 = _shared_facets(pairs, dp1)
    q1, q2 = e1 % dp1, e2 % dp1
    base1, base2 = e1 - q1, e2 - q2  # s * dp1
    del e1, e2
    edges = []
    for a in range(d):
        edges.append(np.stack([base1 + a + (a >= q1), base2 + a + (a >= q2)], axis=1))
    del base1, base2, q1, q2
    edges = np.concatenate(edges)
    ncomp, labels = graph_components(c * dp1, edges)
    del edges
    # components of the link of v = distinct labels among v's nodes; an edge joins two nodes of
    # one vertex, so every component's nodes are one vertex's, and counting components per vertex
    # counts them
    comp_vertex = np.empty(ncomp, dtype=np.int64)
    comp_vertex[labels] = srt.ravel()
    per_vertex = np.bincount(comp_vertex, minlength=n)
    bad |= per_vertex[verts] != 1
    return verts[bad]


def _top_cycle_rank(simplices: np.ndarray, pairs: tuple, d: int) -> int:
    """Dim ker(d_d) over Z/2 when every (d-1)-face has at most two d-simplices.

    A Z/2 d-cycle then takes both simplices at each interior (d-1)-face or
    neither, so it is a union of whole components of the dual graph (simplices
    joined across shared faces), and no such component may have a boundary
    face.  The kernel's dimension is the number of components without one,
    found in linear time instead of by elimination.
    """
    m = len(simplices)
    _, e1, e2 = _shared_facets(pairs, d + 1)
    ncomp, labels = graph_components(m, np.stack([e1 // (d + 1), e2 // (d + 1)], axis=1))
    del e1, e2
    _, _, cnt, order = pairs
    starts = np.cumsum(cnt) - cnt
    open_comp = np.zeros(ncomp, dtype=bool)
    open_comp[labels[order[starts[cnt == 1]] // (d + 1)]] = True
    return int(ncomp - open_comp.sum())


#: The last large complex analysed and its report (see :func:`analyse`).
_LAST: tuple[tuple, TopologyReport] | None = None
#: Complexes at least this large are remembered by :func:`analyse` (hashing
#: them costs well under a millisecond; analysing a 3-manifold of 13,000
#: tetrahedra twice cost 0.15 s).
REMEMBER_MIN = 1_000
#: Before analysing complexes at least this large, freed memory is handed back.
RELEASE_MIN = 100_000


def analyse(simplices: np.ndarray, n_samples: int, d: int) -> TopologyReport:
    """Topology report of a pure d-complex over ``n_samples`` samples.

    The report of the last complex with at least :data:`REMEMBER_MIN`
    simplices is remembered by a digest of its rows: the robust extraction
    checks its final complex and the pipeline then reports on the same one
    (seconds at 10^5-10^6 samples).  A fresh copy is returned each time.
    """
    global _LAST
    simplices = np.asarray(simplices, dtype=np.int64).reshape(-1, d + 1)
    if len(simplices) == 0:
        return TopologyReport(0, False, 0, 0, 0, n_samples, tuple([0] * (d + 1)), 0, None, 0, ["the complex is empty"])
    key = None
    if len(simplices) >= REMEMBER_MIN:
        key = (
            n_samples,
            d,
            simplices.shape,
            hashlib.blake2b(np.ascontiguousarray(simplices).data, digest_size=20).digest(),
        )
        if _LAST is not None and _LAST[0] == key:
            return replace(_LAST[1], messages=list(_LAST[1].messages))
    if len(simplices) >= RELEASE_MIN:
        release_free_memory()  # what the caller freed (an extraction's tables) before the peak here
    report = _analyse(simplices, n_samples, d)
    if key is not None:
        _LAST = (key, replace(report, messages=list(report.messages)))
    return report


def is_closed_manifold(simplices: np.ndarray, d: int) -> bool:
    """Whether a pure d-complex is a closed manifold (:attr:`TopologyReport.closed_manifold`), without Betti numbers.

    The same test as :func:`analyse` (no boundary or non-manifold facet, no
    pinched vertex) without the rank computations, which on a complex with
    non-manifold facets cost seconds at 10^5 simplices.
    """
    simplices = np.asarray(simplices, dtype=np.int64).reshape(-1, d + 1)
    if len(simplices) == 0:
        return False
    counts = _surface_counts(simplices) if d == 2 else None
    if counts is not None:
        return counts[2] == 0 and counts[3] == 0 and counts[6] == 0
    pairs = _facet_pairs(simplices)
    counts = pairs[2]
    if (counts != 2).any():
        return False
    faces = all_faces(simplices, facets=pairs[0])
    return len(singular_vertices(simplices, faces, pairs)) == 0


def _surface_counts(triangles: np.ndarray) -> tuple[int, ...] | None:
    """``_surface.surface_report`` of a triangle complex, or None without the kernel or for a degenerate row.

    Returns (vertices, edges, boundary edges, non-manifold edges, components, closed dual components (-1 with
    a non-manifold edge), pinched vertices (-1 unless a closed pseudo-surface) and orientable (-1 with a
    non-manifold edge)).
    """
    if _surface is None or len(triangles) == 0 or int(triangles.min()) < 0:
        return None
    t = np.ascontiguousarray(triangles, dtype=np.int64)
    top = int(t.max())
    if not dense_ids(top, t.size):
        return None
    return _surface.surface_report(top + 1, t)


def _surface_report(triangles: np.ndarray, n_samples: int) -> TopologyReport | None:
    """:func:`_analyse` of a triangle complex from its compiled counts; None where the general code must run.

    With an edge in three triangles or more, rank d_2 needs the elimination; that case is left to it.
    """
    counts = _surface_counts(triangles)
    if counts is None or counts[3] > 0:
        return None
    nv, ne, boundary, _nonman, comps, closed_parts, sing, orient = counts
    nf = len(triangles)
    pseudo = boundary == 0
    return _report(
        nf,
        boundary,
        0,
        sing if pseudo else 0,
        n_samples,
        nv,
        (comps, ne - (nv - comps) - (nf - closed_parts), closed_parts),
        nv - ne + nf,
        bool(orient) if orient >= 0 else None,
        comps,
    )


def _report(
    n_simplices: int,
    boundary: int,
    nonman: int,
    singular: int,
    n_samples: int,
    nverts: int,
    betti: tuple[int, ...],
    euler: int,
    orient: bool | None,
    comps: int,
) -> TopologyReport:
    """The report with its messages."""
    unused = n_samples - nverts
    msgs = []
    if boundary:
        msgs.append(f"{boundary} (d-1)-faces lie in only one d-simplex (boundary)")
    if nonman:
        msgs.append(f"{nonman} (d-1)-faces lie in more than two d-simplices (non-manifold)")
    if singular:
        msgs.append(f"{singular} vertices have a link that is not a (d-1)-sphere (pinched)")
    if unused:
        msgs.append(f"{unused} of {n_samples} samples are not vertices of the complex")
    return TopologyReport(
        n_simplices=n_simplices,
        closed_manifold=bool(boundary == 0 and nonman == 0 and singular == 0),
        boundary_faces=boundary,
        nonmanifold_faces=nonman,
        singular_vertices=int(singular),
        unused_samples=int(unused),
        betti=tuple(int(b) for b in betti),
        euler=int(euler),
        orientable=orient,
        components=int(comps),
        messages=msgs,
    )


def _analyse(simplices: np.ndarray, n_samples: int, d: int) -> TopologyReport:
    """:func:`analyse` without the memory of the last complex."""
    if d == 2:
        fast = _surface_report(simplices, n_samples)
        if fast is not None:
            return fast
    return _analyse_general(simplices, n_samples, d)


def _analyse_general(simplices: np.ndarray, n_samples: int, d: int) -> TopologyReport:
    """:func:`_analyse` for any pure d-complex (numpy and GF(2) elimination)."""
    pairs = _facet_pairs(simplices)
    faces = all_faces(simplices, facets=pairs[0])
    counts = pairs[2]
    boundary = int((counts == 1).sum())
    nonman = int((counts > 2).sum())
    pseudo = boundary == 0 and nonman == 0
    sing = singular_vertices(simplices, faces, pairs) if pseudo else np.empty(0, np.int64)
    nverts = len(faces[0])
    euler = int(sum((-1) ** j * len(f) for j, f in enumerate(faces)))
    # ranks of boundary maps r[j] = rank(d_j: C_j -> C_{j-1}), r[0] = 0
    edges = faces[1] if d >= 1 else np.empty((0, 2), np.int64)
    vid = np.searchsorted(faces[0][:, 0], edges)
    comps, _ = graph_components(nverts, vid)
    ranks = [0] * (d + 2)
    ranks[1] = nverts - comps
    top_cycles = _top_cycle_rank(simplices, pairs, d) if nonman == 0 else None
    for j in range(2, d + 1):
        if j == d and top_cycles is not None:
            ranks[j] = len(simplices) - top_cycles
        else:
            ranks[j] = boundary_rank_gf2(faces[j], faces[j - 1])
    betti = tuple(len(faces[j]) - ranks[j] - ranks[j + 1] for j in range(d + 1))
    orient = orientable(simplices, pairs) if nonman == 0 else None
    return _report(len(simplices), boundary, nonman, len(sing), n_samples, nverts, betti, euler, orient, comps)
