"""Compare a reconstruction with a ground-truth mesh on the same vertices.

The mesh's faces are given as rows of *input* points; duplicate merging
(:mod:`crustview.core.prepare`) maps them to samples through ``input_index``.
A mesh face counts as **recovered** when M_S has a simplex with exactly the
same samples; an M_S simplex that is no mesh face is **extra**.

**Hausdorff distance, sampled.**  Both complexes are sampled densely: every
d-simplex on a regular barycentric grid whose step along each edge is at
most ``step``.  The directed distance from A to B is estimated as the largest
distance from a sample of A to the nearest sample of B (a k-d tree).  If every
point of a simplex lies within ``delta`` of the simplex's grid points (Jung's
theorem: ``delta = longest sub-simplex edge * sqrt(d / (2 (d + 1)))``), the
true directed distance lies in ``[estimate - delta_B, estimate + delta_A]``,
so the estimate is off by at most ``error_bound = max(delta_A, delta_B)``.
Identical complexes are sampled identically and give exactly 0.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..errors import InputError
from ..result import TopologyReport
from .meshholes import UnresolvedHoles, pinched_vertices, unresolved_holes
from .topology import analyse

#: Dense samples per complex at most (the step grows to stay below it).
MAX_SAMPLES = 1_500_000
#: Dense samples per complex aimed at by default (4 per simplex for larger complexes).
TARGET_SAMPLES = 100_000


@dataclass(frozen=True)
class HausdorffEstimate:
    """Sampled symmetric Hausdorff distance between two complexes.

    Attributes
    ----------
    distance : float
        max(a_to_b, b_to_a); ``inf`` when exactly one complex is empty, 0 when both are.
    a_to_b, b_to_a : float
        Directed estimates: how far A reaches from B, and B from A.
    error_bound : float
        The true value lies within this of each estimate.
    step : float
        Grid step used along the edges.
    n_samples : tuple of int
        Dense samples drawn on A and on B.
    """

    distance: float
    a_to_b: float
    b_to_a: float
    error_bound: float
    step: float
    n_samples: tuple[int, int]

    def words(self) -> str:
        """The estimate as a reader should take it.

        ``value ± bound``, or, where the bound is half the value or more (a sampled 0 included: a small fold
        can hide between grid points), the upper bound rounded up (a new user read "0.01175 ± 0.042" as a
        misprint, and another "0.0092 ± 0.0102" as saying nothing); "none" when one side is empty.
        """
        if not math.isfinite(self.distance):
            return "none"
        if 2 * self.error_bound >= self.distance:
            return f"at most {_round_up(self.distance + self.error_bound)}"
        return f"{self.distance:.4g} ± {self.error_bound:.2g}"


def _round_up(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits, rounded up (an upper bound stays one)."""
    if x <= 0 or not math.isfinite(x):
        return f"{x:.{digits}g}"
    unit = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return f"{math.ceil(x / unit - 1e-9) * unit:.{digits}g}"


