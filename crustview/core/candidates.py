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

Cocone test (Amenta-Choi-Dey-Leekha, generalised)
-------------------------------------------------
The cocone of ``s`` is ``{y : angle(y - s, AT_s) <= theta}``.  ``sigma``
passes when its dual cell meets the cocone of *every* vertex (as in Cocone).
The score is ``cocone = max_s min_{y in cell} angle(y - s, AT_s)`` with
``sin^2 angle(x, AT_s) = |N_s^T x|^2 / |x|^2``.

The minimum over the cell is computed exactly in codimension 1 and 2: the
ratio is a Rayleigh quotient, so its minimum over the cone spanned from ``s``
by a set of points is the smallest eigenvalue of a small symmetric matrix,
attained inside the set's convex hull iff the eigenvector's barycentric
coefficients share one sign.  We evaluate

* every cell vertex,
* every simplex spanned by ``j`` cell vertices, ``2 <= j <= k - d`` (this
  covers the boundary of the cell; in codimension >= 3 only when the cell has
  at most :data:`MAX_SUBSET_VERTICES` vertices, otherwise pairs only),
* the whole plane ``Pi``: the unconstrained minimiser is accepted when it lies
  in the cell, checked as "no Delaunay vertex is closer to it than sigma's
  vertices" with a k-d tree (a Voronoi cell *is* that set).  When the cell is
  itself a simplex (always in codimension 1) barycentric signs are used.

A local minimum of a Rayleigh quotient on an affine chart is the global one,
so "plane minimiser outside the cell" means the minimum lies on the boundary.
In codimension >= 3 with large cells the boundary is sampled by vertex pairs
only, which can only *over*-estimate the angle (reject, never admit wrongly).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

