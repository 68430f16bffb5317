"""Memory housekeeping: freed memory back to the operating system, the collector paused.

numpy frees a temporary array as soon as its last reference goes, but
glibc's allocator keeps arrays below its mmap threshold (which grows to
32 MB as large blocks are freed) in its heaps, and every worker thread has
heaps of its own.  After a stage that made many chunk-sized temporaries on
two threads, hundreds of megabytes can sit free inside the process, and the
next stage's peak comes on top of them.  ``malloc_trim(0)`` returns that
free memory (at the top of each heap and, with ``madvise``, inside it).

Measured on a 300,000-point torus: the peak RSS of a run falls by about
100 MB, and each call takes a few milliseconds.  On other C libraries
(musl, macOS, Windows) :func:`release_free_memory` does nothing.

:func:`small_pages` keeps numpy from asking for transparent huge pages while a run lasts (see there).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import gc
import os
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import lru_cache
from typing import TypeVar

import numpy as np

F = TypeVar("F", bound=Callable)


@lru_cache(maxsize=1)
def _trim():  # noqa: ANN202 - a ctypes function or None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        fn = libc.malloc_trim
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_size_t]
    fn.restype = ctypes.c_int
    return fn


#: Runs of at least this many samples hand freed memory back between their stages
#: (:func:`crustview.core.reconstruct.reconstruct`).  What a stage leaves free grows with the sample: about
#: 330 bytes a sample (the 100 MB measured at 300,000 points), so under 7 MB below this bound, while the
#: call costs 1-2 ms in a process that holds many results (1.5 s over 1,294 calls in the core tests).
TRIM_MIN_POINTS = 20_000


def release_free_memory() -> bool:
    """Return the allocator's free memory to the OS (glibc); True if anything was released."""
    fn = _trim()
    return bool(fn(0)) if fn is not None else False


@contextmanager
def gc_paused() -> Iterator[None]:
    """Suspend Python's cyclic garbage collector for a block, then restore its state.

    The extraction stages build hundreds of thousands of small containers
    (simplex tuples, log entries, steps) that all stay alive.  Each batch of
    allocations triggers a collection that walks every tracked object, so a
    run spends a third of its time collecting garbage that is not there
    (measured: 0.3-0.5 s of a 2.5 s robust extraction on a 43,000-point scan).
    Those structures hold no reference cycles; reference counting frees
    everything they drop.  The collector runs again after the block.
    """
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _hugepage_switch() -> Callable[[bool], bool] | None:
    """The switch of numpy's huge-page advice (``_set_madvise_hugepage``: sets it, returns the old value)."""
    core = getattr(np, "_core", None) or getattr(np, "core", None)
    return getattr(getattr(core, "multiarray", None), "_set_madvise_hugepage", None)


_pages_lock = threading.Lock()
_pages_depth = 0
_pages_before = True


def _leave_numpy_alone() -> bool:
    """Whether the environment asks for numpy's own huge-page setting.

    ``CRUSTVIEW_HUGE_PAGES=1`` (for a kernel where huge pages pay, and to measure the difference), or an
    explicit ``NUMPY_MADVISE_HUGEPAGE`` (numpy's own variable, read at its import: the user chose).
    """
    return os.environ.get("CRUSTVIEW_HUGE_PAGES") == "1" or "NUMPY_MADVISE_HUGEPAGE" in os.environ


class numpy_small_pages:  # noqa: N801 - used as a function: ``with numpy_small_pages():``
    """Run a block with numpy's arrays off the huge-page advice, then restore numpy's setting.

    numpy advises the kernel to back every array of 4 MB or more with transparent huge pages
    (``madvise(MADV_HUGEPAGE)``; numpy's "global state" documentation describes the variable
    ``NUMPY_MADVISE_HUGEPAGE``, read at its import; the switch used here, ``_set_madvise_hugepage``, is the
    private function behind it).  Where the kernel's ``transparent_hugepage/defrag`` policy is ``madvise``
    (this machine's, and a common default) a page fault in such an array compacts memory there and then to
    find a free 2 MB page.  A run allocates its large temporaries afresh in every stage, and the two cores
    then spend their time in the kernel: on the 300,000-point torus the cocone pass took 0.85 s of wall
    time with 0.86 s of system time, against 0.36 s and 0.13 s with 4 KB pages, and the whole run 7.05 s
    against 6.1-6.3 s (``benchmarks/bench_scale.py`` measures it both ways with ``--huge-pages``).  No value
    changes: only the pages under the arrays.

    The advice is numpy's process-wide state: blocks may nest and run on several threads at once, in any
    order; the setting comes back when the last one ends.  Each block decides at its start whether it takes
    part.  Nothing happens where numpy has no such switch, or where the environment asks for numpy's own
    setting (``CRUSTVIEW_HUGE_PAGES=1``, or ``NUMPY_MADVISE_HUGEPAGE`` set at all).
    """

    def __init__(self) -> None:
        self._switch: Callable[[bool], bool] | None = None

    def __enter__(self) -> None:
        global _pages_depth, _pages_before
        switch = _hugepage_switch()
        if switch is None or _leave_numpy_alone():
            return
        with _pages_lock:  # the count and the switch change together, or not at all
            if _pages_depth == 0:
                _pages_before = bool(switch(False))
            _pages_depth += 1
            self._switch = switch

    def __exit__(self, *exc: object) -> None:
        global _pages_depth
        if self._switch is None:
            return
        with _pages_lock:
            _pages_depth -= 1
            if _pages_depth == 0:
                self._switch(_pages_before)
            self._switch = None


def small_pages(func: F) -> F:
    """``func`` run inside :func:`numpy_small_pages` (a decorator)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        with numpy_small_pages():
            return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
