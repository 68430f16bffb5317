"""Work that may be needed, begun at once in a helper process on the second core.

The robust extraction's two paths (labelling the Delaunay cells, growing M_S) are pure Python for the most
part: threads would take turns on the interpreter, so the growing path, which only the labelling's result
decides whether to use, runs in a helper process while the labelling runs in this one
(:class:`Speculation`).  When it is not needed the helper is stopped; when it is, its result is taken as it
arrives.  The work is the same function on the same inputs either way, so the result is the same: the
helper only changes *when* it is computed (``tests/test_second_core.py`` compares the two on real runs).

The helper is a fresh interpreter (``python -c``, :func:`_serve`) that imports crustview once and then runs
one job after another, talking over two pipes.  Not :mod:`multiprocessing`: its ``fork`` would copy the
locks of the window's Qt and VTK threads into the child, and its ``spawn`` and ``forkserver`` import the
caller's main script again in the child (running a user's script a second time where it has no
``if __name__ == "__main__"``).  Starting a helper imports crustview (0.6-0.8 s here); :func:`warm` starts
one in the background as soon as a run begins, and a stopped helper is replaced the same way.  A job then
costs the pickling of its arguments and result (``benchmarks/bench_second_core.py`` measures it).

Every failure to start or to hear back from the helper (a killed process, a result that does not pickle,
an exception in the job) makes :meth:`Speculation.result` raise :class:`Lost`; the caller then computes the
result itself, so a failure costs time, never a result.

``CRUSTVIEW_PROCESSES=1`` in the environment turns this off: where every core is already busy (the batch
command's ``-j 2`` workers, the test suite's ``pytest -n 2`` workers) a second process per run only
competes with the others.
"""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
import threading
from collections.abc import Callable
from multiprocessing.connection import Connection
from typing import Any

from ..errors import Cancelled, check_cancel

#: The environment variable that, set to ``1``, keeps every run in its own process.
PROCESSES_ENV = "CRUSTVIEW_PROCESSES"
#: What the helper imports before its first job (so that a job starts without importing it).
PRELOAD = "crustview.core.robust.driver"
#: Seconds between two looks at the helper, the caller's cancel flag and its progress while waiting.
POLL_S = 0.05
#: Smallest change of the job's progress fraction the helper reports (fewer messages, same bar).
PROGRESS_STEP = 0.01

_lock = threading.Lock()
_idle: list[_Helper] = []


class Lost(RuntimeError):
    """The helper could not be started or did not deliver its result (the caller computes it itself)."""


def enabled() -> bool:
    """Whether a second process may be used: two cores or more, and not turned off by the environment."""
    return (os.cpu_count() or 1) >= 2 and os.environ.get(PROCESSES_ENV, "").strip() != "1"


class _Helper:
    """One helper process and its two pipes (jobs in, messages out)."""

    def __init__(self) -> None:
        job_r, job_w = os.pipe()
        out_r, out_w = os.pipe()
        code = f"import sys; from {__name__} import _serve; _serve(int(sys.argv[1]), int(sys.argv[2]))"
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-c", code, str(job_r), str(out_w)],
                pass_fds=(job_r, out_w),
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                close_fds=True,
            )
        except BaseException:
            for fd in (job_r, job_w, out_r, out_w):
                os.close(fd)
            raise
        os.close(job_r)
        os.close(out_w)
        self.jobs = Connection(job_w, readable=False)
        self.out = Connection(out_r, writable=False)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def kill(self) -> None:
        """Kill the process (a job it runs is dropped); a send to it in progress then fails."""
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait()

    def close(self) -> None:
        """Close the pipes (only once no thread sends on them)."""
        self.jobs.close()
        self.out.close()

    def stop(self) -> None:
        """:meth:`kill`, then :meth:`close`."""
        self.kill()
        self.close()


def _take() -> _Helper:
    """An idle live helper, or a new one."""
    with _lock:
        while _idle:
            helper = _idle.pop()
            if helper.alive():
                return helper
            helper.stop()
    return _Helper()


def _give_back(helper: _Helper) -> None:
    with _lock:
        _idle.append(helper)


@atexit.register
def _stop_all() -> None:
    """Stop the idle helpers at exit (a helper also ends by itself when its job pipe closes)."""
    with _lock:
        while _idle:
            _idle.pop().stop()


def warm() -> None:
    """Start an idle helper in the background if there is none (returns at once).

    A run calls it at its start, so the helper has imported crustview by the time the extraction needs it.
    Errors are ignored here: :class:`Speculation` reports them when a helper is asked for.
    """
    if not enabled():
        return
    with _lock:
        if any(h.alive() for h in _idle):
            return

    def start() -> None:
        try:
            _give_back(_Helper())
        except Exception:  # noqa: BLE001 - reported by Speculation when a helper is asked for
            pass

    threading.Thread(target=start, name="crustview-helper-start", daemon=True).start()


class _Reporter:
    """The helper's ``progress``: a job's fraction sent to the caller when it moved :data:`PROGRESS_STEP`."""

    def __init__(self, out: Connection) -> None:
        self.out = out
        self.last = -1.0

    def __call__(self, fraction: float) -> None:
        if abs(fraction - self.last) >= PROGRESS_STEP:
            self.last = fraction
            self.out.send(("progress", float(fraction)))


