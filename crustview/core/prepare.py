"""Input preparation: validation, duplicate merging, normalisation.

Everything Qhull sees goes through :func:`prepare_points`.  It

1. rejects non-finite values, too few points and ``d`` outside ``[1, k-1]``;
2. merges duplicates and near-duplicates: points closer than
   ``merge_tol * spacing`` (``spacing`` = median nearest-neighbour distance)
   become one sample, so tolerance scales with the data, not with 1e-12;
3. centres and scales the samples to unit radius (Qhull loses precision at
   large offsets).  Before any distance is taken, the input is divided by a
   power of two near its largest absolute value (:func:`prescale`), which is
   exact in binary floating point: coordinates near 1e300 or 1e-300, whose
   squared distances would overflow or underflow, work like any others;
4. detects a lower-dimensional affine hull (relative singular value below
   ``1e-9``) and expresses the points in an orthonormal basis of it; the
   caller lifts results back with :attr:`PreparedPoints.basis`;
5. applies a deterministic joggle of relative size ``joggle`` (of the
   spacing).  Exactly cospherical input (sphere, Clifford torus, S^3) is
   25-130x slower in Qhull and its Voronoi vertices all collapse onto the
   centre; a perturbation far below the sample spacing restores general
   position and a meaningful Voronoi diagram while changing no geometric
   quantity the algorithm uses by more than ``joggle * spacing``;
6. numbers the samples in spatial order (:func:`spatial_order`), so the
   later stages' gathers stay in cache; ``input_index`` and ``point_input``
   map between input rows and samples, and every file crustview writes is
   in input order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from .errors import InputError
from .util.nearest import nearest_other
from .util.vectors import power_of_two_above

#: Default joggle relative to the sample spacing.
DEFAULT_JOGGLE = 1e-6
#: Default merge tolerance relative to the sample spacing.
DEFAULT_MERGE_TOL = 1e-4
#: Leaf size of the k-d tree whose leaf order numbers the samples.
SPATIAL_LEAF = 16


@dataclass(frozen=True)
class PreparedPoints:
    """Samples ready for Qhull and the maps back to the input.

    Attributes
    ----------
    points : ndarray of shape (n, k)
        Unique samples in input coordinates (each merged group's first
        input row), numbered in spatial order (:func:`spatial_order`), not
        in input order: ``input_index`` and ``point_input`` map between them.
    input_index : ndarray of shape (n_in,)
        Sample each input row was merged into.
    point_input : ndarray of shape (n,)
        First input row of each sample.
    center : ndarray of shape (k,)
    scale : float
        ``work = ((points - center) @ basis) / scale`` (plus joggle).
    basis : ndarray of shape (k, r)
        Orthonormal basis of the affine hull's directions.
    work : ndarray of shape (n, r)
        Working coordinates given to Qhull (joggled).
    spacing : float
        Median nearest-neighbour distance of the samples, input units.
    joggle : float
        Joggle size in input units.
    nearest : ndarray of shape (n,) or None
        Each sample's distance to its nearest other sample, input units, as the merging measured it
        (``nearest_distances(points)``'s values, bit for bit wherever squared distances neither overflow nor
        underflow: the same tree query, on the points scaled by a power of two, scaled back); None where
        samples merged (the merged set's distances were not measured).
    """

    points: np.ndarray
    input_index: np.ndarray
    point_input: np.ndarray
    center: np.ndarray
    scale: float
    basis: np.ndarray
    work: np.ndarray
    spacing: float
    joggle: float
    nearest: np.ndarray | None = None

    @property
    def r(self) -> int:
        """Dimension of the affine hull of the samples."""
        return self.basis.shape[1]

    def lift(self, work_coords: np.ndarray) -> np.ndarray:
        """Map working coordinates ``(..., r)`` back to input space ``(..., k)``."""
        out = work_coords @ self.basis.T  # in place from here: one temporary at most
        out *= self.scale
        out += self.center
        return out

    def lift_stacked(self, *parts: np.ndarray) -> np.ndarray:
        """``lift(np.vstack(parts))`` for ``(m_i, r)`` parts, without the stacked copy.

        Each part's rows are mapped by the same product into its rows of one output: every row is the
        same dot products of the same numbers (``tests/test_core_prepare.py`` compares the two).
        """
        out = np.empty((sum(len(p) for p in parts), len(self.center)))
        at = 0
        for p in parts:
            np.matmul(p, self.basis.T, out=out[at : at + len(p)])
            at += len(p)
        out *= self.scale
        out += self.center
        return out

    def lift_appended(self, rows: np.ndarray, more: np.ndarray, block: int = 1 << 16) -> np.ndarray:
        """``lift_stacked(rows, more)`` in the room after ``rows``, whose values it overwrites.

        Where the working space is the whole space (r = k) and ``rows`` is the leading block of a float64
        C-contiguous array with room for ``more`` after it (``circumcenters(..., spare=...)``), ``more``
        is written into that room and the whole is lifted in place, block by block, each block by the
        same product as :meth:`lift_stacked`: the Voronoi vertices of the 300,000 point torus are 118 MB,
        and a fresh array that size cost 0.1-0.2 s of page faults here.  ``rows`` (and every view of its
        array) then holds lifted values: the caller passes rows it does not use again.  Otherwise
        :meth:`lift_stacked`.
        """
        k, r = self.basis.shape
        base = rows.base
        t, h = len(rows), len(more)
        fits = (
            r == k
            and isinstance(base, np.ndarray)
            and base.dtype == rows.dtype == np.float64
            and base.flags.c_contiguous
            and base.flags.writeable
            and base.ndim == 2
            and base.shape[1] == k
            and len(base) >= t + h
            and rows.shape == (t, k)
            and rows.__array_interface__["data"][0] == base.__array_interface__["data"][0]
            and rows.strides == base.strides
        )
        if not fits:
            return self.lift_stacked(rows, more)
        out = base[: t + h]
        out[t:] = more
        bt = self.basis.T
        tmp = np.empty((min(block, len(out)), k))
        for lo in range(0, len(out), block):
            part = out[lo : lo + block]
            got = tmp[: len(part)]
            np.matmul(part, bt, out=got)
            part[...] = got
        out *= self.scale
        out += self.center
        return out

    def lift_vectors(self, vectors: np.ndarray) -> np.ndarray:
        """Map direction vectors ``(..., r)`` to input space (no scaling)."""
        return vectors @ self.basis.T


def validate(points: np.ndarray, d: int) -> np.ndarray:
    """Check shape, finiteness and ``d``; return a float64 copy.

    Raises
    ------
    InputError
        With a sentence saying what to change.
    """
    try:
        pts = np.array(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"points must be a numeric (n, k) array: {exc}") from None
    if pts.ndim != 2:
        raise InputError(f"points must be a 2-D array of shape (n, k); got {pts.ndim}-D shape {pts.shape}")
    n, k = pts.shape
    if k < 2:
        raise InputError(f"points must have at least 2 coordinates (k >= 2); got k = {k}")
    if not isinstance(d, (int, np.integer)) or isinstance(d, bool):
        raise InputError(f"d must be an integer; got {d!r}")
    if not 1 <= d <= k - 1:
        raise InputError(f"d must be between 1 and k-1 = {k - 1} for points in R^{k}; got d = {d}")
    bad = ~np.isfinite(pts).all(axis=1)
    if bad.any():
        rows = np.flatnonzero(bad)
        raise InputError(
            f"{bad.sum()} point(s) contain NaN or infinity (the first is row {rows[0]} of the array, "
            "counting from 0); remove them"
        )
    if n < k + 2:
        raise InputError(f"too few points: {n}; points in R^{k} need at least {k + 2} (k + 2) for a reconstruction")
    return pts


#: Largest absolute coordinate accepted: every quantity the pipeline derives
#: in input units (bounding points at 4x the radius, far Voronoi vertices,
#: sums of squares in R^k) must stay finite.
MAX_ABS_COORD = 1e305


def prescale(pts: np.ndarray) -> float:
    """A power of two ``s`` such that ``pts / s`` has largest absolute value in [0.5, 1).

    Dividing by a power of two only changes exponents, so it is exact (short
    of subnormal numbers); squared distances of ``pts / s`` neither overflow
    nor underflow.

    Raises
    ------
    InputError
        When the largest absolute coordinate is 0 (every point at the origin)
        or above :data:`MAX_ABS_COORD`.
    """
    top = float(np.abs(pts).max())
    if top == 0.0:
        raise InputError("all points coincide; nothing to reconstruct")
    if top > MAX_ABS_COORD:
        raise InputError(
            f"coordinates up to {top:.3g} are too large to work with (the limit is {MAX_ABS_COORD:.0e}: "
            "derived points lie a few radii away); divide the data by a constant first"
        )
    return power_of_two_above(top)


def merge_duplicates(pts: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Merge points closer than ``tol * spacing``.

    Returns
    -------
    input_index : ndarray of shape (n_in,)
        Group of each input row, numbered in order of first appearance.
    point_input : ndarray of shape (n,)
        First input row of each group.
    spacing : float
        Median nearest-neighbour distance among distinct points.
    """
    return _merged(_spatial_tree(pts), tol)[:3]


def _spatial_tree(pts: np.ndarray) -> cKDTree:
    """The k-d tree of :func:`spatial_order` (leaves of SPATIAL_LEAF points, split at sliding midpoints).

    :func:`merge_duplicates` asks its distances of the same tree: they do not depend on the tree's shape, and
    this one builds in half the time of scipy's default balanced tree (300,000 torus points: 0.06 s against
    0.11 s), and where nothing merges its leaf order is the spatial order, without a second tree.
    """
    return cKDTree(pts, leafsize=SPATIAL_LEAF, balanced_tree=False, compact_nodes=False)


def _merged(tree: cKDTree, tol: float) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
    """:func:`merge_duplicates` on ``tree``'s points, and each point's nearest-other distance (in its units)."""
    pts = tree.data
    # median NN distance ignoring exact duplicates: the nearest other point,
    # and for points with an exact copy the nearest positive distance among 7
    first_pos = nearest_other(tree)
    copies = np.flatnonzero(first_pos == 0)
    if len(copies):
        nz = tree.query(pts[copies], k=min(len(pts), 8), workers=-1)[0][:, 1:]
        first_pos[copies] = np.where(nz > 0, nz, np.inf).min(axis=1)
        many = copies[~np.isfinite(first_pos[copies])]
        if len(many):  # 8 or more copies of a point (a file that repeats its rows): ask the distinct points
            distinct = np.unique(pts, axis=0)
            if len(distinct) > 1:
                first_pos[many] = cKDTree(distinct).query(pts[many], k=2, workers=-1)[0][:, 1]
    if not np.isfinite(first_pos).any() or not (first_pos > 0).any():
        raise InputError("all points coincide; nothing to reconstruct")
    spacing = float(np.median(first_pos[np.isfinite(first_pos)]))
    pairs = tree.query_pairs(tol * spacing, output_type="ndarray")
    n = len(pts)
    if len(pairs) == 0:
        idx = np.arange(n)
        return idx, idx.copy(), spacing, first_pos
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    # renumber groups by first appearance
    _, first = np.unique(labels, return_index=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    input_index = rank[labels]
    point_input = np.sort(first)
    return input_index, point_input, spacing, first_pos


def spatial_order(pts: np.ndarray) -> np.ndarray:
    """A permutation listing nearby points near each other (k-d tree leaf order).

    Every later stage gathers rows of per-sample arrays through Delaunay
    simplices and faces; with samples numbered along space those gathers
    stay in cache (at 300,000 torus points the whole run takes 17% less
    than in a random input order).  Deterministic for given coordinates.
    """
    if len(pts) <= SPATIAL_LEAF:
        return np.arange(len(pts))
    return np.asarray(_spatial_tree(pts).indices, dtype=np.int64)


def prepare_points(
    points: np.ndarray,
    d: int,
    *,
    merge_tol: float = DEFAULT_MERGE_TOL,
    joggle: float = DEFAULT_JOGGLE,
    seed: int = 0,
) -> PreparedPoints:
    """Validate, merge, normalise and joggle a sample for Qhull.

    Parameters
    ----------
    points : array_like of shape (n_in, k)
    d : int
        Intrinsic dimension, ``1 <= d <= k - 1``.
    merge_tol : float
        Points closer than ``merge_tol * spacing`` are merged.
    joggle : float
        Relative size (of the spacing) of the deterministic perturbation.
        0 disables it.
    seed : int
        Seed of the joggle.

    Raises
    ------
    InputError
        Bad values, too few distinct points, or an affine hull of dimension
        ``<= d``.
    """
    pts = validate(points, d)
    n_in, k = pts.shape
    unit = prescale(pts)  # exact power of two; everything below works on pts / unit
    tree = _spatial_tree(pts / unit)
    input_index, point_input, spacing, first_pos = _merged(tree, merge_tol)
    spacing *= unit
    # order[i]: sample i's rank by first appearance; where nothing merged, the same tree's leaves give it
    merged = len(point_input) < n_in
    order = (
        spatial_order(pts[point_input] / unit)
        if merged or n_in <= SPATIAL_LEAF
        else np.asarray(tree.indices, dtype=np.int64)
    )
    del tree
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    input_index = rank[input_index]
    point_input = point_input[order]
    uniq = pts[point_input]
    small = uniq / unit
    n = len(uniq)
    if n < k + 2:
        raise InputError(f"only {n} distinct points remain after merging duplicates; need at least {k + 2} in R^{k}")
    center_small = small.mean(axis=0)
    centred = small - center_small
    center = center_small * unit
    # affine hull
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    rank = int((sv > sv[0] * 1e-9).sum())
    if rank <= d:
        raise InputError(
            f"the points span only a {rank}-dimensional affine subspace, so they cannot sample "
            f"a closed {d}-manifold; check d (got d = {d})"
        )
    basis = vt[:rank].T if rank < k else np.eye(k)
    local = centred @ basis
    scale_small = float(np.sqrt((local**2).sum(axis=1).max()))
    work = local / scale_small
    scale = scale_small * unit
    jog = 0.0
    if joggle > 0:
        rng = np.random.default_rng(seed)
        jog = joggle * spacing
        # relative size computed from unit-free quantities (no underflow near 1e-300)
        # drawn in order of first appearance, so a sample's joggle does not
        # depend on the spatial numbering
        noise = rng.uniform(-1.0, 1.0, size=work.shape)[order]
        work = work + noise * (joggle * (spacing / unit) / scale_small)
    return PreparedPoints(
        points=uniq,
        input_index=input_index,
        point_input=point_input,
        center=center,
        scale=scale,
        basis=basis,
        work=work,
        spacing=spacing,
        joggle=jog,
        # where nothing merged, the merging's own distances are those of the samples (in the new order)
        nearest=None if merged else first_pos[point_input] * unit,
    )