@dataclass(frozen=True)
class MeshComparison:
    """M_S against a ground-truth mesh.

    Attributes
    ----------
    mesh_faces : int
        Distinct mesh d-simplices after mapping to samples.
    collapsed_faces : int
        Mesh faces dropped because duplicate merging made two of their
        vertices one sample.
    result_faces : int
        d-simplices of M_S.
    recovered : int
        Mesh faces that are also M_S simplices (same vertex sets).
    extra : int
        M_S simplices that are not mesh faces.
    mesh_topology, result_topology : TopologyReport
        Closedness, Z/2 Betti numbers, orientability of each.
    hausdorff : HausdorffEstimate
        A = the mesh, B = M_S.
    unresolved : UnresolvedHoles or None
        The mesh's holes below the sample's resolution (a surface mesh with boundary only).
    mesh_pinched : int
        Vertices where two sheets of the mesh meet (:func:`.meshholes.pinched_vertices`; the topology
        report counts them on closed meshes only): such a mesh is no manifold.
    """

    mesh_faces: int
    collapsed_faces: int
    result_faces: int
    recovered: int
    extra: int
    mesh_topology: TopologyReport
    result_topology: TopologyReport
    hausdorff: HausdorffEstimate
    unresolved: UnresolvedHoles | None = None
    mesh_pinched: int = 0

    @property
    def recovered_share(self) -> float:
        """Share of mesh faces recovered, in [0, 1] (1 for an empty mesh)."""
        return self.recovered / self.mesh_faces if self.mesh_faces else 1.0

    @staticmethod
    def genus(top: TopologyReport) -> int | None:
        """Genus of a closed connected orientable surface (b1 / 2), else None."""
        if len(top.betti) != 3 or not top.closed_manifold or top.components != 1 or not top.orientable:
            return None
        return top.betti[1] // 2

    def as_dict(self) -> dict:
        """Plain values for a JSON report."""
        h = self.hausdorff

        def top(t: TopologyReport) -> dict:
            return {
                "closed_manifold": t.closed_manifold,
                "betti": list(t.betti),
                "genus": self.genus(t),
                "orientable": t.orientable,
                "components": t.components,
                "n_simplices": t.n_simplices,
                "boundary_faces": t.boundary_faces,
                "nonmanifold_faces": t.nonmanifold_faces,
            }

        return {
            "mesh_faces": self.mesh_faces,
            "collapsed_faces": self.collapsed_faces,
            "result_faces": self.result_faces,
            "recovered": self.recovered,
            "recovered_share": self.recovered_share,
            "extra": self.extra,
            "mesh": top(self.mesh_topology),
            "result": top(self.result_topology),
            "hausdorff": h.distance,
            "hausdorff_mesh_to_result": h.a_to_b,
            "hausdorff_result_to_mesh": h.b_to_a,
            "hausdorff_error_bound": h.error_bound,
            "hausdorff_method": "sampled: barycentric grids on both complexes, nearest sample by k-d tree",
            "mesh_holes_below_resolution": None
            if self.unresolved is None
            else {
                "count": self.unresolved.count,
                "rim_edges": self.unresolved.edges,
                "longest_sampling_radii": self.unresolved.longest,
                "betti_closed": list(self.unresolved.betti),
            },
        }


def _barycentric_grid(d: int, m: int) -> np.ndarray:
    """Weights (g, d + 1) of the points of a d-simplex whose edge is split into m parts."""
    rows = [c for c in itertools.product(range(m + 1), repeat=d) if sum(c) <= m]
    w = np.array([[m - sum(c), *c] for c in rows], dtype=np.float64)
    return w / m


def dense_samples(points: np.ndarray, simplices: np.ndarray, step: float) -> tuple[np.ndarray, float]:
    """Points on every simplex at grid step <= ``step``, and their covering radius bound.

    Returns
    -------
    samples : ndarray of shape (s, k)
    delta : float
        Every point of the complex lies within ``delta`` of a sample.
    """
    simplices = np.asarray(simplices, dtype=np.int64)
    k = points.shape[1]
    if len(simplices) == 0:
        return np.empty((0, k)), 0.0
    d = simplices.shape[1] - 1
    corners = points[simplices]  # (m, d+1, k)
    if d == 0:
        return corners[:, 0], 0.0
    edges = [np.linalg.norm(corners[:, i] - corners[:, j], axis=1) for i, j in itertools.combinations(range(d + 1), 2)]
    longest = np.max(edges, axis=0)
    parts = np.maximum(1, np.ceil(longest / step)).astype(np.int64)
    out = []
    delta = 0.0
    jung = math.sqrt(d / (2.0 * (d + 1)))
    for m in np.unique(parts):
        sel = parts == m
        w = _barycentric_grid(d, int(m))
        out.append(np.einsum("gv,svk->sgk", w, corners[sel]).reshape(-1, k))
        delta = max(delta, float(longest[sel].max()) / m * jung)
    return np.concatenate(out), delta


