"""The exact step of Algorithm 2's cocone score: the minimum over a dual cell.

:mod:`.candidates` settles most (face, vertex) pairs from the cell's vertices
and a one-sided certificate; the rest come here (steps 2 and 3 of its
docstring): the tangent plane's meeting point with the cell's plane, when
it lies in the cell, and otherwise the minimum over the cell's boundary,
from its true edges and polygons (:mod:`.dualcells`) or from vertex subsets.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .conemin import cone_min, dot_rows, over_cell
from .dualcells import CellFaces, cell_boundary_min
from .literal import _orthonormal


def exact_min(
    x: np.ndarray,
    nrm: np.ndarray,
    tan: np.ndarray,
    fpts: np.ndarray,
    s: np.ndarray,
    best: np.ndarray,
    subsets: list[np.ndarray],
    m: int,
    tree: cKDTree,
    sin_lim2: float,
    cell_faces: CellFaces | None = None,
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
        lo, hi = over_cell(np.minimum, x), over_cell(np.maximum, x)
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
        exact = cell_boundary_min(x[rest], nrm[rest], s[rest], edges, polygons, cap, tree)
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
    dots = dot_rows(unit, nu)
    cap = np.minimum(best[rest], sin_lim2)
    for sub in subsets:
        lb = dots[:, sub].min(axis=2)  # (F, S)
        need = (lb <= 0) | (lb**2 < cap[:, None])
        fi, si = np.nonzero(need)
        if len(fi) == 0:
            continue
        v2, ins = cone_min(xr[fi[:, None], sub[si]], nr[fi])
        val = np.where(ins, v2, np.inf)
        low = np.full(len(rest), np.inf)
        np.minimum.at(low, fi, val)
        best[rest] = np.minimum(best[rest], low)
        cap = np.minimum(best[rest], sin_lim2)
    return best
