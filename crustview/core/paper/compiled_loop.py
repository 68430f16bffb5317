"""Algorithm 3's loop in C++ (``_prune.cpp``): the steps of :func:`.extraction.extract`, compiled.

The Python loop in :mod:`.extraction` stays the reference; the compiled one
takes the same decisions in the same order from the same tables (the prune
queue, the heap of non-manifold faces, the pair choice by simulated
cascades, the same floating-point operations for every angle), so the
recorded steps, ``removed_at`` and the final complex are equal, not close
(``tests/test_core_extraction_compiled.py`` compares them step by step).
It runs when the extension was built and every opposite vector is finite
(a NaN would make the heap's order depend on how ties are compared).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..steps import RULE_PRUNE, RULE_RESOLVE, Step

if TYPE_CHECKING:
    from .extraction import _Extractor

try:
    from . import _prune
except ImportError:  # pragma: no cover - the extension is optional
    _prune = None

BOUNDARY_REASON = "only one d-simplex left at this face (boundary)"


def available(ex: _Extractor) -> bool:
    """Whether the compiled loop can run on this extractor's tables."""
    return _prune is not None and bool(np.isfinite(ex.u).all())


def run(
    ex: _Extractor,
    first: list[int],
    limit: int,
    *,
    stop_when_sample_lost: bool,
    cancel: object | None,
    progress: Callable[[float], None] | None,
) -> None:
    """Run the loop of :func:`.extraction.extract` on ``ex``: its tables updated, its steps appended.

    Parameters
    ----------
    ex : _Extractor
        Fresh (no step taken yet); ``alive``, ``count``, ``removed_at``,
        ``exposer`` and ``vcount`` are updated in place, ``lost`` and
        ``steps`` set.
    first : list of int
        The facets sharp at the start (:func:`.extraction._initial_sharp`), in order.
    limit : int
        :data:`.extraction.CASCADE_LIMIT`.
    stop_when_sample_lost, cancel, progress
        As in :func:`.extraction.extract`.

    Raises
    ------
    Cancelled
        When ``cancel.is_set()`` answers True at one of the loop's checks.
    """
    from ..errors import Cancelled

    i64 = np.int64
    for name in ("count", "removed_at", "exposer", "vcount"):  # updated in place: they must be these arrays
        arr = getattr(ex, name)
        if arr.dtype != i64 or not arr.flags.c_contiguous:
            setattr(ex, name, np.ascontiguousarray(arr, dtype=i64))
    status, lost, *raw = _prune.extract_loop(
        np.ascontiguousarray(ex.simplices, dtype=i64),
        np.ascontiguousarray(ex.facet_of, dtype=i64),
        np.ascontiguousarray(ex.ptr, dtype=i64),
        np.ascontiguousarray(ex.inc, dtype=i64),
        np.ascontiguousarray(ex.u, dtype=np.float64),
        np.asarray(first, dtype=i64),
        ex.alive,
        ex.count,
        ex.removed_at,
        ex.exposer,
        ex.vcount,
        ex.simplices.shape[1],
        ex.u.shape[2],
        ex.prune_boundary,
        stop_when_sample_lost,
        limit,
        cancel,
        progress,
    )
    ex.lost = None if lost < 0 else int(lost)
    ex.steps = _steps(ex, *raw)
    if status == 1:
        raise Cancelled("reconstruction cancelled")


def _steps(ex: _Extractor, *raw: bytes) -> list[Step]:
    """The :class:`Step` records from the compiled loop's flat arrays (the Python loop's fields and sentences)."""
    rule, facet, keep_a, keep_b, angle, cause, size, rptr, removed = (
        np.frombuffer(b, dtype=np.uint8 if i == 0 else np.float64 if i == 4 else np.int64) for i, b in enumerate(raw)
    )
    n = len(rule)
    if n == 0:
        return []
    taus = [tuple(t) for t in ex.facets[facet].tolist()]
    flat = removed.tolist()
    ptr = rptr.tolist()
    degrees = np.degrees(angle).tolist()
    angles = angle.tolist()
    out = []
    append = out.append
    for idx, (r, ka, kb, cs, m, deg) in enumerate(
        zip(rule.tolist(), keep_a.tolist(), keep_b.tolist(), cause.tolist(), size.tolist(), degrees)
    ):
        gone = tuple(flat[ptr[idx] : ptr[idx + 1]])
        if r == 0:
            why = BOUNDARY_REASON if m == 1 else f"all {m} d-simplices meet within {deg:.1f} deg < 90 deg (sharp)"
            append(Step(idx, RULE_PRUNE, taus[idx], (), gone, angles[idx], why, cause=cs))
        else:
            why = (
                f"{m} d-simplices at this face; kept the pair meeting at "
                f"{deg:.1f} deg (180 = flat), removed {len(gone)}"
            )
            append(Step(idx, RULE_RESOLVE, taus[idx], (ka, kb), gone, angles[idx], why))
    return out
