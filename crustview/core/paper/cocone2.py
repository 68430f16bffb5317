"""Codimension 2's cocone scores: the compiled vertex pass, then the exact step in large batches.

:func:`.candidates.cocone_angles` scores faces in chunks of equal cell size.
In codimension 2 the compiled :mod:`._cellpass` settles each chunk's
(face, vertex) pairs from the cell's vertices and the one-sided certificate
without the GIL; about 1 % of the pairs (the 10,000-point Klein bottle) are
left for :func:`.exactmin.exact_min`.  Run per chunk and per face vertex,
that step got a few hundred pairs per call, and numpy's fixed cost per
operation was most of its time, with the GIL held.  Here the chunks only
collect the pairs left; the exact step then runs on all of one cell size's
pairs at once, in batches of :data:`EXACT_BATCH`, on the thread pool.

Every pair's value is computed from the same arrays, in the same memory
layout, by the same operations as the chunk-wise step (each row of the
exact step depends on its own row only: batched solves, row reductions, k-d
tree queries, per-face minima over the cell's edges), so the scores are
equal bit for bit; ``tests/test_core_parallel.py`` compares them with the
plain numpy path.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

from ..result import fold_columns
from ..util.parallel import chunks, run_in_order
from .dualcells import CellFaces
from .exactmin import exact_min

#: (face, vertex) pairs per call of the exact step.
EXACT_BATCH = 1 << 14
#: Share of the progress reported by the vertex pass (the exact step reports the rest).
PASS_SHARE = 0.9


def task_cells(
    faces: np.ndarray, cell_ptr: np.ndarray, cell_simplices: np.ndarray, nv: int, sel: np.ndarray | slice
) -> tuple[np.ndarray, np.ndarray]:
    """The faces of one chunk of Algorithm 2's work and the ``nv`` cells of each one's dual cell.

    ``sel`` is a slice (faces with consecutive rows) or the rows themselves.
    """
    if isinstance(sel, slice):
        fc, starts = faces[sel], cell_ptr[sel]
    else:
        fc, starts = np.take(faces, sel, axis=0), np.take(cell_ptr, sel)
    return fc, np.take(cell_simplices, starts[:, None] + np.arange(nv))


def codim2_scores(
    native,  # noqa: ANN001 - the compiled module crustview.core.delaunay._cellpass
    work: np.ndarray,
    normals: np.ndarray,
    tangents: np.ndarray,
    centres: np.ndarray,
    faces: np.ndarray,
    cell_ptr: np.ndarray,
    cell_simplices: np.ndarray,
    simplices: np.ndarray | None,
    tasks: list[tuple],
    tree: cKDTree,
    sin_lim: float,
    workers: int | None,
    progress: Callable[[float], None] | None,
    minimum: np.ndarray | None = None,
) -> np.ndarray:
    """Cocone angles ``(f, d + 1)`` of every face, codimension 2 (see :func:`.candidates.cocone_angles`).

    Parameters
    ----------
    native : module
        :mod:`crustview.core.delaunay._cellpass`.
    work, normals, tangents, centres
        Delaunay vertices ``(n_all, r)``, normals ``(n, r, 2)``, tangent
        bases ``(n, r, d)`` and Voronoi vertices ``(t, r)``, float64.
    faces, cell_ptr, cell_simplices
        From :func:`.candidates.enumerate_faces`.
    simplices : ndarray of shape (t, r + 1) or None
        The Delaunay simplices: the cells' true edges (see :mod:`.dualcells`).
    tasks : list of (nv, slice or ndarray, subsets)
        Chunks of faces whose cells have ``nv`` vertices, as
        :func:`.candidates.cocone_angles` builds them.
    tree : cKDTree
        Of ``work``.
    sin_lim : float
        ``sin(limit)``: pairs certified at or above it keep the bound.
    workers : int or None
        Threads (the result does not depend on it).
    progress : callable(fraction), optional
        Called in this thread after each chunk and each exact batch.
    minimum : ndarray of shape (f,), optional
        Filled with each face's smallest angle (the ``cocone`` test's), block by block as the angles are
        made.

    Returns
    -------
    ndarray of shape (f, d + 1), radians
    """
    f, w = faces.shape
    m = normals.shape[2]
    arrays = tuple(np.ascontiguousarray(a) for a in (work, normals, centres))
    sq = np.zeros((f, w))  # sin^2 of the scores until the end

    # the compiled pass also gathers the chunk's faces and cells and writes its rows of sq (int32 owners)
    whole = (
        cell_simplices.dtype == np.int32
        and faces.dtype == np.int64
        and cell_ptr.dtype == np.int64
        and all(a.flags.c_contiguous for a in (faces, cell_ptr, cell_simplices))
    )

    def vertex_pass(task: tuple) -> tuple:
        nv, sel, _ = task
        if whole:
            rows = (
                np.arange(sel.start, sel.stop, dtype=np.int64)
                if isinstance(sel, slice)
                else np.ascontiguousarray(sel, np.int64)
            )
            args = (*arrays, faces, cell_ptr, cell_simplices, rows, sq, work.shape[1], m, w, nv, sin_lim)
            left_rows, left_pos = native.cellpass_rows(*args)
            return len(rows), [(np.frombuffer(left_rows, np.int64), np.frombuffer(left_pos, np.int8))]
        fc, cell_ids = task_cells(faces, cell_ptr, cell_simplices, nv, sel)
        fc64 = np.ascontiguousarray(fc, dtype=np.int64)
        ids64 = np.ascontiguousarray(cell_ids, dtype=np.int64)
        best_b, lean_b = native.cellpass(*arrays, fc64, ids64, work.shape[1], m, w, nv)
        best = np.frombuffer(best_b, dtype=np.float64).reshape(len(fc), w)
        lean = np.frombuffer(lean_b, dtype=np.float64).reshape(len(fc), w)
        certified = lean >= sin_lim
        sq[sel] = np.where(certified, lean**2, best)  # rows of this chunk only: no other thread writes them
        rows = np.arange(len(fc)) if isinstance(sel, slice) else sel
        if isinstance(sel, slice):
            rows = rows + sel.start
        # the pairs left, vertex by vertex (as the chunk-wise step visits them)
        left = [(rows[t], np.full(len(t), a, np.int8)) for a in range(w) for t in [np.flatnonzero(~certified[:, a])]]
        return len(fc), left

    # per cell size: the rows and vertex positions of the pairs the vertex pass left
    pending: dict[int, list] = {}
    subsets_of: dict[int, list] = {}
    done = 0
    for task, (count, left) in zip(tasks, run_in_order(vertex_pass, tasks, workers)):
        nv = task[0]
        pending.setdefault(nv, []).extend(left)
        subsets_of[nv] = task[2]
        done += count
        if progress is not None:
            progress(PASS_SHARE * done / max(f, 1))

    batches = []
    for nv, parts in pending.items():
        rows = np.concatenate([p[0] for p in parts])
        pos = np.concatenate([p[1] for p in parts])
        for lo in range(0, len(rows), EXACT_BATCH):
            batches.append((nv, rows[lo : lo + EXACT_BATCH], pos[lo : lo + EXACT_BATCH]))
    use_cells = simplices is not None

    def exact(batch: tuple) -> np.ndarray:
        nv, rows, pos = batch
        fc = np.take(faces, rows, axis=0)
        cell_ids = np.take(cell_simplices, np.take(cell_ptr, rows)[:, None] + np.arange(nv))
        va = fc[np.arange(len(rows)), pos]
        s = np.take(work, va, axis=0)
        # (r, T, nv) contiguous, as the chunk-wise step's x_t[:, todo]: the exact step sees the same strides
        x_t = np.ascontiguousarray(np.take(centres, cell_ids, axis=0).transpose(2, 0, 1)) - s.T[:, :, None]
        cells = use_cells and nv > m + 1
        return exact_min(
            x_t.transpose(1, 2, 0),
            np.take(normals, va, axis=0),
            np.take(tangents, va, axis=0),
            np.take(work, fc, axis=0),
            s,
            sq[rows, pos],
            [] if cells else subsets_of[nv],
            m,
            tree,
            sin_lim**2,
            CellFaces(fc, simplices, cell_ids, len(work), m, once=True) if cells else None,
            np.arange(len(rows)),
        )

    total = sum(len(b[1]) for b in batches)
    done = 0
    for (_, rows, pos), values in zip(batches, run_in_order(exact, batches, workers)):
        sq[rows, pos] = values
        done += len(rows)
        if progress is not None:
            progress(PASS_SHARE + (1 - PASS_SHARE) * done / max(total, 1))

    def angles(part: slice) -> None:
        block = sq[part]
        np.clip(block, 0.0, 1.0, out=block)
        np.sqrt(block, out=block)
        np.arcsin(block, out=block)
        if minimum is not None:
            fold_columns(np.minimum, block, minimum[part])

    for _ in run_in_order(angles, chunks(f, EXACT_BATCH * 16), workers):
        pass
    if progress is not None and not batches:
        progress(1.0)
    return sq
