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

try:  # one greedy round in compiled code (setup.py builds it; numpy does the same without it)
    from ..delaunay import _poles as _native
except ImportError:  # pragma: no cover - depends on the build
    _native = None


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
    native = _native is not None and simplices.dtype == np.int32 and r <= 8
    normals = np.zeros((n_samples, r, n_poles))  # AN_s, filled column by column
    # first greedy round over the finite Voronoi vertices: with nothing chosen
    # yet, the residual of a vector is the vector itself
    if native:
        first0, seg0, inc.max_abs = _farthest(inc, normals, 0)
    else:
        norm2 = np.empty(inc.size + n_samples)  # room for the vertices at infinity (at most one per sample)
        seg0 = np.full(n_samples, -np.inf)
        for owner, _sid, vec, pos in inc.blocks(with_pos=True, extra=False):
            if len(vec):
                inc.max_abs = max(inc.max_abs, float(np.abs(vec).max()))
            nb = _sq_norms(vec)
            norm2[pos] = nb
            np.maximum.at(seg0, owner, nb)
    # vertices at infinity of hull samples: the mean unit direction to the
    # truncated vertices, longer than any finite vertex (same sums, in the
    # same order per sample, as a CSR walk)
    dir_sum = np.zeros((n_samples, r))
    len_sum = np.zeros(n_samples)
    far_count = np.zeros(n_samples)
    for of, vec in inc.far_blocks():
        lf = np.sqrt(_sq_norms(vec))
        unit = vec / np.maximum(lf, 1e-300)[:, None]
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
    has = inc.count > 0
    for j in range(n_poles):
        # longest residual per sample; the first entry attaining it (in the
        # order simplex id, then vertex at infinity) is the pole
        if native:
            first, segmax = (first0, seg0) if j == 0 else _farthest(inc, normals, j)[:2]
            if len(inc.extra_owner):  # after every simplex entry: they win only when strictly longer
                resid = _residual(inc.extra_vec, normals[inc.extra_owner, :, :j])
                wins = np.flatnonzero(_sq_norms(resid) > segmax[inc.extra_owner])
                first[inc.extra_owner[wins]] = inc.simplices.size + wins
        else:
            segmax = seg0 if j == 0 else np.full(n_samples, -np.inf)
            for owner, _sid, vec, pos in inc.blocks(with_pos=True, finite=j > 0):
                resid = _residual(vec, normals[owner, :, :j])
                nb = _sq_norms(resid)
                norm2[pos] = nb
                np.maximum.at(segmax, owner, nb)
            first = np.full(n_samples, inc.size)
            for owner, _sid, _vec, pos in inc.blocks(with_pos=True, geometry=False):
                hit = np.flatnonzero(norm2[pos] == segmax[owner])
                np.minimum.at(first, owner[hit], pos[hit])
        who = np.flatnonzero(has)
        chosen = first[who]
        owner_c, vec_c, index_c = inc.entries(chosen)
        u = _residual(vec_c, normals[owner_c, :, :j])
        length = np.sqrt((u**2).sum(axis=1))
        # a vector (numerically) in the span already chosen: its residual vanishes against its own length.
        # (Against the largest vector of the whole set, one far outlier, whose Voronoi vertices lie far
        # off, made the poles of 79 % of a scan's samples "degenerate": their normals became an axis.)
        degenerate = length <= 1e-12 * np.sqrt((vec_c**2).sum(axis=1))
        u = u / np.where(degenerate, 1.0, length)[:, None]
        if degenerate.any():
            u[degenerate] = _complement_direction(normals[who[degenerate], :, :j])
        pole_index[who, j] = index_c
        normals[who, :, j] = u
    if not has.all():
        missing = np.flatnonzero(~has)
        normals[missing] = np.eye(r)[:, :n_poles]
    return pole_index, normals, infinite


def _farthest(inc: _Incidences, basis: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray, float]:
    """One greedy round over the finite Voronoi vertices, by the extension :mod:`._poles`.

    Returns per sample the first entry attaining the longest residual (-1 if
    none) and its squared length (-inf), and the largest |coordinate| of any
    vector.  Same arithmetic as the numpy rounds (:func:`_sq_norms`,
    :func:`_residual`), so the same entries.
    """
    r = inc.work.shape[1]
    first, best, max_abs = _native.farthest(
        np.ascontiguousarray(inc.centres, dtype=np.float64),
        np.ascontiguousarray(inc.work, dtype=np.float64),
        np.ascontiguousarray(inc.simplices),
        np.ascontiguousarray(basis),
        inc.n,
        r,
        r + 1,
        basis.shape[2],
        j,
    )
    return np.frombuffer(first, dtype=np.int64).copy(), np.frombuffer(best, dtype=np.float64), max_abs


def _sq_norms(vec: np.ndarray) -> np.ndarray:
    """Squared row lengths, summed from the first coordinate on (as :mod:`._poles` sums them)."""
    return (vec * vec).sum(axis=1)


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
        if _native is not None and simplices.dtype == np.int32 and simplices.flags.c_contiguous:
            # one pass, without bincount's int64 copy of the table (the same counts and flags)
            count, far = _native.vertex_counts(simplices, n_samples, self.width)
            self.count = np.frombuffer(count, dtype=np.int64)
            self.far = np.frombuffer(far, dtype=np.bool_)
        else:
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

    def blocks(
        self,
        with_pos: bool = False,
        geometry: bool = True,
        finite: bool = True,  # noqa: ANN201
        extra: bool = True,
    ):
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

    def far_blocks(self):  # noqa: ANN201
        """Yield ``(owner, vec)`` of the entries of simplices with a bounding point, block by block.

        The blocks are those of :meth:`blocks`, so per-block sums are added in the same order.
        """
        t, w = len(self.simplices), self.width
        for lo in range(0, t, self.BLOCK):
            sids = lo + np.flatnonzero(self.far[lo : lo + self.BLOCK])
            if len(sids) == 0:
                continue
            flat = self.simplices[sids].ravel()
            keep = np.flatnonzero(flat < self.n)
            owner = flat[keep]
            sid = sids[keep // w]
            yield owner, np.take(self.centres, sid, axis=0) - np.take(self.work, owner, axis=0)

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