def hausdorff(
    points: np.ndarray, a: np.ndarray, b: np.ndarray, *, step: float | None = None, max_samples: int = MAX_SAMPLES
) -> HausdorffEstimate:
    """Sampled symmetric Hausdorff distance between complexes ``a`` and ``b`` on ``points``.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    a, b : ndarray of shape (m_a, d + 1), (m_b, d + 1)
        Simplices as rows of ``points``.
    step : float, optional
        Grid step along edges; default an eighth of the median edge length of
        ``a`` and ``b``, raised until neither complex needs more than
        ``max_samples`` samples.

    Returns
    -------
    HausdorffEstimate
    """
    points = np.asarray(points, dtype=np.float64)
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    if len(a) == 0 or len(b) == 0:
        value = 0.0 if len(a) == len(b) else math.inf
        return HausdorffEstimate(value, value, value, 0.0, 0.0, (0, 0))
    d = a.shape[1] - 1
    if step is None:
        # aim at TARGET_SAMPLES per complex (more for big meshes), never above max_samples
        base = TARGET_SAMPLES if d >= 2 else TARGET_SAMPLES // 5  # curves: far queries cost ~ r / step
        target = min(max_samples, max(base, 4 * max(len(a), len(b))))
        both = np.concatenate([a, b])
        lengths = np.linalg.norm(points[both[:, 0]] - points[both[:, -1]], axis=1)
        step = float(np.median(lengths)) / 8 or 1.0
        for _ in range(8):
            count = max(_grid_count(points, s, step, d) for s in (a, b))
            ratio = (count / target) ** (1.0 / max(d, 1))
            if 0.8 <= ratio <= 1.0 or (ratio < 1.0 and step >= float(lengths.max())):
                break
            step *= ratio * 1.05 if ratio > 1.0 else ratio
    sa, da = dense_samples(points, a, step)
    sb, db = dense_samples(points, b, step)
    a_to_b = _directed(sa, cKDTree(sb))
    b_to_a = _directed(sb, cKDTree(sa))
    return HausdorffEstimate(max(a_to_b, b_to_a), a_to_b, b_to_a, float(max(da, db)), step, (len(sa), len(sb)))


def _directed(samples: np.ndarray, tree: cKDTree, eps: float = 1.0) -> float:
    """Largest nearest-neighbour distance from ``samples`` to ``tree``'s points, exactly.

    A k-d tree search for a far point visits every node in its nearest
    neighbour's ball, which is slow when the answer is many sample spacings
    away.  An approximate search (``eps``: within a factor 1 + eps) is fast;
    only samples whose approximate distance could be the largest are then
    searched exactly, so the maximum is exact.
    """
    if len(samples) == 0 or tree.n == 0:
        return 0.0
    approx = tree.query(samples, eps=eps)[0]
    cand = approx >= approx.max() / (1.0 + eps)
    return float(tree.query(samples[cand])[0].max())


def _grid_count(points: np.ndarray, simplices: np.ndarray, step: float, d: int) -> float:
    """Number of grid points :func:`dense_samples` draws at ``step``: sum of C(m + d, d)."""
    corners = points[simplices]
    longest = np.max(
        [np.linalg.norm(corners[:, i] - corners[:, j], axis=1) for i, j in itertools.combinations(range(d + 1), 2)],
        axis=0,
    )
    m = np.maximum(1, np.ceil(longest / step))
    return float(np.sum(np.prod([m + i for i in range(1, d + 1)], axis=0)) / math.factorial(d))


def _row_set(simplices: np.ndarray) -> np.ndarray:
    srt = np.sort(np.asarray(simplices, dtype=np.int64), axis=1)
    return np.unique(srt, axis=0) if len(srt) else srt


def _count_common(a: np.ndarray, b: np.ndarray) -> int:
    """Rows common to two sets of sorted unique rows."""
    if len(a) == 0 or len(b) == 0:
        return 0
    both = np.concatenate([a, b])
    _, counts = np.unique(both, axis=0, return_counts=True)
    return int((counts == 2).sum())


