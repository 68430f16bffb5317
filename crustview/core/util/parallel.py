"""Chunked work on both cores.

Algorithm 2 scores millions of independent faces.  Working on chunks of a
few tens of thousands of faces keeps every temporary array in cache (whole
arrays of hundreds of megabytes spend most of their time in page faults) and
lets two threads run at once: numpy's kernels, fancy indexing and the k-d
tree queries release the GIL.  Results come back in task order, so they are
the same as a serial run, bit for bit.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from typing import TypeVar

T = TypeVar("T")
R = TypeVar("R")

#: Default number of worker threads (the machine's cores, at most 4).
WORKERS = max(1, min(4, os.cpu_count() or 1))


def chunks(n: int, size: int) -> list[slice]:
    """Slices covering ``range(n)`` in pieces of at most ``size``."""
    size = max(1, int(size))
    return [slice(lo, min(n, lo + size)) for lo in range(0, n, size)]


def run_in_order(fn: Callable[[T], R], tasks: Iterable[T], workers: int | None = None) -> Iterator[R]:
    """``map(fn, tasks)`` on a thread pool, yielding results in task order.

    At most ``2 * workers`` tasks are in flight, so results that the caller
    has not consumed yet do not pile up.  If the caller stops early (an
    exception, such as a cancel raised from a progress callback), tasks not
    yet started are dropped and the running ones are waited for.
    """
    workers = WORKERS if workers is None else max(1, int(workers))
    tasks = list(tasks)
    if workers == 1 or len(tasks) <= 1:
        for task in tasks:
            yield fn(task)
        return
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="crustview")
    pending: list = []
    try:
        it = iter(tasks)
        for task in it:
            pending.append(pool.submit(fn, task))
            if len(pending) >= 2 * workers:
                break
        while pending:
            result = pending.pop(0).result()
            nxt = next(it, None)
            if nxt is not None:
                pending.append(pool.submit(fn, nxt))
            yield result
    finally:
        for fut in pending:
            fut.cancel()
        pool.shutdown(wait=True, cancel_futures=True)


def start_in_background(fn: Callable[..., R], *args: object, **kwargs: object) -> Future[R]:
    """Run ``fn(*args, **kwargs)`` on a thread of its own while the caller goes on.

    For a compiled step that releases the GIL (the face lists of Algorithm 2)
    beside a stage that leaves the second core idle (Algorithm 1).  The
    result, or the exception ``fn`` raised, comes from ``.result()``; the
    thread ends with ``fn``.

    Returns
    -------
    concurrent.futures.Future
    """
    pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="crustview-bg")
    try:
        return pool.submit(fn, *args, **kwargs)
    finally:
        pool.shutdown(wait=False)
