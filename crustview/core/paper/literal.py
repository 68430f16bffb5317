"""Algorithm 2's literal test: the angle between a face's dual cell and AN_s.

See :mod:`.candidates` for what the test means and how it is used.  The
orientation of the dual (k-d)-cell is that of the orthogonal complement of
``aff(sigma)``, so ``sin(angle) = ||N_s^T U_sigma||_2`` (largest principal
angle), minimised over the face's vertices s.  Faces of dimension <= 2 work on
contiguous per-coordinate columns (closed-form bases and Gram matrices);
larger faces use batched QR and eigenvalues.
"""

from __future__ import annotations

import numpy as np

from ..util.parallel import chunks, run_in_order

try:  # triangles' sines in compiled code (setup.py builds it; numpy does the same without it)
    from ..delaunay import _literal as _native
except ImportError:  # pragma: no cover - depends on the build
    _native = None

#: Faces per chunk (keeps temporaries in cache; chunks run on threads).
CHUNK_FACES = 1 << 16


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


def literal_angles(work: np.ndarray, normals: np.ndarray, faces: np.ndarray, workers: int | None = None) -> np.ndarray:
    """Paper's test: min over vertices of the angle between aff(sigma) and AT_s.

    Parameters
    ----------
    work : ndarray of shape (n, r)
    normals : ndarray of shape (n, r, m)
    faces : ndarray of shape (f, d + 1)
    workers : int, optional
        Threads working on chunks of faces; the result does not depend on it.

    Returns
    -------
    ndarray of shape (f,), radians in [0, pi/2].
    """
    out = np.empty(len(faces))
    # faces of dimension <= 2: everything on contiguous per-coordinate columns
    # (a 2-face's basis in closed form, N_s^T U entry by entry), which is
    # several times faster than batched einsum/matmul on (F, r, <=3) blocks
    by_columns = faces.shape[1] <= 3
    # triangles: the same sines bit for bit from the extension, without the GIL
    native = _native is not None and faces.shape[1] == 3 and work.dtype == normals.dtype == np.float64
    if native:
        work, normals = np.ascontiguousarray(work), np.ascontiguousarray(normals)

    def chunk(sl: slice) -> slice:
        fc = faces[sl]
        if native:
            sines = _native.literal(work, normals, np.ascontiguousarray(fc, dtype=np.int64), *normals.shape[1:])
            out[sl] = np.arcsin(np.clip(np.frombuffer(sines, dtype=np.float64), 0.0, 1.0))
            return sl
        p = np.take(work, fc, axis=0)
        if by_columns:
            u_cols = _orthonormal_columns(p)
        else:
            u = _orthonormal(p[:, 1:] - p[:, :1])  # (F, r, d)
        best_sin = np.full(len(fc), np.inf)  # arcsin is increasing: take it once, of the minimum
        for a in range(fc.shape[1]):
            nrm = np.take(normals, fc[:, a], axis=0)  # (F, r, m)
            if by_columns:
                s = np.sqrt(_spectral_sq_columns(nrm, u_cols))
            else:
                s = np.sqrt(_largest_eig(np.einsum("frm,frd->fmd", nrm, u)))
            np.minimum(best_sin, s, out=best_sin)
        out[sl] = np.arcsin(np.clip(best_sin, 0.0, 1.0))
        return sl

    for _ in run_in_order(chunk, chunks(len(faces), CHUNK_FACES), workers):
        pass
    return out


def _orthonormal_columns(p: np.ndarray) -> list[list[np.ndarray]]:
    """Orthonormal basis of the edge span of each 1- or 2-face, as columns.

    ``p`` is (F, d + 1, r) with d in {1, 2}; returns ``cols[c][q]``, the
    q-th coordinate (a contiguous (F,) array) of the c-th basis vector:
    Gram-Schmidt on the edges from the first vertex.
    """
    r = p.shape[2]
    e1 = [p[:, 1, q] - p[:, 0, q] for q in range(r)]
    _normalise_columns(e1)
    if p.shape[1] == 2:
        return [e1]
    w = [p[:, 2, q] - p[:, 0, q] for q in range(r)]
    proj = _dot_columns(w, e1)
    for q in range(r):
        w[q] -= proj * e1[q]
    _normalise_columns(w)
    return [e1, w]


def _dot_columns(a: list[np.ndarray], b: list[np.ndarray]) -> np.ndarray:
    out = a[0] * b[0]
    for x, y in zip(a[1:], b[1:]):
        out += x * y
    return out


def _normalise_columns(cols: list[np.ndarray]) -> None:
    norm = np.maximum(np.sqrt(_dot_columns(cols, cols)), 1e-300)
    for c in cols:
        c /= norm


def _spectral_sq_columns(nrm: np.ndarray, u_cols: list[list[np.ndarray]]) -> np.ndarray:
    """``||N^T U||_2^2`` for N (F, r, m) and U given as columns (at most 2 of them).

    The largest eigenvalue of the d x d Gram matrix of the columns of
    ``N^T U``: the sum of squares when ``N^T U`` has rank one (d = 1 or
    m = 1), the closed form for d = 2.
    """
    m = nrm.shape[2]
    # mt[c][j] = (N^T U)[j, c]
    mt = [[_dot_columns([nrm[:, q, j] for q in range(nrm.shape[1])], col) for j in range(m)] for col in u_cols]
    if len(u_cols) == 1 or m == 1:  # rank one: the spectral norm is the Frobenius norm
        return sum(_dot_columns(row, row) for row in mt)
    a = _dot_columns(mt[0], mt[0])
    b = _dot_columns(mt[0], mt[1])
    c = _dot_columns(mt[1], mt[1])
    return 0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + b**2)


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