def compare_complexes(
    points: np.ndarray,
    mesh: np.ndarray,
    result: np.ndarray,
    d: int,
    *,
    result_topology: TopologyReport | None = None,
    collapsed: int = 0,
    step: float | None = None,
) -> MeshComparison:
    """Compare two d-complexes on the same vertex rows ``points``.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    mesh : ndarray of shape (m, d + 1)
        The ground truth (rows of ``points``; duplicates allowed).
    result : ndarray of shape (r, d + 1)
        The reconstruction.
    d : int
    result_topology : TopologyReport, optional
        Reused when given (a reconstruction already has it).
    collapsed : int
        Reported as ``collapsed_faces``.
    step : float, optional
        See :func:`hausdorff`.
    """
    n = len(points)
    mesh_rows = _row_set(np.asarray(mesh, dtype=np.int64).reshape(-1, d + 1))
    res_rows = _row_set(np.asarray(result, dtype=np.int64).reshape(-1, d + 1))
    common = _count_common(mesh_rows, res_rows)
    mesh_top = analyse(mesh_rows, n, d)
    # on a mesh with boundary the report does not count pinches: two sheets at a vertex, no manifold
    surface_with_boundary = d == 2 and mesh_top.boundary_faces > 0 and mesh_top.nonmanifold_faces == 0
    pinched = pinched_vertices(mesh_rows, n) if surface_with_boundary else 0
    return MeshComparison(
        mesh_faces=len(mesh_rows),
        collapsed_faces=int(collapsed),
        result_faces=len(res_rows),
        recovered=common,
        extra=len(res_rows) - common,
        mesh_topology=mesh_top,
        result_topology=result_topology if result_topology is not None else analyse(res_rows, n, d),
        hausdorff=hausdorff(points, mesh_rows, res_rows, step=step),
        unresolved=unresolved_holes(points, mesh_rows, mesh_top) if d == 2 and not pinched else None,
        mesh_pinched=pinched,
    )


def compare_to_mesh(rec, mesh_faces: np.ndarray, *, step: float | None = None) -> MeshComparison:
    """Compare a reconstruction's M_S with mesh faces given as *input* rows.

    Parameters
    ----------
    rec : Reconstruction
    mesh_faces : ndarray of shape (m, d + 1)
        Faces of the ground-truth mesh, indices into ``rec.input_points``
        (quads already split; see :meth:`crustview.meshfiles.mesh.MeshData.simplices`).
    step : float, optional
        See :func:`hausdorff`.

    Raises
    ------
    InputError
        When the faces do not have d + 1 vertices or refer to missing rows.

    Examples
    --------
    >>> import numpy as np
    >>> from crustview.core import reconstruct
    >>> t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    >>> rec = reconstruct(np.c_[np.cos(t), np.sin(t)], d=1)
    >>> ring = np.c_[np.arange(40), (np.arange(40) + 1) % 40]
    >>> c = compare_to_mesh(rec, ring)
    >>> c.recovered_share, c.extra, c.hausdorff.distance
    (1.0, 0, 0.0)
    """
    faces = np.asarray(mesh_faces)
    d = rec.d
    n_in = len(rec.input_points)
    if faces.ndim != 2 or faces.shape[1] != d + 1 or faces.dtype.kind not in "iu":
        raise InputError(
            f"mesh faces must be an integer array of shape (m, {d + 1}) for d = {d}; got shape {faces.shape}"
        )
    if len(faces) and (faces.min() < 0 or faces.max() >= n_in):
        raise InputError(
            f"mesh faces refer to vertex {int(faces.max() if faces.max() >= n_in else faces.min())}, "
            f"but there are {n_in} input points"
        )
    mapped = np.asarray(rec.input_index)[faces.astype(np.int64)]
    srt = np.sort(mapped, axis=1)
    ok = (srt[:, 1:] != srt[:, :-1]).all(axis=1)
    return compare_complexes(
        rec.points, mapped[ok], rec.manifold, d, result_topology=rec.topology, collapsed=int((~ok).sum()), step=step
    )