#: Cells with more vertices skip the (k-d)-subset enumeration in codim >= 3.
MAX_SUBSET_VERTICES = 12


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
        uniq_key, first, inverse = np.unique(key, return_index=True, return_inverse=True)
        uniq = faces[first]
    else:
        uniq, inverse = np.unique(faces, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    order = np.argsort(inverse, kind="stable")
    counts = np.bincount(inverse, minlength=len(uniq))
    ptr = np.concatenate([[0], np.cumsum(counts)])
    return uniq.astype(np.int64), ptr, owner[order]


def _orthonormal(vectors: np.ndarray) -> np.ndarray:
    """Orthonormal basis (columns) of the span of the rows, batched: (..., j, r) -> (..., r, j)."""
    q, _ = np.linalg.qr(np.swapaxes(vectors, -1, -2))
    return q


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
        s = np.linalg.svd(nt_u, compute_uv=False)[:, 0]
        best = np.minimum(best, np.arcsin(np.clip(s, 0.0, 1.0)))
    return best


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
    q, rr = np.linalg.qr(np.swapaxes(x, -1, -2))  # (..., r, j), (..., j, j)
    diag = np.abs(np.diagonal(rr, axis1=-2, axis2=-1))
    scale = np.linalg.norm(x, axis=-1).max(axis=-1)
    ok = diag.min(axis=-1) > 1e-10 * np.maximum(scale, 1e-300)
    b = np.swapaxes(nrm, -1, -2) @ q  # (..., m, j)
    mat = np.swapaxes(b, -1, -2) @ b
    w, v = np.linalg.eigh(mat)
    z = v[..., 0]
    eye = np.eye(rr.shape[-1])
    safe = np.where(ok[..., None, None], rr, eye)
    lam = np.linalg.solve(safe, z[..., None])[..., 0]
    tol = 1e-9 * np.abs(lam).max(axis=-1, keepdims=True)
    inside = ok & ((lam >= -tol).all(axis=-1) | (lam <= tol).all(axis=-1))
    return np.clip(w[..., 0], 0.0, 1.0), inside


def cocone_angles(
    work: np.ndarray,
    normals: np.ndarray,
    centres: np.ndarray,
    faces: np.ndarray,
    cell_ptr: np.ndarray,
    cell_simplices: np.ndarray,
    *,
    progress: Callable[[float], None] | None = None,
) -> np.ndarray:
    """Cocone score of every face (see module docstring).

    Parameters
    ----------
    work : ndarray of shape (n_all, r)
        All Delaunay vertices (samples first, then bounding points).
    normals : ndarray of shape (n, r, m)
    centres : ndarray of shape (t, r)
        Voronoi vertices.
    faces, cell_ptr, cell_simplices
        From :func:`enumerate_faces`.

    Returns
    -------
    ndarray of shape (f,), radians in [0, pi/2].
    """
    f, dp1 = faces.shape
    r = work.shape[1]
    m = normals.shape[2]
    nv_all = np.diff(cell_ptr)
    out = np.full(f, np.pi / 2)
    tree = cKDTree(work)
    buckets = np.unique(nv_all)
    done = 0
    for nv in buckets:
        sel = np.flatnonzero(nv_all == nv)
        cells = centres[cell_simplices[cell_ptr[sel][:, None] + np.arange(nv)]]  # (F, nv, r)
        fc = faces[sel]
        p = work[fc]
        whole_is_simplex = nv <= m + 1
        if not whole_is_simplex:
            u = _orthonormal(p[:, 1:] - p[:, :1])  # (F, r, d)
            w_basis = _plane_complement(u, m)  # (F, r, m)
        jmax = min(m, nv)
        subsets = []
        for j in range(2, jmax + 1):
            if j > 2 and m >= 3 and nv > MAX_SUBSET_VERTICES:
                break
            subsets.append(np.array(list(itertools.combinations(range(nv), j))))
        if whole_is_simplex and nv >= 2 and (nv > jmax):
            subsets.append(np.arange(nv)[None, :])
        worst = np.zeros(len(sel))
        for a in range(dp1):
            s = p[:, a]
            nrm = normals[fc[:, a]]
            x = cells - s[:, None, :]
            xn = np.einsum("fvr,frm->fvm", x, nrm)
            val = (xn**2).sum(axis=2) / np.maximum((x**2).sum(axis=2), 1e-300)
            best = val.min(axis=1)
            for sub in subsets:
                xs = x[:, sub]  # (F, S, j, r)
                v2, ins = _cone_min(xs, nrm[:, None])
                v2 = np.where(ins, v2, np.inf).min(axis=1)
                best = np.minimum(best, v2)
            if not whole_is_simplex:
                best = np.minimum(best, _plane_min(x[:, 0], w_basis, nrm, s, p[:, 0], tree))
            worst = np.maximum(worst, best)
        out[sel] = np.arcsin(np.sqrt(np.clip(worst, 0.0, 1.0)))
        done += len(sel)
        if progress is not None:
            progress(done / max(f, 1))
    return out


def _plane_complement(u: np.ndarray, m: int) -> np.ndarray:
    """Orthonormal basis of the complement of the columns of ``u`` (F, r, d) -> (F, r, m)."""
    q, _ = np.linalg.qr(u, mode="complete")
    return q[:, :, u.shape[2] : u.shape[2] + m]


def _plane_min(
    x0: np.ndarray,
    w_basis: np.ndarray,
    nrm: np.ndarray,
    s: np.ndarray,
    anchor: np.ndarray,
    tree: cKDTree,
) -> np.ndarray:
    """sin^2 of the plane-wide minimiser when it lies in the dual cell, else inf.

    ``x0`` is one cell vertex minus ``s``; the plane is ``x0 + span(w_basis)``.
    """
    h = x0 - np.einsum("frm,fm->fr", w_basis, np.einsum("frm,fr->fm", w_basis, x0))
    gens = np.concatenate([h[:, None, :], np.swapaxes(w_basis, 1, 2)], axis=1)  # (F, m+1, r)
    q, _ = np.linalg.qr(np.swapaxes(gens, 1, 2))
    b = np.swapaxes(nrm, 1, 2) @ q
    w, v = np.linalg.eigh(np.swapaxes(b, 1, 2) @ b)
    xv = np.einsum("frj,fj->fr", q, v[:, :, 0])
    hn = np.linalg.norm(h, axis=1)
    along = np.einsum("fr,fr->f", xv, h) / np.maximum(hn, 1e-300)
    ok = np.abs(along) > 1e-9
    scale = np.where(ok, hn / np.where(ok, along, 1.0), 0.0)
    y = s + xv * scale[:, None]
    radius = np.linalg.norm(y - anchor, axis=1)
    dist, _ = tree.query(y)
    inside = ok & (dist >= radius * (1 - 1e-9) - 1e-12)
    return np.where(inside, np.clip(w[:, 0], 0.0, 1.0), np.inf)
