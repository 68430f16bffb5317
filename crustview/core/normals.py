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

from .delaunay import vertex_simplices


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
    indptr, inc = vertex_simplices(simplices, len(work))
    indptr = indptr[: n_samples + 1]
    inc = inc[: indptr[-1]]
    owner = np.repeat(np.arange(n_samples), np.diff(indptr))
    vec = centres[inc] - work[owner]
    # vertices at infinity of hull samples
    far = (simplices[inc] >= n_samples).any(axis=1)
    length = np.linalg.norm(vec, axis=1)
    hull = np.unique(owner[far])
    infinite = np.empty((0, r))
    if len(hull):
        unit = vec[far] / np.maximum(length[far], 1e-300)[:, None]
        pos = np.searchsorted(hull, owner[far])
        mean_dir = np.zeros((len(hull), r))
        np.add.at(mean_dir, pos, unit)
        mean_dir /= np.maximum(np.linalg.norm(mean_dir, axis=1, keepdims=True), 1e-300)
        mean_len = np.bincount(pos, weights=length[far]) / np.bincount(pos)
        max_len = np.zeros(n_samples)
        np.maximum.at(max_len, owner, length)
        infinite = work[hull] + mean_dir * mean_len[:, None]
        owner = np.concatenate([owner, hull])
        vec = np.vstack([vec, mean_dir * (2.0 * max_len[hull] + 1.0)[:, None]])
        inc = np.concatenate([inc, t + np.arange(len(hull))])
        order = np.argsort(owner, kind="stable")
        owner, vec, inc = owner[order], vec[order], inc[order]
        indptr = np.concatenate([[0], np.cumsum(np.bincount(owner, minlength=n_samples))])
    resid = vec.copy()
    pole_index = np.full((n_samples, n_poles), -1, dtype=np.int64)
    normals = np.zeros((n_samples, r, n_poles))
    has = np.diff(indptr) > 0
    starts = indptr[:-1][has]
    owner_rank = np.repeat(np.arange(has.sum()), np.diff(indptr)[has])
    for j in range(n_poles):
        norm2 = np.einsum("er,er->e", resid, resid)
        # entries are grouped by owner (CSR order): segment maxima, then the
        # first entry attaining each maximum
        segmax = np.maximum.reduceat(norm2, starts)
        hit = np.flatnonzero(norm2 == segmax[owner_rank])
        first = np.concatenate([[True], owner[hit][1:] != owner[hit][:-1]])
        chosen = hit[first]  # one entry per sample that has incidences
        who = owner[chosen]
        u = resid[chosen]
        length = np.sqrt((u**2).sum(axis=1))
        degenerate = length <= 1e-12 * max(1.0, float(np.abs(vec).max()))
        u = u / np.where(degenerate, 1.0, length)[:, None]
        if degenerate.any():
            u[degenerate] = _complement_direction(normals[who[degenerate], :, :j])
        pole_index[who, j] = inc[chosen]
        normals[who, :, j] = u
        # remove the new direction from every residual of the same sample
        uo = np.zeros((n_samples, r))
        uo[who] = u
        ue = uo[owner]
        resid -= (resid * ue).sum(axis=1, keepdims=True) * ue
    if not has.all():
        missing = np.flatnonzero(~has)
        normals[missing] = np.eye(r)[:, :n_poles]
    return pole_index, normals, infinite


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
