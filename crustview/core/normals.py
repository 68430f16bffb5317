"""Algorithm 1: approximate normal planes AN_s from k - d poles.

For a sample ``s`` with Voronoi vertices ``v`` (circumcentres of the Delaunay
simplices around ``s``), the paper's loop is::

    X := {s}
    while |X| < k - d + 1:                  # the paper prints "n - d + 1"
        v := Voronoi vertex of Vor(s) whose vector s->v has the longest
             projection onto P_X^perp
        X := X u {v}
    return P_X

``P_X`` is the affine hull of ``X``; its directions are spanned by the chosen
``v - s``.  We keep an orthonormal basis of those directions (Gram-Schmidt of
the chosen residuals), which *is* AN_s; AT_s is its orthogonal complement.
The loop is vectorised over all samples at once: each iteration projects every
(sample, Voronoi vertex) pair once.

The printed bound ``n - d + 1`` is read as ``k - d + 1`` (n is the number of
samples elsewhere in the paper; a normal plane of a d-manifold in R^k has
dimension k - d).
"""

from __future__ import annotations

import numpy as np


def greedy_poles(
    work: np.ndarray,
    simplices: np.ndarray,
    centres: np.ndarray,
    n_samples: int,
    n_poles: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run Algorithm 1 for every sample.

    Parameters
    ----------
    work : ndarray of shape (n_all, r)
        Delaunay vertices (samples first, then far bounding points).
    simplices : ndarray of shape (t, r + 1)
    centres : ndarray of shape (t, r)
        Voronoi vertices (circumcentres).
    n_samples : int
        Only the first ``n_samples`` vertices are processed; larger indices
        are bounding points.
    n_poles : int
        ``r - d`` (codimension inside the working space).

    Returns
    -------
    pole_index : ndarray of shape (n_samples, n_poles)
        Chosen Voronoi vertices in greedy order: rows of ``centres``, or
        ``t + h`` for the h-th vertex at infinity (see below).
    normals : ndarray of shape (n_samples, r, n_poles)
        Orthonormal basis of AN_s in working coordinates.
    infinite : ndarray of shape (h, r)
        Drawable positions of the vertices at infinity.

    Notes
    -----
    A sample on the convex hull has an unbounded cell; the paper's farthest
    vertex is then the vertex at infinity in the direction of the cell's
    recession cone.  The far bounding points truncate that cone; we represent
    its direction by the mean unit direction from ``s`` to the truncated
    vertices (those of simplices with a bounding point), give it a length
    larger than any finite vertex so that the greedy loop picks it first (as
    it would pick a vertex at infinity), and draw it at the mean distance of
    the truncated vertices.  Using one truncated corner instead would tilt
    the normal by up to the cone's angular radius.
    """
    r = work.shape[1]
    t = len(centres)
    inc = _Incidences(work, simplices, centres, n_samples)
    # vertices at infinity of hull samples: the mean unit direction to the
    # truncated vertices, longer than any finite vertex (same sums, in the
    # same order per sample, as a CSR walk)
    # this pass also does the first greedy round's work for the finite vertices:
    # with nothing chosen yet, the residual of a vector is the vector itself
    norm2 = np.empty(inc.size + n_samples)  # room for the vertices at infinity (at most one per sample)
    seg0 = np.full(n_samples, -np.inf)
    dir_sum = np.zeros((n_samples, r))
    len_sum = np.zeros(n_samples)
    far_count = np.zeros(n_samples)
    for owner, sid, vec, pos in inc.blocks(with_pos=True, extra=False):
        if len(vec):
            inc.max_abs = max(inc.max_abs, float(np.abs(vec).max()))
        nb = np.einsum("er,er->e", vec, vec)
        norm2[pos] = nb
        np.maximum.at(seg0, owner, nb)
        far = inc.far[sid]
        if far.any():
            of, lf = owner[far], np.sqrt(nb[far])
            unit = vec[far] / np.maximum(lf, 1e-300)[:, None]
            for c in range(r):
                dir_sum[:, c] += np.bincount(of, weights=unit[:, c], minlength=n_samples)
            len_sum += np.bincount(of, weights=lf, minlength=n_samples)
            far_count += np.bincount(of, minlength=n_samples)
    hull = np.flatnonzero(far_count > 0)
    infinite = np.empty((0, r))
    if len(hull):
        mean_dir = dir_sum[hull]
        mean_dir /= np.maximum(np.linalg.norm(mean_dir, axis=1, keepdims=True), 1e-300)
        mean_len = len_sum[hull] / far_count[hull]
        infinite = work[hull] + mean_dir * mean_len[:, None]
        max_len = np.sqrt(np.maximum(seg0[hull], 0.0))
        inc.add_extra(hull, mean_dir * (2.0 * max_len + 1.0)[:, None], t + np.arange(len(hull)))
    del dir_sum, len_sum
    pole_index = np.full((n_samples, n_poles), -1, dtype=np.int64)
    normals = np.zeros((n_samples, r, n_poles))
    has = inc.count > 0
    for j in range(n_poles):
        # longest residual per sample; the first entry attaining it (in the
        # order simplex id, then vertex at infinity) is the pole
        segmax = seg0 if j == 0 else np.full(n_samples, -np.inf)
        for owner, sid, vec, pos in inc.blocks(with_pos=True, finite=j > 0):
            resid = _residual(vec, normals[owner, :, :j])
            nb = np.einsum("er,er->e", resid, resid)
            norm2[pos] = nb
            np.maximum.at(segmax, owner, nb)
        first = np.full(n_samples, inc.size)
        for owner, sid, vec, pos in inc.blocks(with_pos=True, geometry=False):
            hit = np.flatnonzero(norm2[pos] == segmax[owner])
            np.minimum.at(first, owner[hit], pos[hit])
        who = np.flatnonzero(has)
        chosen = first[who]
        owner_c, vec_c, index_c = inc.entries(chosen)
        u = _residual(vec_c, normals[owner_c, :, :j])
        length = np.sqrt((u**2).sum(axis=1))
        degenerate = length <= 1e-12 * max(1.0, inc.max_abs)
        u = u / np.where(degenerate, 1.0, length)[:, None]
        if degenerate.any():
            u[degenerate] = _complement_direction(normals[who[degenerate], :, :j])
        pole_index[who, j] = index_c
        normals[who, :, j] = u
    if not has.all():
        missing = np.flatnonzero(~has)
        normals[missing] = np.eye(r)[:, :n_poles]
    return pole_index, normals, infinite


def _residual(vec: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """``vec`` with the directions ``basis[e, :, i]`` removed one after another."""
    resid = vec.copy()
    for i in range(basis.shape[2]):
        ue = basis[:, :, i]
        resid -= (resid * ue).sum(axis=1, keepdims=True) * ue
    return resid


class _Incidences:
    """(sample, Voronoi vertex) pairs of Algorithm 1, walked in blocks.

    Entry ``e = sid * (r + 1) + a`` is vertex ``a`` of simplex ``sid`` (kept
    only when that vertex is a sample); entries after ``t * (r + 1)`` are the
    vertices at infinity of hull samples.  Vectors ``centre - sample`` are
    recomputed per block rather than stored, so memory stays at a few
    numbers per entry even for tens of millions of entries.
    """

    #: Simplices per block.
    BLOCK = 1 << 18

    def __init__(self, work: np.ndarray, simplices: np.ndarray, centres: np.ndarray, n_samples: int) -> None:
        self.work, self.simplices, self.centres, self.n = work, simplices, centres, n_samples
        self.width = simplices.shape[1]
        self.far = (simplices >= n_samples).any(axis=1)
        self.count = np.bincount(simplices.ravel(), minlength=n_samples)[:n_samples]
        self.size = simplices.size
        self.extra_owner = np.empty(0, np.int64)
        self.extra_vec = np.empty((0, work.shape[1]))
        self.extra_index = np.empty(0, np.int64)
        self.max_abs = 0.0  # largest |coordinate| of any vector, set by the caller

    def add_extra(self, owner: np.ndarray, vec: np.ndarray, index: np.ndarray) -> None:
        """Append the vertices at infinity (after every simplex entry)."""
        self.extra_owner, self.extra_vec, self.extra_index = owner, vec, index
        self.count[owner] += 1
        self.size = self.simplices.size + len(owner)
        if len(vec):
            self.max_abs = max(self.max_abs, float(np.abs(vec).max()))

    def blocks(self, with_pos: bool = False, geometry: bool = True, finite: bool = True,  # noqa: ANN201
               extra: bool = True):
        """Yield ``(owner, sid, vec[, pos])`` per block; ``vec`` is None without geometry.

        ``finite`` and ``extra`` select the simplex entries and the vertices at
        infinity (which come only ``with_pos``).
        """
        t, w = len(self.simplices), self.width
        for lo in range(0, t if finite else 0, self.BLOCK):
            flat = self.simplices[lo : lo + self.BLOCK].ravel()
            keep = np.flatnonzero(flat < self.n)
            owner = flat[keep]
            sid = lo + keep // w
            vec = np.take(self.centres, sid, axis=0) - np.take(self.work, owner, axis=0) if geometry else None
            yield (owner, sid, vec, lo * w + keep) if with_pos else (owner, sid, vec)
        if with_pos and extra and len(self.extra_owner):
            pos = self.simplices.size + np.arange(len(self.extra_owner))
            sid = np.full(len(pos), -1)
            yield self.extra_owner, sid, self.extra_vec if geometry else None, pos

    def entries(self, pos: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Owner, vector and Voronoi-vertex index of the entries at ``pos``."""
        base = self.simplices.size
        fin = pos < base
        owner = np.empty(len(pos), np.int64)
        index = np.empty(len(pos), np.int64)
        vec = np.empty((len(pos), self.work.shape[1]))
        sid = pos[fin] // self.width
        owner[fin] = self.simplices.ravel()[pos[fin]]
        index[fin] = sid
        vec[fin] = self.centres[sid] - self.work[owner[fin]]
        ext = pos[~fin] - base
        owner[~fin] = self.extra_owner[ext]
        index[~fin] = self.extra_index[ext]
        vec[~fin] = self.extra_vec[ext]
        return owner, vec, index


def _complement_direction(basis: np.ndarray) -> np.ndarray:
    """A unit vector orthogonal to the columns of each ``basis`` (m, r, j)."""
    m, r, j = basis.shape
    out = np.zeros((m, r))
    for i in range(m):
        q, _ = np.linalg.qr(np.hstack([basis[i], np.eye(r)]), mode="reduced")
        out[i] = q[:, j]
    return out


def complete_bases(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split R^k into the normal basis and its orthogonal complement.

    Parameters
    ----------
    normals : ndarray of shape (n, k, c)
        Orthonormal columns.

    Returns
    -------
    normals : ndarray of shape (n, k, c)
        Re-orthonormalised.
    tangents : ndarray of shape (n, k, k - c)
    """
    n, k, c = normals.shape
    q, _ = np.linalg.qr(normals, mode="complete")
    # q[..., :c] spans the same space as normals; keep the original orientation
    return q[:, :, :c] * np.sign(np.einsum("nkc,nkc->nc", q[:, :, :c], normals))[:, None, :], q[:, :, c:]
