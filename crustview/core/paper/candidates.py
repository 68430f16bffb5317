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

from ..delaunay.faces import enumerate_faces, sort_rows  # noqa: F401 - part of this module's API
from ..result import fold_columns
from ..util.parallel import chunks, run_in_order
from .cocone2 import codim2_scores, task_cells
from .conemin import lean_bound, over_cell
from .dualcells import CellFaces
from .exactmin import exact_min as _exact_min
from .literal import _orthonormal, literal_angles  # noqa: F401 - literal_angles is part of this module's API

try:  # codimension 1's segment ends in compiled code (setup.py builds it; numpy does the same without it)
    from ..delaunay import _segments as _native_segments
except ImportError:  # pragma: no cover - depends on the build
    _native_segments = None
try:  # codimension 2's vertex minima and certificates likewise (see .cocone2)
    from ..delaunay import _cellpass as _native_cellpass
except ImportError:  # pragma: no cover - depends on the build
    _native_cellpass = None

#: Cells with more vertices skip the (k-d)-subset enumeration in codim >= 3.
MAX_SUBSET_VERTICES = 12
#: Cell vertices per chunk of faces scored at once (keeps temporaries in cache).
CHUNK_CELL_VERTICES = 1 << 18
#: Cocone scores below this are exact; larger ones are only known to be >= it.
SCORE_LIMIT = np.pi / 4


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
    workers: int | None = None,
    minimum: np.ndarray | None = None,
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
    progress : callable(fraction), optional
        Called after each chunk of faces, in the calling thread (it may
        raise to cancel: chunks not started are dropped).
    workers : int, optional
        Threads scoring chunks of faces (default :data:`crustview.core.util.parallel.WORKERS`).
        The result does not depend on it.
    minimum : ndarray of shape (f,), optional
        Filled with each face's smallest angle (the ``cocone`` test's verdict) by the threads that
        score the faces, while their rows are in cache; the same values as the reduction afterwards.

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
    tasks = []
    # the cells' own edges/polygons replace subset enumeration where known (see _score_chunk)
    own_faces = simplices is not None and m in (2, 3)
    compiled = m == 2 and _native_cellpass is not None and work.dtype == normals.dtype == centres.dtype == np.float64
    nv_all = None if compiled else np.diff(cell_ptr)  # (the compiled grouping reads the pointers)
    sizes = np.unique(nv_all[:: max(1, f // 4096)]) if nv_all is not None and f else []
    if len(sizes) == 1 and (nv_all == sizes[0]).all():  # every cell a segment (codimension 1): plain slices
        groups = [(int(sizes[0]), None)]
    elif f:
        groups = size_groups(cell_ptr, nv_all)
    else:
        groups = []
    for nv, sel in groups:
        subsets = [] if own_faces and nv > m + 1 else _boundary_subsets(nv, m)
        # a slice needs no gathers of faces and pointers, and no scatter of the result
        tasks += [
            (nv, c if sel is None else sel[c], subsets)
            for c in chunks(f if sel is None else len(sel), CHUNK_CELL_VERTICES // nv)
        ]
    # the exact steps' k-d tree and tangent bases; codimension 1's segments need neither (segment_sin2)
    segments_only = m == 1 and all(nv == 2 for nv, _ in groups)
    tree = None if segments_only else cKDTree(work)
    # contiguous: gathers from a strided view of the Q factor take 20x longer
    tangents = None if segments_only else np.ascontiguousarray(np.linalg.qr(normals, mode="complete")[0][:, :, m:])
    if workers is None and len(cell_simplices) < CHUNK_CELL_VERTICES:  # one chunk's worth: threads only add overhead
        workers = 1

    if compiled:
        # the compiled vertex pass per chunk, then the exact step in large batches (same values)
        args = (work, normals, tangents, centres, faces, cell_ptr, cell_simplices, simplices, tasks, tree)
        return codim2_scores(_native_cellpass, *args, np.sin(limit), workers, progress, minimum)

    out = np.zeros((f, dp1))

    def score(task: tuple) -> tuple[np.ndarray | slice, np.ndarray]:
        # (each task's rows are its own: no two threads write the same rows of out or minimum)
        nv, sel, subsets = task
        fc, cell_ids = task_cells(faces, cell_ptr, cell_simplices, nv, sel)
        values = _score_chunk(work, normals, tangents, centres, fc, cell_ids, simplices, subsets, tree, limit)
        if minimum is not None:  # rows of this chunk only: no other thread writes them
            if isinstance(sel, slice):
                fold_columns(np.minimum, values, minimum[sel])
            else:
                low = np.empty(len(values))
                fold_columns(np.minimum, values, low)
                minimum[sel] = low
        if isinstance(sel, slice):  # its own rows: written on the worker's core, not the caller's
            out[sel] = values
        return sel, values

    done = 0
    for sel, values in run_in_order(score, tasks, workers):
        if not isinstance(sel, slice):
            out[sel] = values
        done += len(values)
        if progress is not None:
            progress(done / max(f, 1))
    return out


def size_groups(cell_ptr: np.ndarray, nv_all: np.ndarray | None = None) -> list[tuple[int, np.ndarray]]:
    """The faces grouped by the size of their dual cell: ``(size, rows)``, sizes and rows increasing.

    A stable sort by size: the compiled counting sort where it is built (one pass to count, one to
    place: 0.2 s less than numpy's radix sort and gather on the 5.2 million faces of the 10,000-point
    Klein bottle), else numpy's stable argsort of ``nv_all`` (``np.diff(cell_ptr)``, computed if not
    given); the same groups either way.
    """
    if _native_cellpass is not None and hasattr(_native_cellpass, "size_groups") and cell_ptr.dtype == np.int64:
        order_b, sizes_b, counts_b = _native_cellpass.size_groups(np.ascontiguousarray(cell_ptr))
        order = np.frombuffer(order_b, np.int64)
        ends = np.cumsum(np.frombuffer(counts_b, np.int64))
        sizes = np.frombuffer(sizes_b, np.int64)
        return [(int(v), order[e - c : e]) for v, c, e in zip(sizes, np.diff(ends, prepend=0), ends, strict=True)]
    if nv_all is None:
        nv_all = np.diff(cell_ptr)
    # numpy's radix sort on 16-bit sizes, one pass instead of one scan per size
    order = np.argsort(nv_all.astype(np.int16) if nv_all.max() < 2**15 else nv_all, kind="stable")
    ordered = nv_all[order]
    starts = np.flatnonzero(ordered[1:] != ordered[:-1]) + 1
    return [(int(part[0]), sel) for part, sel in zip(np.split(ordered, starts), np.split(order, starts), strict=True)]


def _score_chunk(
    work: np.ndarray,
    normals: np.ndarray,
    tangents: np.ndarray,
    centres: np.ndarray,
    fc: np.ndarray,
    cell_ids: np.ndarray,
    simplices: np.ndarray | None,
    subsets: list[np.ndarray],
    tree: cKDTree,
    limit: float,
) -> np.ndarray:
    """Cocone angles (F, d + 1) of a chunk of faces whose cells all have ``nv`` vertices."""
    nv = cell_ids.shape[1]
    m = normals.shape[2]
    sin_lim = np.sin(limit)
    if m == 1 and nv == 2:
        return _score_segments(work, normals, centres, fc, cell_ids, limit)
    # the cells' own edges/polygons replace subset enumeration where known
    use_cells = simplices is not None and m in (2, 3) and nv > m + 1
    if use_cells:
        subsets = []
    cell_faces = CellFaces(fc, simplices, cell_ids, len(work), m) if use_cells else None
    cells = np.take(centres, cell_ids, axis=0)  # (F, nv, r)
    out = np.empty(fc.shape)
    r = work.shape[1]
    # coordinates as contiguous (F, nv) planes: the per-vertex products below
    # are whole-array operations instead of batched matmul/einsum on tiny axes
    cells_t = np.ascontiguousarray(cells.transpose(2, 0, 1))  # (r, F, nv)
    for a in range(fc.shape[1]):
        s = np.take(work, fc[:, a], axis=0)
        nrm = np.take(normals, fc[:, a], axis=0)
        nrm_t = np.ascontiguousarray(nrm.transpose(1, 2, 0))  # (r, m, F)
        x_t = cells_t - s.T[:, :, None]  # (r, F, nv)
        xsq = x_t[0] * x_t[0]
        for q in range(1, r):
            xsq += x_t[q] * x_t[q]
        np.maximum(xsq, 1e-300, out=xsq)
        xlen = np.sqrt(xsq)
        xn_t = []  # N_s^T x, one (F, nv) plane per normal direction
        for j in range(m):
            dot = x_t[0] * nrm_t[0, j][:, None]
            for q in range(1, r):
                dot += x_t[q] * nrm_t[q, j][:, None]
            xn_t.append(dot)
        num = xn_t[0] * xn_t[0]
        for j in range(1, m):
            num += xn_t[j] * xn_t[j]
        best = over_cell(np.minimum, num / xsq)
        # (1) cheap certificate: every cell point leans to one normal side
        unit = np.stack([dot / xlen for dot in xn_t], axis=-1)  # (F, nv, m)
        lean = lean_bound(unit, iterations=0)
        if m >= 3:  # exact minima are costly here: tighten the bound first
            weak = np.flatnonzero(lean < sin_lim)
            lean[weak] = np.maximum(lean[weak], lean_bound(unit[weak]))
        certified = lean >= sin_lim
        todo = np.flatnonzero(~certified)
        best = np.where(certified, lean**2, best)
        if len(todo):
            best[todo] = _exact_min(
                x_t[:, todo].transpose(1, 2, 0),
                nrm[todo],
                np.take(tangents, fc[todo, a], axis=0),
                np.take(work, fc[todo], axis=0),
                s[todo],
                best[todo],
                subsets,
                m,
                tree,
                sin_lim**2,
                cell_faces,
                todo,
            )
        out[:, a] = np.arcsin(np.sqrt(np.clip(best, 0.0, 1.0)))
    return out


def _score_segments(
    work: np.ndarray, normals: np.ndarray, centres: np.ndarray, fc: np.ndarray, cell_ids: np.ndarray, limit: float
) -> np.ndarray:
    """:func:`_score_chunk` for codimension 1, where every dual cell is a segment.

    The same steps (vertex minimum, one-sided certificate, exact minimum on
    the rest) on one array per coordinate instead of (F, 2, r) blocks: the
    normal is a single vector, so the certificate's direction is a sign, and
    the exact minimum over a segment follows from its two ends
    (:func:`segment_sin2`): no cone minimum, tangent basis or k-d tree query.
    """
    sin_lim = np.sin(limit)
    if _native_segments is not None and work.dtype == normals.dtype == centres.dtype == np.float64:
        out = _segment_sin2_native(work, normals, centres, fc, cell_ids, sin_lim)
    else:
        out = np.empty(fc.shape)
        for a, (best, lean) in enumerate(_segment_ends(work, normals, centres, fc, cell_ids)):
            out[:, a] = segment_sin2(best, lean, sin_lim)
    return np.arcsin(np.sqrt(np.clip(out, 0.0, 1.0, out=out), out=out), out=out)


def segment_sin2(best: np.ndarray, lean: np.ndarray, sin_lim: float) -> np.ndarray:
    """The exact minimum of sin^2 angle(y - s, AT_s) over a dual segment, from its two ends.

    Seen from ``s``, the points of a segment not through ``s`` sweep an arc of
    a great circle of less than pi, on which ``n . u = A cos(phi - phi0)``.
    Where the ends lie on one side of the tangent plane (same sign of
    ``n . x``) the cosine keeps its sign on the arc and is concave there, so
    its smallest magnitude is at an end: the minimum is ``best``, the ends'
    smaller value.  Where they lie on opposite sides the segment crosses the
    plane and the minimum is 0.  (A segment through ``s`` itself would score 0 too; a
    Voronoi edge of a face never passes through the face's own vertices.)  ``lean`` (the one-sided bound of
    :func:`_segment_ends`) tells the cases apart: it is the smaller of the
    ends' signed sines, signed by their side, so it is positive when both ends
    are on one side, and 0 or below when the segment crosses (or touches) the
    plane.  Pairs with ``lean >= sin_lim`` keep ``lean ** 2`` as before (their
    angle is only reported as at least the limit).

    Parameters
    ----------
    best, lean : ndarray of shape (F,)
        From :func:`_segment_ends` (or its compiled twin) for one face vertex.
    sin_lim : float
        ``sin(limit)``.

    Returns
    -------
    ndarray of shape (F,)
        sin^2 of the cocone angle (not clipped).
    """
    return np.where(lean >= sin_lim, lean**2, np.where(lean <= 0.0, 0.0, best))


def _segment_ends(
    work: np.ndarray, normals: np.ndarray, centres: np.ndarray, fc: np.ndarray, cell_ids: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per face vertex a: (sin^2 at the nearer end of the dual segment, one-sided bound of sin).

    Coordinates as contiguous rows (r, F): gather rows, transpose the small
    chunk; the products then run on contiguous memory.  :mod:`._segments`
    does the same arithmetic in compiled code.
    """
    r = work.shape[1]
    c0 = np.take(centres, cell_ids[:, 0], axis=0).T.copy()
    c1 = np.take(centres, cell_ids[:, 1], axis=0).T.copy()
    out = []
    for a in range(fc.shape[1]):
        s = np.take(work, fc[:, a], axis=0)
        nr = np.take(normals, fc[:, a], axis=0)[:, :, 0].T.copy()
        x0, x1 = c0 - s.T, c1 - s.T  # (r, F)
        p0 = x0[0] * nr[0]
        p1 = x1[0] * nr[0]
        q0 = x0[0] * x0[0]
        q1 = x1[0] * x1[0]
        for c in range(1, r):
            p0 += x0[c] * nr[c]
            p1 += x1[c] * nr[c]
            q0 += x0[c] * x0[c]
            q1 += x1[c] * x1[c]
        np.maximum(q0, 1e-300, out=q0)
        np.maximum(q1, 1e-300, out=q1)
        best = np.minimum(p0 * p0 / q0, p1 * p1 / q1)
        u0, u1 = p0 / np.sqrt(q0), p1 / np.sqrt(q1)
        side = u0 + u1
        side /= np.maximum(np.abs(side), 1e-300)
        out.append((best, np.minimum(u0 * side, u1 * side)))
    return out


def _segment_sin2_native(
    work: np.ndarray, normals: np.ndarray, centres: np.ndarray, fc: np.ndarray, cell_ids: np.ndarray, sin_lim: float
) -> np.ndarray:
    """:func:`segment_sin2` of :func:`_segment_ends`, (F, w), in one pass of :mod:`._segments` (bit for bit)."""
    f, w = fc.shape
    raw = _native_segments.sin2(*_segment_args(work, normals, centres, fc, cell_ids), float(sin_lim))
    return np.frombuffer(raw, dtype=np.float64).reshape(f, w)


def _segment_args(work: np.ndarray, normals: np.ndarray, centres: np.ndarray, fc: np.ndarray, cell_ids: np.ndarray):
    """The arrays and sizes :mod:`._segments` takes, contiguous and typed."""
    return (
        np.ascontiguousarray(work),
        np.ascontiguousarray(normals),
        np.ascontiguousarray(centres),
        np.ascontiguousarray(fc, dtype=np.int64),
        np.ascontiguousarray(cell_ids, dtype=np.int64),
        work.shape[1],
        fc.shape[1],
    )


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
