"""Algorithm 2: the candidate complex T_S and its two tests.

Every Delaunay d-face ``sigma`` whose vertices are all samples is scored by
two tests; both scores are kept, so the threshold can be changed (and both
tests compared) without recomputing anything.

Dual cells
----------
The Voronoi cell dual to ``sigma`` is the convex polytope spanned by the
circumcentres of the Delaunay simplices that contain ``sigma``.  It lies in
the (k-d)-plane ``Pi`` orthogonal to ``aff(sigma)`` through its circumcentre.
It is bounded because far bounding points were added (see ``delaunay``).

Literal test (the paper, line 3 of Algorithm 2)
-----------------------------------------------
"the angle between the (k-d)-cell and AN_s is less than pi/8 for some sample
point s of an adjacent cell".  The cell is a (k-d)-polytope; its orientation
is that of ``Pi``, i.e. the orthogonal complement of ``aff(sigma)``.  We
measure the angle between two (k-d)-planes as their largest principal angle,
which equals the largest principal angle between ``aff(sigma)`` and AT_s:
``sin(angle) = ||N_s^T U_sigma||_2``.  The cells adjacent to the dual cell are
the Voronoi cells of ``sigma``'s vertices, so ``literal = min_s angle``.  The
test looks at *orientation only*: a face far from the manifold that happens
to be parallel to it passes.

Cocone tests (Amenta-Choi-Dey-Leekha, generalised)
--------------------------------------------------
The cocone of ``s`` is ``{y : angle(y - s, AT_s) <= theta}``: the points seen
from ``s`` within ``theta`` of the tangent plane.  Unlike the literal test it
looks at *where* the dual cell is, not only at its orientation.  With
``c(sigma, s) = min_{y in cell} angle(y - s, AT_s)``
(``sin^2 angle(x, AT_s) = |N_s^T x|^2 / |x|^2``):

* ``cocone = min_s c(sigma, s)``: the cell meets the cocone of *some* vertex,
  the paper's quantifier ("for some sample point for an adjacent cell").
  This is the default: on real scans (spot.xyz) requiring every vertex
  leaves holes in T_S, and Algorithm 3's pruning then eats the whole surface.
* ``cocone-all = max_s c(sigma, s)``: every vertex, as in Cocone.

The minimum over the cell is computed exactly below :data:`SCORE_LIMIT`
(45 deg), per (face, vertex s):

1. *Certificate of rejection.*  With ``x_i`` the cell vertices minus ``s``
   and ``nu`` a unit normal direction (the mean of their unit normal
   components, improved by a few Badoiu-Clarkson steps), if every
   ``nu . N_s^T x_i / |x_i| >= sin(limit)`` then every point of the convex
   cell satisfies the same inequality, so its angle is >= ``limit``; the
   lower bound is recorded and the face is rejected for every threshold up to
   ``limit`` (most faces of a dense sample end here).
2. *Interior.*  The affine tangent plane ``s + AT_s`` (dimension d) and the
   cell's plane ``Pi`` (dimension k-d) meet in one point ``y*``; if ``y*`` is
   in the cell (no Delaunay vertex is closer to ``y*`` than sigma's vertices,
   a k-d tree query: a Voronoi cell *is* that set) the minimum is 0.
3. *Boundary.*  Otherwise the minimum lies on the cell's boundary.  The
   ratio ``|N^T x|^2 / |x|^2`` is a Rayleigh quotient, so its minimum over the
   cone spanned from ``s`` by a few points is the smallest eigenvalue of a
   small symmetric matrix, attained inside their convex hull iff the
   eigenvector's barycentric coefficients share one sign.  We evaluate every
   cell vertex and every simplex spanned by ``j`` cell vertices,
   ``2 <= j <= k - d`` (these cover the cell's boundary; when the cell itself
   is a simplex -- always in codimension 1 -- the whole cell).  In
   codimension 2 and 3, when the Delaunay simplices are given, the cell's
   true edges (and in codimension 3 polygons) are used instead: edges join
   simplices sharing a facet, polygons are dual to the cofaces
   ``sigma + w``, with the Voronoi criterion for "inside a polygon".  In
   codimension >= 4 cells with more than :data:`MAX_SUBSET_VERTICES`
   vertices use vertex pairs only, which can only *over*-estimate the angle
   (reject, never admit wrongly).

Exact in codimension 1, 2 and 3.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

#: Cells with more vertices skip the (k-d)-subset enumeration in codim >= 3.
MAX_SUBSET_VERTICES = 12
#: Cocone scores below this are exact; larger ones are only known to be >= it.
SCORE_LIMIT = np.pi / 4


def enumerate_faces(simplices: np.ndarray, n_samples: int, d: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All d-faces of the Delaunay simplices whose vertices are samples.

    Returns
    -------
    faces : ndarray of shape (f, d + 1)
        Sorted rows, lexicographically sorted.
    cell_ptr : ndarray of shape (f + 1,)
    cell_simplices : ndarray
        ``cell_simplices[cell_ptr[i]:cell_ptr[i+1]]`` are the Delaunay
        simplices containing face ``i`` (vertices of its dual cell).
    """
    srt = np.sort(simplices, axis=1)
    combos = np.array(list(itertools.combinations(range(srt.shape[1]), d + 1)))
    faces = srt[:, combos].reshape(-1, d + 1)
    owner = np.repeat(np.arange(len(srt)), len(combos))
    keep = faces[:, -1] < n_samples  # rows sorted: the largest index decides
    faces, owner = faces[keep], owner[keep]
    if len(faces) == 0:
        return np.empty((0, d + 1), np.int64), np.zeros(1, np.int64), np.empty(0, np.int64)
    if float(n_samples) ** (d + 1) < 2**62:
        key = np.zeros(len(faces), dtype=np.int64)
        for c in range(d + 1):
            key = key * n_samples + faces[:, c]
        order = np.argsort(key, kind="stable")
        sk = key[order]
        starts = np.flatnonzero(np.concatenate([[True], sk[1:] != sk[:-1]]))
    else:
        order = np.lexsort(faces.T[::-1])
        sf = faces[order]
        starts = np.flatnonzero(np.concatenate([[True], (sf[1:] != sf[:-1]).any(axis=1)]))
    uniq = faces[order[starts]]
    ptr = np.concatenate([starts, [len(order)]])
    return uniq.astype(np.int64), ptr, owner[order]


