"""Betti numbers of the union of balls around the samples, across scales (the alpha filtration).

Why
---
The union of balls of radius r around a sample of a manifold has the
manifold's homology for r between the noise and the reach (Niyogi, Smale and
Weinberger 2008; Chazal and Lieutier 2008): where r is too small it falls
apart, where r is too large it fills in.  The alpha complex (Edelsbrunner
1995) is the nerve of the balls cut by the Voronoi cells: a subcomplex of the
Delaunay triangulation with the union's homotopy type at every r.  Counting its
Betti numbers at a ladder of scales and taking the longest run of one answer
is how persistent homology reads the number of loops a sample stands for
without a scale chosen in advance (Edelsbrunner, Letscher and Zomorodian 2002).

The curve rule (:mod:`crustview.core.robust.tour_curve`) uses it to count the
closed curves in a sample before it joins them: each closed curve is one
1-cycle of its tube.

What is computed
----------------
For points in R^2 or R^3 only: there the Betti numbers follow from component
counts alone.  b0 is the number of components of the edges; b2 in R^3 is the
number of bounded components of the complement (Alexander duality: the
tetrahedra not in the complex, joined through triangles not in it); and
b1 = b0 - chi + b2, with chi the Euler characteristic of the complex.  The
filtration value of a simplex is GUDHI's and CGAL's alpha value: the radius of
its smallest circumscribing ball if no other vertex of a Delaunay coface lies
inside that ball (it is Gabriel), otherwise the smallest value of a coface that
attaches it.
"""

from __future__ import annotations

import math
from itertools import combinations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import Delaunay

from ..util.rows import unique_rows
from . import _components

#: A cycle (a loop in the plane, a void in space) is one of the sample's own when it lives from radius r to
#: at least this many times r: an eps-sample keeps a closed curve's loop, or the region a closed surface
#: encloses, from about eps * lfs (its balls cover it) to about lfs, a ratio 1 / eps, which is 2 or more
#: where eps <= 1/2 (the resolution the features' GAP_MIN and LOOP_SUPPORTED call resolved).  Measured
#: (``benchmarks/bench_curves.py``): a noisy ellipse's loop 7.0-16.3, its noise's at most 1.51.
PERSISTENT = 2.0
#: Relative slack of the attachment test (a vertex within it of a face's smallest ball counts as inside):
#: far above the rounding of the squared distances (1e-16 relative), far below any real gap.  Four samples
#: on one circle (a grid's square) make a flat simplex whose circumcentre is anywhere on an axis; a face
#: left out of it would wall off a void no union of balls has (the bumpy sphere's grid: 27 of them).
ATTACH_TOL = 1e-9


