"""Smallest angle to a tangent plane over cones, segments and polygons.

For a sample s with orthonormal normal basis N (columns spanning AN_s), the
squared sine of the angle between a vector x and the tangent plane AT_s is
the Rayleigh quotient ``|N^T x|^2 / |x|^2``.  Its minimum over the linear span
of a few generators is the smallest eigenvalue of a small symmetric matrix;
the minimiser lies in their convex cone iff its coefficients share one sign.
These batched primitives serve the cocone test of Algorithm 2
(:mod:`crustview.core.paper.candidates`), together with cheap one-sided bounds
(:func:`lean_bound`) that settle most pairs without an eigenproblem.
"""

from __future__ import annotations

import numpy as np


def cone_min_pair(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closed form of :func:`cone_min` for two generators, x: (..., 2, r)."""
    xn = x @ nrm
    return segment_min(x[..., 0, :], x[..., 1, :], xn[..., 0, :], xn[..., 1, :])


def segment_min(x1: np.ndarray, x2: np.ndarray, n1: np.ndarray, n2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def cone_min(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
        return cone_min_pair(x, nrm)
    value, lam, ok = span_min(x, nrm)
    tol = 1e-9 * np.abs(lam).max(axis=-1, keepdims=True)
    inside = ok & ((lam >= -tol).all(axis=-1) | (lam <= tol).all(axis=-1))
    return value, inside


def span_min(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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


def span_min3(x: np.ndarray, nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`span_min` for three generators in closed form, x: (P, 3, r).

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
        [
            np.stack([m00 - lam_min, m01, m02], 1),
            np.stack([m01, m11 - lam_min, m12], 1),
            np.stack([m02, m12, m22 - lam_min], 1),
        ],
        axis=1,
    )
    cands = np.stack(
        [np.cross(rows[:, 0], rows[:, 1]), np.cross(rows[:, 0], rows[:, 2]), np.cross(rows[:, 1], rows[:, 2])], axis=1
    )
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
        value[fragile], coef[fragile], ok[fragile] = span_min(x[fragile], nrm[fragile])
    return value, coef, ok


def _null_vector(rows: np.ndarray) -> np.ndarray:
    """A unit vector orthogonal to the (rank <= 1) rows of each 3x3 block."""
    big = rows[np.arange(len(rows)), np.einsum("pij,pij->pi", rows, rows).argmax(axis=1)]
    trial = np.where((np.abs(big[:, :1]) < 0.9), np.array([[1.0, 0, 0]]), np.array([[0, 1.0, 0]]))
    v = np.cross(big, trial)
    tiny = np.einsum("pi,pi->p", v, v) <= 1e-300
    v[tiny] = [1.0, 0.0, 0.0]
    return v


def lean_bound(unit: np.ndarray, iterations: int = 12) -> np.ndarray:
    """Lower bound of ``max_nu min_i nu . unit_i`` over unit ``nu`` (batched (F, v, m)).

    Starts from the mean direction and moves ``nu`` towards the worst vector
    with shrinking steps (Badoiu-Clarkson); any ``nu`` gives a valid bound,
    the iterations only tighten it.
    """
    nu = np.einsum("fvm->fm", unit)
    nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
    dots = dot_rows(unit, nu)
    best = over_cell(np.minimum, dots)
    rows = np.arange(len(unit))
    for it in range(iterations):
        worst = unit[rows, dots.argmin(axis=1)]
        nu = nu + (worst - nu) / (it + 2)
        nu /= np.maximum(np.linalg.norm(nu, axis=1, keepdims=True), 1e-300)
        dots = dot_rows(unit, nu)
        best = np.maximum(best, over_cell(np.minimum, dots))
    return best


def over_cell(op: np.ufunc, a: np.ndarray) -> np.ndarray:
    """``op`` (np.minimum or np.maximum) reduced over axis 1, the few cell vertices.

    A loop of whole-array operations is several times faster than numpy's
    reduction over a short middle axis.
    """
    if a.shape[1] > 8:  # large cells: numpy's own reduction wins again
        return op.reduce(a, axis=1)
    out = a[:, 0].copy()
    for i in range(1, a.shape[1]):
        op(out, a[:, i], out=out)
    return out


def dot_rows(unit: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """``unit[f, v] . nu[f]`` for (F, v, m) and (F, m).

    A loop over the small m axis beats matmul/einsum on these shapes.
    """
    out = unit[..., 0] * nu[:, None, 0]
    for j in range(1, unit.shape[2]):
        out += unit[..., j] * nu[:, None, j]
    return out