def _orthonormal(vectors: np.ndarray) -> np.ndarray:
    """Orthonormal basis (columns) of the span of the rows, batched: (..., j, r) -> (..., r, j).

    Gram-Schmidt in closed form for one or two rows (the common cases),
    QR otherwise.
    """
    j = vectors.shape[-2]
    if j > 2:
        return np.linalg.qr(np.swapaxes(vectors, -1, -2))[0]
    e1 = vectors[..., 0, :]
    e1 = e1 / np.maximum(np.sqrt(np.einsum("...r,...r->...", e1, e1)), 1e-300)[..., None]
    if j == 1:
        return e1[..., :, None]
    w = vectors[..., 1, :]
    w = w - np.einsum("...r,...r->...", w, e1)[..., None] * e1
    e2 = w / np.maximum(np.sqrt(np.einsum("...r,...r->...", w, w)), 1e-300)[..., None]
    return np.stack([e1, e2], axis=-1)


def literal_angles(work: np.ndarray, normals: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Paper's test: min over vertices of the angle between aff(sigma) and AT_s.

    Parameters
    ----------
    work : ndarray of shape (n, r)
    normals : ndarray of shape (n, r, m)
    faces : ndarray of shape (f, d + 1)

    Returns
    -------
    ndarray of shape (f,), radians in [0, pi/2].
    """
    p = work[faces]
    u = _orthonormal(p[:, 1:] - p[:, :1])  # (f, r, d)
    best = np.full(len(faces), np.pi / 2)
    for a in range(faces.shape[1]):
        nt_u = np.einsum("frm,frd->fmd", normals[faces[:, a]], u)
        s = np.sqrt(_largest_eig(nt_u))
        best = np.minimum(best, np.arcsin(np.clip(s, 0.0, 1.0)))
    return best


def _largest_eig(mat: np.ndarray) -> np.ndarray:
    """Largest eigenvalue of ``M^T M`` (= squared spectral norm) for a batch (..., a, b)."""
    if mat.shape[-1] > mat.shape[-2]:
        mat = np.swapaxes(mat, -1, -2)
    g = np.swapaxes(mat, -1, -2) @ mat
    if g.shape[-1] == 1:
        return g[..., 0, 0]
    if g.shape[-1] == 2:
        a, b, c = g[..., 0, 0], g[..., 0, 1], g[..., 1, 1]
        return 0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + b**2)
    return np.linalg.eigvalsh(g)[..., -1]


def _cone_min_pair(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closed form of :func:`_cone_min` for two generators, x: (..., 2, r)."""
    xn = x @ nrm
    return _segment_min(x[..., 0, :], x[..., 1, :], xn[..., 0, :], xn[..., 1, :])


def _segment_min(
    x1: np.ndarray, x2: np.ndarray, n1: np.ndarray, n2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum of sin^2 angle(., AT) over the cone of two generators.

    ``x1, x2`` (..., r) are the generators, ``n1, n2`` (..., m) their normal
    components ``N^T x``; everything is done with 2x2 algebra.
    """
    l1 = np.sqrt(np.einsum("...r,...r->...", x1, x1))
    inv1 = 1.0 / np.maximum(l1, 1e-300)
    p = np.einsum("...r,...r->...", x2, x1) * inv1
    x2sq = np.einsum("...r,...r->...", x2, x2)
    w = x2 - (p * inv1)[..., None] * x1  # explicit: |x2|^2 - p^2 cancels for near-parallel generators
    l2 = np.sqrt(np.einsum("...r,...r->...", w, w))
    ok = (l1 > 1e-300) & (l2 > 1e-10 * np.maximum(np.sqrt(x2sq), 1e-300))
    inv2 = 1.0 / np.where(ok, l2, 1.0)
    b1 = n1 * inv1[..., None]
    b2 = (n2 - p[..., None] * b1) * inv2[..., None]
    a = np.einsum("...m,...m->...", b1, b1)
    c = np.einsum("...m,...m->...", b2, b2)
    b = np.einsum("...m,...m->...", b1, b2)
    rad = np.sqrt((0.5 * (a - c)) ** 2 + b**2)
    lam = 0.5 * (a + c) - rad
    # eigenvector of [[a, b], [b, c]] for lam: (b, lam - a) or (lam - c, b)
    first = np.abs(a - lam) >= np.abs(c - lam)
    z1 = np.where(first, b, lam - c)
    z2 = np.where(first, lam - a, b)
    degenerate = (np.abs(z1) + np.abs(z2)) <= 1e-300
    z1 = np.where(degenerate, 1.0, z1)  # isotropic: any direction is a minimiser
    c2 = z2 * inv2
    c1 = (z1 - c2 * p) * inv1
    tol = 1e-9 * np.maximum(np.abs(c1), np.abs(c2))
    inside = ok & (((c1 >= -tol) & (c2 >= -tol)) | ((c1 <= tol) & (c2 <= tol)))
    return np.clip(lam, 0.0, 1.0), inside


def _cone_min(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Minimum of sin^2 angle(x, AT) over the convex cone of the rows of x.

    Parameters
    ----------
    x : ndarray of shape (..., j, r)
        Generators (vectors from s).
    nrm : ndarray of shape (..., r, m)
        Normal basis, broadcast against ``x``.

    Returns
    -------
    value : ndarray of shape (...)
        Minimal sin^2 over the linear span.
    inside : ndarray of bool, shape (...)
        Whether the minimiser lies in the cone (all coefficients one sign).
    """
    if x.shape[-2] == 2:
        return _cone_min_pair(x, nrm)
    value, lam, ok = _span_min(x, nrm)
    tol = 1e-9 * np.abs(lam).max(axis=-1, keepdims=True)
    inside = ok & ((lam >= -tol).all(axis=-1) | (lam <= tol).all(axis=-1))
    return value, inside


def _span_min(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum of sin^2 angle(., AT) over the linear span of the rows of x.

    Returns the value, the minimiser's coefficients on the rows (..., j),
    and whether the rows were independent.
    """
    q, rr = np.linalg.qr(np.swapaxes(x, -1, -2))  # (..., r, j), (..., j, j)
    diag = np.abs(np.diagonal(rr, axis1=-2, axis2=-1))
    scale = np.linalg.norm(x, axis=-1).max(axis=-1)
    ok = diag.min(axis=-1) > 1e-10 * np.maximum(scale, 1e-300)
    b = np.swapaxes(nrm, -1, -2) @ q  # (..., m, j)
    w, v = np.linalg.eigh(np.swapaxes(b, -1, -2) @ b)
    safe = np.where(ok[..., None, None], rr, np.eye(rr.shape[-1]))
    lam = np.linalg.solve(safe, v[..., 0][..., None])[..., 0]
    return np.clip(w[..., 0], 0.0, 1.0), lam, ok


def _span_min3(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_span_min` for three generators in closed form, x: (P, 3, r).

    Gram-Schmidt gives ``x = Q R``; the smallest eigenpair of the 3x3 matrix
    ``B^T B`` (``B = N^T Q``) comes from the trigonometric formula and a cross
    product of two rows of ``B^T B - lambda I``; back substitution gives the
    coefficients.  No LAPACK call per polygon.
    """
    xn = x @ nrm  # (P, 3, m): N^T x_i

    def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.einsum("...i,...i->...", a, b)

    a1, a2, a3 = x[:, 0], x[:, 1], x[:, 2]
    r11 = np.sqrt(dot(a1, a1))
    q1 = a1 / np.maximum(r11, 1e-300)[:, None]
    r12, r13 = dot(q1, a2), dot(q1, a3)
    w2 = a2 - r12[:, None] * q1
    r22 = np.sqrt(dot(w2, w2))
    q2 = w2 / np.maximum(r22, 1e-300)[:, None]
    r23 = dot(q2, a3)
    w3 = a3 - r13[:, None] * q1 - r23[:, None] * q2
    r33 = np.sqrt(dot(w3, w3))
    scale = np.sqrt(np.maximum(np.maximum(r11**2, dot(a2, a2)), dot(a3, a3)))
    ok = np.minimum(np.minimum(r11, r22), r33) > 1e-10 * np.maximum(scale, 1e-300)
    b1 = xn[:, 0] / np.maximum(r11, 1e-300)[:, None]
    b2 = (xn[:, 1] - r12[:, None] * b1) / np.maximum(r22, 1e-300)[:, None]
    b3 = (xn[:, 2] - r13[:, None] * b1 - r23[:, None] * b2) / np.maximum(r33, 1e-300)[:, None]
    m00, m11, m22 = dot(b1, b1), dot(b2, b2), dot(b3, b3)
    m01, m02, m12 = dot(b1, b2), dot(b1, b3), dot(b2, b3)
    q = (m00 + m11 + m22) / 3
    p1 = m01**2 + m02**2 + m12**2
    p = np.sqrt(((m00 - q) ** 2 + (m11 - q) ** 2 + (m22 - q) ** 2 + 2 * p1) / 6)
    ps = np.maximum(p, 1e-300)
    c00, c11, c22 = (m00 - q) / ps, (m11 - q) / ps, (m22 - q) / ps
    c01, c02, c12 = m01 / ps, m02 / ps, m12 / ps
    det = c00 * (c11 * c22 - c12**2) - c01 * (c01 * c22 - c12 * c02) + c02 * (c01 * c12 - c11 * c02)
    phi = np.arccos(np.clip(det / 2, -1.0, 1.0)) / 3
    lam_min = np.where(p > 1e-300, q + 2 * p * np.cos(phi + 2 * np.pi / 3), q)
    # eigenvector: the longest cross product of two rows of M - lam I
    rows = np.stack(
        [np.stack([m00 - lam_min, m01, m02], 1), np.stack([m01, m11 - lam_min, m12], 1),
         np.stack([m02, m12, m22 - lam_min], 1)], axis=1)
    cands = np.stack([np.cross(rows[:, 0], rows[:, 1]), np.cross(rows[:, 0], rows[:, 2]),
                      np.cross(rows[:, 1], rows[:, 2])], axis=1)
    size = dot(cands, cands)
    v = cands[np.arange(len(x)), size.argmax(axis=1)]
    flat = size.max(axis=1) <= 1e-300  # repeated smallest eigenvalue: any vector in its space
    if flat.any():
        v[flat] = _null_vector(rows[flat])
    v /= np.maximum(np.sqrt(dot(v, v)), 1e-300)[:, None]
    c3 = v[:, 2] / np.where(ok, r33, 1.0)
    c2 = (v[:, 1] - r23 * c3) / np.where(ok, r22, 1.0)
    c1 = (v[:, 0] - r12 * c2 - r13 * c3) / np.where(ok, r11, 1.0)
    value, coef = np.clip(lam_min, 0.0, 1.0), np.stack([c1, c2, c3], axis=1)
    # ill-conditioned cases go to LAPACK: nearly dependent generators (classical
    # Gram-Schmidt loses orthogonality) and a repeated smallest eigenvalue (the
    # cross products vanish and the eigenvector is noise)
    frob2 = (rows**2).sum(axis=(1, 2))
    fragile = ok & ((np.minimum(r22, r33) < 1e-4 * scale) | (size.max(axis=1) <= 1e-16 * frob2**2))
    if fragile.any():
        value[fragile], coef[fragile], ok[fragile] = _span_min(x[fragile], nrm[fragile])
    return value, coef, ok


def _null_vector(rows: np.ndarray) -> np.ndarray:
    """A unit vector orthogonal to the (rank <= 1) rows of each 3x3 block."""
    big = rows[np.arange(len(rows)), np.einsum("pij,pij->pi", rows, rows).argmax(axis=1)]
    trial = np.where((np.abs(big[:, :1]) < 0.9), np.array([[1.0, 0, 0]]), np.array([[0, 1.0, 0]]))
    v = np.cross(big, trial)
    tiny = np.einsum("pi,pi->p", v, v) <= 1e-300
    v[tiny] = [1.0, 0.0, 0.0]
    return v


def _cell_structure(face: np.ndarray, simp_rows: np.ndarray, n_all: int, m: int) -> tuple[np.ndarray, tuple]:
    """Edges (and, in codimension 3, polygons) of 2- or 3-dimensional dual cells.

    Edges join two cell simplices sharing a facet (both contain sigma);
    polygons are dual to the cofaces ``sigma + w``: their vertices are the
    cell simplices containing ``w`` (three of them span the polygon's plane).

    Parameters
    ----------
    face : ndarray of shape (F, d + 1)
    simp_rows : ndarray of shape (F, nv, r + 1)
        Vertex rows of each cell's simplices.

    Returns
    -------
    edges : ndarray of shape (E, 3)
        ``(face, i, j)``: cell vertices i and j are joined by an edge.
    polygons : (ndarray of shape (P, 6), ndarray)
        Rows ``(face, i, j, l, start, size)``: three vertices spanning one
        polygon, and the slice ``members[start:start + size]`` of the member
        array listing all its vertices (empty unless m = 3).
    """
    f_count, nv, _ = simp_rows.shape
    in_face = (simp_rows[..., None] == face[:, None, None, :]).any(axis=3)
    others = np.sort(simp_rows[~in_face].reshape(f_count, nv, m), axis=2)
    fidx = np.broadcast_to(np.arange(f_count, dtype=np.int64)[:, None], (f_count, nv))
    vidx = np.broadcast_to(np.arange(nv)[None, :], (f_count, nv))
    base = np.int64(n_all)
    keys = []
    for q in range(m):
        rest = np.delete(others, q, axis=2)
        key_q = fidx.copy()
        for c in range(m - 1):
            key_q = key_q * base + rest[..., c]
        keys.append(key_q.ravel())
    key = np.concatenate(keys)
    fe, ve = np.tile(fidx.ravel(), m), np.tile(vidx.ravel(), m)
    order = np.argsort(key, kind="stable")
    key, fe, ve = key[order], fe[order], ve[order]
    pair = np.flatnonzero(key[1:] == key[:-1])
    edges = np.stack([fe[pair], ve[pair], ve[pair + 1]], axis=1)
    if m != 3:
        return edges, (np.empty((0, 6), np.int64), np.empty(0, np.int64))
    pkey = (fidx[..., None] * base + others).ravel()
    pf, pv = np.repeat(fidx.ravel(), m), np.repeat(vidx.ravel(), m)
    order = np.argsort(pkey, kind="stable")
    pkey, pf, pv = pkey[order], pf[order], pv[order]
    start = np.flatnonzero(np.concatenate([[True], pkey[1:] != pkey[:-1]]))
    size = np.diff(np.concatenate([start, [len(pkey)]]))
    polygons = np.stack([pf[start], pv[start], pv[start + 1], pv[start + 2], start, size], axis=1)
    # member list (pv) is kept so bounds can use every vertex of a polygon
    return edges, (polygons[size >= 3], pv)


class _CellFaces:
    """Edges and polygons of one bucket's cells, built for the faces that need them.

    Most faces are settled before the boundary is needed; the structure is
    built for just the requested batch, or once for the whole bucket when a
    batch covers a third of it or more (later batches then reuse it).
    """

    def __init__(self, face: np.ndarray, simp_rows: np.ndarray, n_all: int, m: int) -> None:
        self.face, self.simp_rows, self.n_all, self.m = face, simp_rows, n_all, m
        self.whole: tuple | None = None

    def for_batch(self, idx: np.ndarray) -> tuple[np.ndarray, tuple]:
        """Structure with face column renumbered to positions in ``idx`` (sorted)."""
        if self.whole is None and 3 * len(idx) < len(self.face):
            return _cell_structure(self.face[idx], self.simp_rows[idx], self.n_all, self.m)
        if self.whole is None:
            self.whole = _cell_structure(self.face, self.simp_rows, self.n_all, self.m)
        edges, (polygons, members) = self.whole
        pos = np.full(len(self.face), -1)
        pos[idx] = np.arange(len(idx))
        e = edges[pos[edges[:, 0]] >= 0]
        pg = polygons[pos[polygons[:, 0]] >= 0]
        return np.c_[pos[e[:, 0]], e[:, 1:]], (np.c_[pos[pg[:, 0]], pg[:, 1:]], members)


def _sorted_group_min(out: np.ndarray, group: np.ndarray, values: np.ndarray) -> None:
    """``out[g] = min(out[g], values[group == g])`` for a non-decreasing ``group``."""
    if len(group) == 0:
        return
    start = np.flatnonzero(np.concatenate([[True], group[1:] != group[:-1]]))
    g = group[start]
    out[g] = np.minimum(out[g], np.minimum.reduceat(values, start))


def _cell_boundary_min(
    x: np.ndarray,
    nrm: np.ndarray,
    s: np.ndarray,
    edges: np.ndarray,
    polygons: np.ndarray,
    cap: np.ndarray,
    tree: cKDTree,
) -> np.ndarray:
    """Exact minimum of sin^2 angle over the edges and polygons of dual cells.

    Each edge is a segment (closed form).  On each polygon the minimiser
    over its plane is accepted when the Voronoi criterion puts it inside (no
    Delaunay vertex closer to it than s).  Edges and polygons whose vertices
    all lean to one normal side by more than ``sqrt(cap)`` are skipped: they
    cannot go below ``cap``.

    Parameters
    ----------
    x : ndarray of shape (F, nv, r)
        Cell vertices minus s.
    nrm : ndarray of shape (F, r, m)
    s : ndarray of shape (F, r)
    edges, polygons
        From :func:`_cell_structure`, with face indices into this batch.
    cap : ndarray of shape (F,)
        Values at or above it are of no interest.

    Returns
    -------
    ndarray of shape (F,), inf where nothing below ``cap`` was found.
    """
    out = np.full(len(x), np.inf)
    xn = x @ nrm
    unit = xn / np.maximum(np.linalg.norm(x, axis=2), 1e-300)[..., None]
    nu = np.einsum("fvm->fm", unit)
    nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
    dots = _dots(unit, nu)

    def wanted(f: np.ndarray, cols: list[np.ndarray]) -> np.ndarray:
        lb = np.min([dots[f, c] for c in cols], axis=0)
        return (lb <= 0) | (lb**2 < cap[f])

    if len(edges):
        e = edges[wanted(edges[:, 0], [edges[:, 1], edges[:, 2]])]
        val, ins = _segment_min(x[e[:, 0], e[:, 1]], x[e[:, 0], e[:, 2]], xn[e[:, 0], e[:, 1]], xn[e[:, 0], e[:, 2]])
        _sorted_group_min(out, e[:, 0], np.where(ins, val, np.inf))
    polygons, members = polygons
    if len(polygons):
        # bound over every vertex of the polygon (member slices)
        sizes, starts = polygons[:, 5], polygons[:, 4]
        offs = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        idx = np.arange(sizes.sum()) + np.repeat(starts - offs, sizes)
        pf_all = np.repeat(polygons[:, 0], sizes)
        lb = np.minimum.reduceat(dots[pf_all, members[idx]], offs)
        want = (lb <= 0) | (lb**2 < cap[polygons[:, 0]])
        if not want.any():
            return out
        p = polygons[want]
        gf = p[:, 0]
        gens = np.stack([x[gf, p[:, 1 + i]] for i in range(3)], axis=1)  # (P, 3, r)
        val, lam, ok = _span_min3(gens, nrm[gf])
        tot = lam.sum(axis=1)
        # only a value below the cap and below the edges' minimum matters
        ok &= (np.abs(tot) > 1e-12 * np.abs(lam).max(axis=1)) & (val < np.minimum(cap, out)[gf])
        xy = np.einsum("pj,pjr->pr", lam / np.where(ok, tot, 1.0)[:, None], gens)
        # a point outside the bounding box of the polygon's vertices is outside it
        mem = np.repeat(want, sizes)
        pts = x[pf_all[mem], members[idx[mem]]]
        o = np.concatenate([[0], np.cumsum(sizes[want])[:-1]])
        lo, hi = np.minimum.reduceat(pts, o, axis=0), np.maximum.reduceat(pts, o, axis=0)
        slack = 1e-9 * (np.maximum(-lo, hi).max(axis=1) + np.abs(xy).max(axis=1))[:, None]
        ask = np.flatnonzero(ok & ((xy >= lo - slack) & (xy <= hi + slack)).all(axis=1))
        inside = np.zeros(len(p), dtype=bool)
        if len(ask):
            radius = np.linalg.norm(xy[ask], axis=1)
            dist, _ = tree.query(s[gf[ask]] + xy[ask])
            inside[ask] = dist >= radius * (1 - 1e-9) - 1e-12
            # report the value actually reached at the accepted point (equal to
            # the eigenvalue up to rounding; never below what the polygon has)
            nxy = np.einsum("pr,prm->pm", xy[ask], nrm[gf[ask]])
            val[ask] = (nxy**2).sum(axis=1) / np.maximum(radius**2, 1e-300)
        _sorted_group_min(out, gf, np.where(inside, val, np.inf))
    return out


def cocone_angles(
    work: np.ndarray,
    normals: np.ndarray,
    centres: np.ndarray,
    faces: np.ndarray,
    cell_ptr: np.ndarray,
    cell_simplices: np.ndarray,
    *,
    limit: float = SCORE_LIMIT,
    simplices: np.ndarray | None = None,
    progress: Callable[[float], None] | None = None,
) -> np.ndarray:
    """Cocone angle of every (face, vertex) pair (see module docstring).

    Parameters
    ----------
    work : ndarray of shape (n_all, r)
        All Delaunay vertices (samples first, then bounding points).
    normals : ndarray of shape (n, r, m)
    centres : ndarray of shape (t, r)
        Voronoi vertices.
    faces, cell_ptr, cell_simplices
        From :func:`enumerate_faces`.
    limit : float
        Angles below ``limit`` are exact; an angle >= ``limit`` is only known
        to be >= ``limit`` (a bound, not the exact minimum): the pair fails
        every threshold up to ``limit``.
    simplices : ndarray of shape (t, r + 1), optional
        The Delaunay simplices; in codimension 2 and 3 they give the cells'
        true edges and polygons, so the boundary minimum needs no subset
        enumeration (same exact value, much faster on large cells).

    Returns
    -------
    ndarray of shape (f, d + 1), radians in [0, pi/2]
        ``[i, a]``: smallest angle between ``y - s`` and AT_s over the dual
        cell of face ``i``, with ``s`` its ``a``-th vertex.  The "cocone"
        test takes the minimum over ``a`` (some vertex, the paper's
        quantifier), "cocone-all" the maximum (every vertex, as Cocone).
    """
    f, dp1 = faces.shape
    m = normals.shape[2]
    nv_all = np.diff(cell_ptr)
    out = np.zeros((f, dp1))
    tree = cKDTree(work)
    tangents = np.linalg.qr(normals, mode="complete")[0][:, :, m:]  # (n, r, d)
    sin_lim = np.sin(limit)
    done = 0
    for nv in np.unique(nv_all):
        sel = np.flatnonzero(nv_all == nv)
        cell_ids = cell_simplices[cell_ptr[sel][:, None] + np.arange(nv)]
        cells = centres[cell_ids]  # (F, nv, r)
        simp_rows = simplices[cell_ids] if simplices is not None and m in (2, 3) else None
        # the cells' own edges/polygons replace subset enumeration where known
        use_cells = simp_rows is not None and nv > m + 1
        subsets = [] if use_cells else _boundary_subsets(int(nv), m)
        fc = faces[sel]
        cell_faces = _CellFaces(fc, simp_rows, len(work), m) if use_cells else None
        for a in range(dp1):
            s = work[fc[:, a]]
            nrm = normals[fc[:, a]]
            x = cells - s[:, None, :]
            xn = x @ nrm
            xsq = np.maximum(np.einsum("fvr,fvr->fv", x, x), 1e-300)
            xlen = np.sqrt(xsq)
            best = _over_cell(np.minimum, np.einsum("fvm,fvm->fv", xn, xn) / xsq)
            # (1) cheap certificate: every cell point leans to one normal side
            unit = xn / xlen[..., None]
            lean = _lean(unit, iterations=0)
            if m >= 3:  # exact minima are costly here: tighten the bound first
                weak = np.flatnonzero(lean < sin_lim)
                lean[weak] = np.maximum(lean[weak], _lean(unit[weak]))
            certified = lean >= sin_lim
            todo = np.flatnonzero(~certified)
            best = np.where(certified, lean**2, best)
            if len(todo):
                best[todo] = _exact_min(
                    x[todo], nrm[todo], tangents[fc[todo, a]], work[fc[todo]], s[todo],
                    best[todo], subsets, m, tree, sin_lim**2, cell_faces, todo,
                )
            out[sel, a] = np.arcsin(np.sqrt(np.clip(best, 0.0, 1.0)))
        done += len(sel)
        if progress is not None:
            progress(done / max(f, 1))
    return out


def _lean(unit: np.ndarray, iterations: int = 12) -> np.ndarray:
    """Lower bound of ``max_nu min_i nu . unit_i`` over unit ``nu`` (batched (F, v, m)).

    Starts from the mean direction and moves ``nu`` towards the worst vector
    with shrinking steps (Badoiu-Clarkson); any ``nu`` gives a valid bound,
    the iterations only tighten it.
    """
    nu = np.einsum("fvm->fm", unit)
    nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
    dots = _dots(unit, nu)
    best = _over_cell(np.minimum, dots)
    rows = np.arange(len(unit))
    for it in range(iterations):
        worst = unit[rows, dots.argmin(axis=1)]
        nu = nu + (worst - nu) / (it + 2)
        nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
        dots = _dots(unit, nu)
        best = np.maximum(best, _over_cell(np.minimum, dots))
    return best


def _over_cell(op: np.ufunc, a: np.ndarray) -> np.ndarray:
    """``op`` (np.minimum or np.maximum) reduced over axis 1, the few cell
    vertices: a loop of whole-array operations is several times faster than
    numpy's reduction over a short middle axis."""
    if a.shape[1] > 8:  # large cells: numpy's own reduction wins again
        return op.reduce(a, axis=1)
    out = a[:, 0].copy()
    for i in range(1, a.shape[1]):
        op(out, a[:, i], out=out)
    return out


def _dots(unit: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """``unit[f, v] . nu[f]`` for (F, v, m) and (F, m); a loop over the small m
    axis beats matmul/einsum on these shapes."""
    out = unit[..., 0] * nu[:, None, 0]
    for j in range(1, unit.shape[2]):
        out += unit[..., j] * nu[:, None, j]
    return out


def _boundary_subsets(nv: int, m: int) -> list[np.ndarray]:
    """Vertex subsets whose simplices cover the cell boundary (or the cell, if a simplex)."""
    if nv <= m + 1:  # the cell is a simplex: test it whole
        return [np.arange(nv)[None, :]] if nv >= 2 else []
    out = []
    for j in range(2, m + 1):
        if j > 2 and nv > MAX_SUBSET_VERTICES:
            break
        out.append(np.array(list(itertools.combinations(range(nv), j))))
    return out


def _exact_min(
    x: np.ndarray,
    nrm: np.ndarray,
    tan: np.ndarray,
    fpts: np.ndarray,
    s: np.ndarray,
    best: np.ndarray,
    subsets: list[np.ndarray],
    m: int,
    tree: cKDTree,
    sin_lim2: float = np.sin(SCORE_LIMIT) ** 2,
    cell_faces: _CellFaces | None = None,
    batch: np.ndarray | None = None,
) -> np.ndarray:
    """Minimum of sin^2 angle(y - s, AT_s) over the dual cell for a batch of faces.

    ``x``: cell vertices minus s (F, nv, r); ``best``: the vertex minimum.
    """
    nv = x.shape[1]
    best = best.copy()
    if nv > m + 1:
        # the tangent plane at s meets the cell's plane in one point y*; if
        # y* is in the cell the minimum is 0
        u = _orthonormal(fpts[:, 1:] - fpts[:, :1])  # (F, r, d)
        ut = np.swapaxes(u, 1, 2) @ tan  # (F, d, d)
        rhs = np.einsum("frd,fr->fd", u, x[:, 0])
        det = np.abs(np.linalg.det(ut))
        ok = det > 1e-9
        coef = np.linalg.solve(np.where(ok[:, None, None], ut, np.eye(ut.shape[1])), rhs[..., None])[..., 0]
        xs = np.einsum("frd,fd->fr", tan, coef)
        y = s + xs
        radius = np.linalg.norm(xs, axis=1)
        # the convex cell lies in the bounding box of its vertices: y* outside
        # that box is outside the cell (no query needed)
        lo, hi = _over_cell(np.minimum, x), _over_cell(np.maximum, x)
        slack = 1e-9 * (np.maximum(-lo, hi).max(axis=1) + radius)[:, None]
        in_box = ((xs >= lo - slack) & (xs <= hi + slack)).all(axis=1)
        ask = np.flatnonzero(ok & in_box)
        inside = np.zeros(len(x), dtype=bool)
        if len(ask):
            dist, _ = tree.query(y[ask])
            inside[ask] = dist >= radius[ask] * (1 - 1e-9) - 1e-12
        best[inside] = 0.0
        rest = np.flatnonzero(~inside)
    else:
        rest = np.arange(len(x))
    if len(rest) == 0:
        return best
    if cell_faces is not None and nv > m + 1:
        edges, polygons = cell_faces.for_batch(batch[rest])
        cap = np.minimum(best[rest], sin_lim2)
        exact = _cell_boundary_min(x[rest], nrm[rest], s[rest], edges, polygons, cap, tree)
        best[rest] = np.minimum(best[rest], exact)
        return best
    if not subsets:
        return best
    xr, nr = x[rest], nrm[rest]
    # lower bound per vertex subset: with any unit normal direction nu, a
    # subset whose vertices all have nu . N^T x / |x| >= c > 0 has sin >= c on
    # its whole cone; skip subsets that cannot beat the current minimum
    xn = xr @ nr
    unit = xn / np.maximum(np.linalg.norm(xr, axis=2), 1e-300)[..., None]
    nu = np.einsum("fvm->fm", unit)
    nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
    dots = _dots(unit, nu)
    cap = np.minimum(best[rest], sin_lim2)
    for sub in subsets:
        lb = dots[:, sub].min(axis=2)  # (F, S)
        need = (lb <= 0) | (lb**2 < cap[:, None])
        fi, si = np.nonzero(need)
        if len(fi) == 0:
            continue
        v2, ins = _cone_min(xr[fi[:, None], sub[si]], nr[fi])
        val = np.where(ins, v2, np.inf)
        low = np.full(len(rest), np.inf)
        np.minimum.at(low, fi, val)
        best[rest] = np.minimum(best[rest], low)
        cap = np.minimum(best[rest], sin_lim2)
    return best