def _circumballs(points: np.ndarray, simplices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and squared radius of the smallest ball through each simplex's vertices (in its affine hull)."""
    p = points[simplices]  # (m, j + 1, k)
    base = p[:, 0]
    a = p[:, 1:] - base[:, None, :]  # (m, j, k)
    gram = np.einsum("mik,mjk->mij", a, a)
    rhs = 0.5 * np.einsum("mik,mik->mi", a, a)
    # the centre is base + a^T x with gram x = rhs; degenerate simplices get a huge ball
    det = np.linalg.det(gram)
    ok = np.abs(det) > 1e-300
    x = np.zeros(rhs.shape)
    if ok.any():
        x[ok] = np.linalg.solve(gram[ok], rhs[ok][..., None])[..., 0]
    centre = base + np.einsum("mi,mik->mk", x, a)
    r2 = np.einsum("mk,mk->m", centre - base, centre - base)
    r2[~ok] = np.inf
    return centre, r2


def _faces(simplices: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The distinct j-faces of the simplices; per (simplex, face) pair the face id and the opposite vertices.

    Returns ``(faces, owner, face_of, opposite)``: faces sorted row-wise, and for every simplex and every one
    of its j-faces (in ``combinations`` order) the simplex index, the face index and, for faces one dimension
    down (``j`` = the simplices' dimension - 1), the simplex's vertex not in the face (else -1).
    """
    m, width = simplices.shape
    combos = list(combinations(range(width), j + 1))
    # the simplices' rows are sorted (alpha_levels' callers sort them), so every face's row comes sorted
    all_faces = np.concatenate([simplices[:, list(c)] for c in combos])
    faces, face_of = unique_rows(all_faces)  # np.unique(axis=0)'s rows and order, by integer keys
    owner = np.tile(np.arange(m), len(combos))
    if j == width - 2:  # each face leaves out one column: its vertex is the one opposite
        dropped = [next(i for i in range(width) if i not in c) for c in combos]
        opposite = np.concatenate([simplices[:, i] for i in dropped])
    else:
        opposite = np.full(len(owner), -1, np.int64)
    return faces, owner, face_of.ravel(), opposite


def dual_merges(
    born: np.ndarray, side_a: np.ndarray, side_b: np.ndarray, face_alpha: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The elder rule's merges of the dual graph read from the largest value down.

    Nodes are top cells (and the outside) with the value at which each enters (``born``); edges join the
    two sides of each face, taken in decreasing ``face_alpha``.  Returns per merge the face, the younger
    component's root (whose value is the cycle's death, the face's its birth) and the elder's root.
    """
    order = np.argsort(-face_alpha, kind="stable")
    merged = np.frombuffer(
        _components.merges(
            np.ascontiguousarray(born, dtype=np.float64),
            np.ascontiguousarray(side_a[order], dtype=np.int64),
            np.ascontiguousarray(side_b[order], dtype=np.int64),
        ),
        np.int64,
    ).reshape(-1, 3)
    return order[merged[:, 0]], merged[:, 1], merged[:, 2]


def merge_regions(n_nodes: int, young: np.ndarray, elder: np.ndarray, cut: np.ndarray) -> np.ndarray:
    """Per node, the root of ``cut`` it was merged into first (or its last root): the cycles' regions.

    A cycle's region at its birth is every cell merged into its root before then: its subtree in the
    forest of merges (each younger root under the elder), here cut at the roots in ``cut``.
    """
    parent = np.arange(n_nodes)
    parent[young] = elder
    parent[cut] = cut
    while True:
        up = parent[parent]
        if np.array_equal(up, parent):
            return parent
        parent = up


def alpha_levels(
    points: np.ndarray, top: np.ndarray, upto: float = math.inf
) -> tuple[list[np.ndarray], list[np.ndarray], dict[int, tuple[np.ndarray, np.ndarray]]]:
    """The alpha value (squared radius) of every face of a Delaunay triangulation, in any dimension.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    top : ndarray of shape (m, r + 1)
        The Delaunay r-simplices, each row sorted (its faces are then read off sorted).
    upto : float
        Values above ``upto ** 2`` are only said to be above it (``inf``): a face whose longest edge is over
        ``2 upto`` has a smallest ball, and so a value, beyond it, and its ball is not computed (the cells at
        far bounding points, a convex hull's long faces).

    Returns
    -------
    faces : list of ndarray
        ``faces[j]``: the distinct j-faces (rows sorted; ``faces[r]`` is ``top``; ``faces[0]`` unused).
    levels : list of ndarray
        ``levels[j]``: their squared alpha radii (0 for the vertices): a top simplex's circumball; a face
        whose smallest ball holds the opposite vertex of one of its cofaces (attached) enters with its
        first coface; any other face with its smallest ball (Edelsbrunner 1995; GUDHI's and CGAL's values).
    incidence : dict
        ``incidence[j] = (owner, face_of)``: per (coface, j-face) pair the (j + 1)-face and the j-face.
    """
    n, k = points.shape
    r = top.shape[1] - 1
    cut2 = upto * upto
    levels: list[np.ndarray] = [np.zeros(0)] * (r + 1)
    faces_of: list[np.ndarray] = [np.zeros((0, 1), np.int64)] * (r + 1)
    faces_of[r] = top
    co_far = _beyond(points, top, cut2)
    levels[r] = np.full(len(top), np.inf)
    if not co_far.all():
        _, levels[r][~co_far] = _circumballs(points, top[~co_far])
    cofaces = top
    co_alpha = levels[r]
    incidence: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for j in range(r - 1, 0, -1):
        faces, owner, face_of, opposite = _faces(cofaces, j)
        far = _beyond(points, faces, cut2)
        centre, r2 = np.zeros((len(faces), k)), np.full(len(faces), np.inf)
        if not far.all():
            centre[~far], r2[~far] = _circumballs(points, faces[~far])
        flat = ~np.isfinite(co_alpha) & ~co_far
        if flat.any():  # a flat coface (its vertices on one circle or line) fills with its last face
            fix = np.zeros(len(co_alpha))
            np.maximum.at(fix, owner, np.where(np.isfinite(r2), r2, 0.0)[face_of])
            co_alpha = np.where(flat, fix, co_alpha)
            levels[j + 1] = co_alpha
        # a vertex on the sphere attaches the face too (ATTACH_TOL: co-circular grids)
        inside = ((points[opposite] - centre[face_of]) ** 2).sum(axis=1) <= r2[face_of] * (1 + ATTACH_TOL)
        alpha = np.full(len(faces), np.inf)
        np.minimum.at(alpha, face_of[inside], co_alpha[owner[inside]])
        # attached by a coface beyond the cut only: beyond it too (its value is at least that coface's)
        by_far = np.zeros(len(faces), bool)
        by_far[face_of[inside & co_far[owner]]] = True
        alpha = np.where(np.isfinite(alpha) | by_far | far, alpha, r2)
        levels[j], faces_of[j] = alpha, faces
        incidence[j] = (owner, face_of)
        cofaces, co_alpha, co_far = faces, alpha, far | (by_far & ~np.isfinite(alpha))
    levels[0] = np.zeros(n)
    return faces_of, levels, incidence


def _beyond(points: np.ndarray, simplices: np.ndarray, cut2: float) -> np.ndarray:
    """Simplices whose longest edge is over twice ``sqrt(cut2)``: their smallest ball is beyond the cut."""
    if not math.isfinite(cut2):
        return np.zeros(len(simplices), bool)
    p = points[simplices]
    longest = np.zeros(len(simplices))
    width = simplices.shape[1]
    for a in range(width):
        for b in range(a + 1, width):
            np.maximum(longest, ((p[:, a] - p[:, b]) ** 2).sum(axis=1), out=longest)
    return longest > 4 * cut2


class AlphaLadder:
    """The alpha complex of a point set in R^2 or R^3, ready to give Betti numbers at any scale.

    Parameters
    ----------
    points : ndarray of shape (n, k), k in (2, 3)
        Points in general enough position for a Delaunay triangulation.
    """

    def __init__(self, points: np.ndarray) -> None:
        self.points = np.asarray(points, dtype=float)
        n, k = self.points.shape
        if k not in (2, 3):
            raise ValueError("the alpha ladder counts Betti numbers in R^2 and R^3 only")
        self.n, self.k = n, k
        tri = Delaunay(self.points)
        top = np.sort(tri.simplices.astype(np.int64), axis=1)
        self.top = top
        faces_of, levels, self._incidence = alpha_levels(self.points, top)
        self.levels, self.faces = levels, faces_of
        if k == 3:
            # which tetrahedra share each triangle (or one tetrahedron and the outside)
            owner, face_of = self._incidence[2]
            order = np.argsort(face_of, kind="stable")
            fo, ow = face_of[order], owner[order]
            first = np.r_[True, fo[1:] != fo[:-1]]
            starts = np.flatnonzero(first)
            counts = np.diff(np.r_[starts, len(fo)])
            a = ow[starts]
            b = np.where(counts == 2, ow[np.minimum(starts + 1, len(ow) - 1)], len(top))  # len(top): outside
            self._tri_tets = (fo[starts], a, b)

    def betti(self, r: float) -> tuple[int, ...]:
        """Betti numbers (b0, b1) in R^2, (b0, b1, b2) in R^3, of the union of balls of radius ``r``."""
        r2 = r * r
        n = self.n
        edges = self.faces[1][self.levels[1] <= r2]
        graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
        b0 = connected_components(graph, directed=False)[0]
        counts = [n] + [int((lv <= r2).sum()) for lv in self.levels[1:]]
        chi = sum((-1) ** j * c for j, c in enumerate(counts))
        if self.k == 2:
            return (b0, b0 - chi)
        tri_id, a, b = self._tri_tets
        out = self.levels[2][tri_id] > r2  # triangles not in the complex join their two sides
        m = len(self.top)
        keep = out & (self.levels[3][a] > r2) & ((b == m) | (self.levels[3][np.minimum(b, m - 1)] > r2))
        links = coo_matrix((np.ones(int(keep.sum())), (a[keep], b[keep])), shape=(m + 1, m + 1))
        _, lab = connected_components(links, directed=False)
        absent = np.r_[self.levels[3] > r2, True]
        b2 = len(np.unique(lab[absent])) - 1
        return (b0, b0 - chi + b2, b2)

    def components(self, r: float) -> np.ndarray:
        """Component label of every point in the union of balls of radius ``r``."""
        edges = self.faces[1][self.levels[1] <= r * r]
        graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(self.n, self.n))
        return connected_components(graph, directed=False)[1]

    def loops(self) -> np.ndarray:
        """The persistence pairs of the 1-cycles, in the plane: rows (birth radius, death radius, u, v).

        (u, v) is the edge whose arrival makes the cycle (the samples of its region:
        :meth:`loop_samples`).  By duality in the plane a cycle is a bounded region of the complement, so
        the pairs are the 0-dimensional persistence of the dual graph (triangles, joined across edges,
        and the outside) with the filtration reversed: taking simplices out from the largest value down,
        a triangle starts a region, an edge merges the two regions on its sides, and the younger region
        ends (the elder rule).  Cycles of zero length are left out.
        """
        if self.k != 2:
            raise ValueError("loops() reads the plane's 1-cycles by duality: points in R^2 only")
        tris, edges = self.faces[2], self.faces[1]
        owner, face_of = self._incidence[1]
        m = len(tris)
        # the two sides of each edge: its triangles, or one triangle and the outside (node m)
        order = np.argsort(face_of, kind="stable")
        fo, ow = face_of[order], owner[order]
        starts = np.flatnonzero(np.r_[True, fo[1:] != fo[:-1]])
        counts = np.diff(np.r_[starts, len(fo)])
        side_a = np.full(len(edges), m, np.int64)
        side_b = np.full(len(edges), m, np.int64)
        side_a[fo[starts]] = ow[starts]
        two = counts == 2
        side_b[fo[starts[two]]] = ow[starts[two] + 1]
        born = np.r_[self.levels[2], np.inf]  # a region's value: its first triangle in reverse order
        e_alpha = self.levels[1]
        edge, young, elder = dual_merges(born, side_a, side_b, e_alpha)
        live = born[young] > e_alpha[edge]  # a region born and gone at one value is no cycle
        self._forest = (m, young, elder, young[live])
        return np.c_[np.sqrt(e_alpha[edge[live]]), np.sqrt(born[young[live]]), edges[edge[live]]].reshape(-1, 4)

    def loop_samples(self, chosen: np.ndarray) -> list[np.ndarray]:
        """The samples of the region of each chosen cycle of :meth:`loops` (row indices) at its birth.

        A region at its birth is every triangle merged into it before then, less the regions of the other
        chosen cycles inside it (two nested circles: the inner disc is not part of the ring's region).
        """
        m, young, elder, cycles = self._forest
        roots = cycles[np.asarray(chosen, np.int64)]
        region = merge_regions(m + 1, young, elder, roots)[:m]
        return [np.unique(self.faces[2][region == r].ravel()) for r in roots.tolist()]