def _serve(job_fd: int, out_fd: int) -> None:
    """The helper's loop: ``(fn, args, with_progress)`` in; ``("progress", f)`` and ``("done", (ok, x))`` out.

    Python's cyclic collector is off, as the caller's is around the extraction (:func:`.memory.gc_paused`):
    the work builds many long-lived small objects without cycles.  It runs once between two jobs.
    """
    import gc
    import importlib

    jobs = Connection(job_fd, writable=False)
    out = Connection(out_fd, readable=False)
    importlib.import_module(PRELOAD)
    while True:
        try:
            fn, args, with_progress = jobs.recv()
        except (EOFError, OSError):  # the caller is gone, or stopped this helper
            return
        out.send(("started", None))
        gc.disable()
        try:
            if with_progress:
                result: tuple[bool, Any] = (True, fn(*args, progress=_Reporter(out)))
            else:
                result = (True, fn(*args))
        except BaseException as err:  # noqa: BLE001 - any failure goes back to the caller, which recomputes
            result = (False, repr(err))
        try:
            out.send(("done", result))
        except Exception as err:  # noqa: BLE001 - a result that does not pickle
            out.send(("done", (False, f"the result could not be sent back: {err!r}")))
        del result
        gc.enable()
        gc.collect()


class Speculation:
    """``fn(*args)`` begun in a helper process at once; :meth:`result` takes it, :meth:`discard` drops it.

    Parameters
    ----------
    fn : callable
        A module-level function (the helper imports it by name).
    args : tuple
        Its arguments (pickled to the helper).
    with_progress : bool
        Pass ``progress=`` (a callable taking a fraction in [0, 1]) to ``fn``; :meth:`result` relays it.
    """

    def __init__(self, fn: Callable[..., Any], args: tuple, *, with_progress: bool = False) -> None:
        self._helper: _Helper | None = None
        self._error: str | None = None
        self._progress = 0.0
        self._begun = False  # the helper said it has the job
        self._guard = threading.Lock()
        self._dropped = False  # discarded: the starter must not send, and closes what it took
        self._sending = False
        # sent from a thread of its own: sending the arguments waits until the helper reads them, after its
        # imports if it was only just started; the caller goes on
        self._starter = threading.Thread(
            target=self._start, args=(fn, args, with_progress), name="crustview-helper-send", daemon=True
        )
        self._starter.start()

    def _start(self, fn: Callable[..., Any], args: tuple, with_progress: bool) -> None:
        try:
            helper = _take()
        except Exception as err:  # noqa: BLE001 - no helper: result() says so, the caller computes it
            self._error = f"no helper process: {err!r}"
            return
        with self._guard:
            if self._dropped:  # discarded before the job was sent: the helper is as good as new
                _give_back(helper)
                return
            self._helper, self._sending = helper, True
        try:
            helper.jobs.send((fn, args, with_progress))
        except Exception as err:  # noqa: BLE001 - a helper that died or was stopped, or arguments that do not pickle
            self._error = f"the job could not be sent: {err!r}"
        with self._guard:
            self._sending = False
            if self._dropped:  # discard() killed the helper while this thread sent: close its pipes here
                helper.close()

    def result(
        self,
        cancel: object | None = None,
        progress: Callable[[float], None] | None = None,
        *,
        wait_for_start: bool = False,
    ) -> Any:
        """Wait for the helper's result, relaying its progress and checking ``cancel`` every :data:`POLL_S`.

        A helper that has not begun the job yet (it was still importing crustview) is not waited for: the
        job is dropped and :class:`Lost` raised, so that the caller computes it at once; unless
        ``wait_for_start``, which waits for it to begin.

        Raises
        ------
        Lost
            The helper did not start, had not begun, died, or the job failed (the message says which).
        Cancelled
            ``cancel`` was set while waiting (the helper is stopped).
        """
        if wait_for_start:
            self._starter.join()
            self._begun = self._begun or self._error is None
        try:
            if self._starter.is_alive() or self._helper is None or self._error is not None:
                raise Lost(self._error or "the helper had not begun the job (it was still starting)")
            helper = self._helper
            while True:
                if helper.out.poll(0 if not self._begun else POLL_S):
                    try:
                        kind, payload = helper.out.recv()
                    except (EOFError, OSError) as err:  # the helper closed its end: it died
                        code = helper.proc.wait(5)
                        raise Lost(f"the helper process ended (exit code {code}) without a result") from err
                    if kind == "done":
                        break
                    if kind == "started":
                        self._begun = True
                    else:
                        self._progress = payload
                elif not self._begun:
                    raise Lost("the helper had not begun the job (it was still starting)")
                if progress is not None:
                    progress(self._progress)
                check_cancel(cancel)
        except (Cancelled, Lost):
            self.discard()
            raise
        with self._guard:
            self._helper, self._dropped = None, True
        _give_back(helper)
        ok, value = payload
        if not ok:
            raise Lost(f"the job failed in the helper: {value}")
        return value

    def discard(self) -> None:
        """Stop the helper if its job is still running (a new one starts in the background for later runs).

        Returns at once: a send still in progress fails when the helper is killed, and its thread closes
        the pipes.
        """
        with self._guard:
            self._dropped = True
            helper, self._helper = self._helper, None
            sending = self._sending
        if helper is None:
            return
        helper.kill()
        if not sending:
            helper.close()
        warm()
