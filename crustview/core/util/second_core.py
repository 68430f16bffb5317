"""Work that may be needed, begun at once in a helper process on the second core.

The robust extraction's two paths (labelling the Delaunay cells, growing M_S) are pure Python for the most
part: threads would take turns on the interpreter, so the growing path, which only the labelling's result
decides whether to use, runs in a helper process while the labelling runs in this one
(:class:`Speculation`).  When it is not needed the helper is stopped; when it is, its result is taken as it
arrives.  The work is the same function on the same inputs either way, so the result is the same: the
helper only changes *when* it is computed (``tests/test_second_core.py`` compares the two on real runs).

The helper is a fresh interpreter (``python -I -c``, :func:`_serve`) given the caller's ``sys.path``, so that
it imports the crustview the caller runs (it says which, and a helper that imported another is not used); it
imports crustview once and then runs one job after another, talking over two pipes. Not
:mod:`multiprocessing`: its ``fork`` would copy the locks of the window's Qt and VTK threads into the child,
and its ``spawn`` and ``forkserver`` import the caller's main script again in the child (running a user's
script a second time where it has no ``if __name__ == "__main__"``). Starting a helper imports crustview
(0.6-0.8 s here), overlapping the caller's own work; a helper stopped with a job that was not needed is
replaced in the background (:func:`warm`), ready for the next job. A job then costs the pickling of its
arguments and result (``benchmarks/bench_second_core.py`` measures it). A helper whose caller goes away (exit,
crash) ends within a second, even in the middle of a job (at its next Python step); it ignores Ctrl-C, which
is the caller's to handle.

Every failure to start or to hear back from the helper (a killed process, a result that does not pickle,
an exception in the job, a helper still importing when the result is wanted) makes
:meth:`Speculation.result` raise :class:`Lost`; the caller then computes the result itself, so a failure
costs time, never a result.  A helper that ends before it is ready (a ``sys.executable`` that cannot import
crustview) turns helpers off for the rest of the session.

``CRUSTVIEW_PROCESSES=1`` in the environment turns this off: where every core is already busy (the batch
command's ``-j 2`` workers, the test suite's ``pytest -n 2`` workers) a second process per run only
competes with the others.
"""

from __future__ import annotations

import atexit
import json
import os
import pickle
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from multiprocessing.connection import Connection
from typing import Any

#: The environment variable that, set to ``1``, keeps every run in its own process.
PROCESSES_ENV = "CRUSTVIEW_PROCESSES"
#: What the helper imports before its first job (so that a job starts without importing it).
PRELOAD = "crustview.core.robust.driver"
#: Seconds between two looks at the helper, the caller's cancel flag and its progress while waiting.
POLL_S = 0.05
#: Smallest change of the job's progress fraction the helper reports (fewer messages, same bar).
PROGRESS_STEP = 0.01

#: Seconds ``result(wait_for_start=True)`` waits for a helper to begin its job before giving up.
START_WAIT_S = 60.0
#: Helpers kept idle at most (each holds an interpreter with crustview imported, about 70 MB).
IDLE_MAX = 1
#: The helper's niceness: its work may be thrown away, so where the caller's own threads want both cores
#: they come first (10: the ``nice`` command's default step, the usual "background" level).
NICENESS = 10

_lock = threading.Lock()
_arrived = threading.Condition(_lock)  # a helper warm() started joined the idle ones
_idle: list[_Helper] = []
_busy: set[_Helper] = set()  # helpers with a job: stopped at exit too
_starting = 0  # helpers warm() is starting
_broken = False  # a helper ended before it was ready, or imported other code: no more helpers this session


class Lost(RuntimeError):
    """The helper could not be started or did not deliver its result (the caller computes it itself)."""


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))  # the cores this process may use (a container, taskset)
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def enabled() -> bool:
    """Whether a helper process may be used.

    Two usable cores or more; not turned off by :data:`PROCESSES_ENV`; a Python that can run ``python -c``
    (not a frozen application, whose executable is the application itself); SIGPIPE ignored, as CPython
    sets it (killing a helper while a job is sent to it then fails the send instead of killing the caller);
    and no helper of this session ended before it was ready.
    """
    import select
    import signal

    if _broken or getattr(sys, "frozen", False) or not sys.executable:
        return False
    if os.name != "posix" or not hasattr(select, "poll"):  # pass_fds and the helper's watch need POSIX
        return False
    if os.environ.get(PROCESSES_ENV, "").strip() == "1" or _cores() < 2:
        return False
    return not hasattr(signal, "SIGPIPE") or signal.getsignal(signal.SIGPIPE) == signal.SIG_IGN


def _package_dir() -> str:
    """The folder of the crustview package this process imported (the helper must import the same one)."""
    return os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # crustview/core/util/..


class _Helper:
    """One helper process and its two pipes (jobs in, messages out)."""

    def __init__(self) -> None:
        # -I: no current folder, no PYTHON* variables, no user site on the path; the caller's own path is set
        # instead, led by the folder holding the crustview the caller runs, so that the helper imports it.
        # Niceness first: numpy's and scipy's thread pools, started by the imports, inherit it
        code = (
            f"import os\ntry: os.nice({NICENESS})\nexcept OSError: pass\n"
            "import json, sys; sys.path[:] = json.loads(sys.argv[3]); "
            f"from {__name__} import _serve; _serve(int(sys.argv[1]), int(sys.argv[2]))"
        )
        paths = [os.path.dirname(_package_dir())]
        for entry in sys.path:
            try:
                paths.append(os.path.abspath(entry or os.curdir) if isinstance(entry, str) else None)
            except OSError:  # a current folder that no longer exists
                continue
        path_arg = json.dumps([p for p in paths if p])
        # a process group of its own keeps a terminal's Ctrl-C away; not a session of its own, whose
        # scheduler autogroup would make the niceness count for nothing against the caller
        group = {"process_group": 0} if sys.version_info >= (3, 11) else {"start_new_session": True}
        job_r, job_w = os.pipe()
        out_r, out_w = os.pipe()
        try:
            self.proc = subprocess.Popen(
                [sys.executable, "-I", "-c", code, str(job_r), str(out_w), path_arg],
                pass_fds=(job_r, out_w),
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                close_fds=True,
                **group,
            )
        except BaseException:
            for fd in (job_r, job_w, out_r, out_w):
                os.close(fd)
            raise
        os.close(job_r)
        os.close(out_w)
        self.jobs = Connection(job_w, readable=False)
        self.out = Connection(out_r, writable=False)
        self.ready = False  # its "ready" message was read (crustview imported, from the caller's folder)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def kill(self, wait: bool = True) -> None:
        """Kill the process (a job it runs is dropped); a send to it in progress then fails.

        ``wait=False`` returns once the signal is sent and reaps the process on a daemon thread: a helper
        killed in the middle of a job takes 2-35 ms to exit on the public scans (the kernel frees its
        memory), which the caller need not wait for.
        """
        if self.proc.poll() is not None:
            return  # already gone, and reaped by poll()
        self.proc.kill()
        if not wait:
            try:
                threading.Thread(target=self.proc.wait, name="crustview-reap", daemon=True).start()
                return
            except RuntimeError:  # no thread to be had (the interpreter is ending): wait here
                pass
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
    """An idle live helper, the one :func:`warm` is starting, or a new one; marked busy."""
    with _lock:
        while True:
            while _idle:
                helper = _idle.pop()
                if helper.alive():
                    _busy.add(helper)
                    return helper
                helper.stop()
            if not _starting:
                break
            _arrived.wait(START_WAIT_S)  # one is on its way: starting another would import crustview twice
    helper = _Helper()
    with _lock:
        _busy.add(helper)
    return helper


def _give_back(helper: _Helper) -> None:
    """An idle helper back to the pool; beyond :data:`IDLE_MAX`, or dead, it is stopped."""
    with _lock:
        _busy.discard(helper)
        dead = [h for h in _idle if not h.alive()]
        _idle[:] = [h for h in _idle if h.alive()]
        keep = helper.alive() and len(_idle) < IDLE_MAX
        if keep:
            _idle.append(helper)
    for h in dead:
        h.stop()
    if not keep:
        helper.stop()


def _forget_busy(helper: _Helper) -> None:
    """A helper killed with its job: no longer busy."""
    with _lock:
        _busy.discard(helper)


@atexit.register
def _stop_all() -> None:
    """Stop every helper at exit, idle or busy (a helper also ends by itself when the caller's end closes)."""
    with _lock:
        helpers = list(_idle) + list(_busy)
        _idle.clear()
        _busy.clear()
    for helper in helpers:
        helper.kill()


def warm() -> None:
    """Start an idle helper in the background if there is none (returns at once).

    :meth:`Speculation.discard` calls it, so that the next job finds a helper that has imported crustview.
    Errors are ignored here: :class:`Speculation` reports them when a helper is asked for.
    """
    global _starting
    if not enabled():
        return
    with _lock:
        if _starting or any(h.alive() for h in _idle):
            return
        _starting += 1

    def start() -> None:
        global _starting
        global _broken
        try:
            helper = _Helper()
        except Exception:  # noqa: BLE001 - no helper can be started: none is asked for again this session
            helper = None
            _broken = True
        if helper is not None:
            _give_back(helper)
        with _lock:
            _starting -= 1
            _arrived.notify_all()

    try:
        threading.Thread(target=start, name="crustview-helper-start", daemon=True).start()
    except RuntimeError:  # no thread to be had: no helper, nothing else changes
        with _lock:
            _starting -= 1


class _Reporter:
    """The helper's ``progress``: a job's fraction sent to the caller when it moved :data:`PROGRESS_STEP`."""

    def __init__(self, out: Connection) -> None:
        self.out = out
        self.last = -1.0

    def __call__(self, fraction: float) -> None:
        if abs(fraction - self.last) >= PROGRESS_STEP:
            self.last = fraction
            self.out.send(("progress", float(fraction)))


def _watch_caller(job_fd: int) -> None:
    """End the helper at once when the caller's end of the job pipe closes (the caller exited or died).

    Between jobs the helper sees that as the end of its input; during a job only this thread does.
    """
    import select

    poller = select.poll()
    poller.register(job_fd, select.POLLHUP)
    while True:
        for _, event in poller.poll():
            if event & (select.POLLHUP | select.POLLERR | select.POLLNVAL):
                os._exit(0)


def _serve(job_fd: int, out_fd: int) -> None:
    """The helper's loop: jobs ``(fn, args, with_progress)`` in, messages out.

    Out: ``("ready", folder)`` once crustview is imported, then per job ``("started", None)``,
    ``("progress", f)`` and ``("done", (ok, result or message))``.

    Python's cyclic collector is off during a job, as the caller's is around the extraction
    (:func:`.memory.gc_paused`): the work builds many long-lived small objects without cycles.  Between jobs
    it runs, and the freed memory goes back to the system.  A caller that went away ends the helper quietly.
    """
    import gc
    import importlib
    import signal

    from .memory import numpy_small_pages, release_free_memory

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the caller decides when a helper stops
    jobs = Connection(job_fd, writable=False)
    out = Connection(out_fd, readable=False)
    threading.Thread(target=_watch_caller, args=(job_fd,), daemon=True).start()
    try:
        importlib.import_module(PRELOAD)
        out.send(("ready", _package_dir()))
        while True:
            try:
                job = jobs.recv_bytes()
            except (EOFError, OSError):  # the caller is gone, or stopped this helper
                return
            out.send(("started", None))  # before unpickling: a large job has begun once it has arrived
            gc.disable()
            try:
                fn, args, with_progress = pickle.loads(job)
                del job
                with numpy_small_pages():  # as the caller's run (see there)
                    if with_progress:
                        result: tuple[bool, Any] = (True, fn(*args, progress=_Reporter(out)))
                    else:
                        result = (True, fn(*args))
            except (BrokenPipeError, ConnectionError):
                raise
            except BaseException as err:  # noqa: BLE001 - any failure goes back to the caller, which recomputes
                result = (False, repr(err))
            try:
                out.send(("done", result))
            except (BrokenPipeError, ConnectionError):
                raise
            except Exception as err:  # noqa: BLE001 - a result that does not pickle
                out.send(("done", (False, f"the result could not be sent back: {err!r}")))
            del result
            gc.enable()
            gc.collect()
            release_free_memory()
    except (BrokenPipeError, ConnectionError):  # the caller is gone: nothing to say, to no one
        os._exit(0)


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
        try:
            self._starter.start()
        except RuntimeError as err:  # no thread to be had: no helper; result() says so
            self._error = f"no thread to send the job: {err!r}"

    def _start(self, fn: Callable[..., Any], args: tuple, with_progress: bool) -> None:
        global _broken
        try:
            helper = _take()
        except Exception as err:  # noqa: BLE001 - no helper: result() says so, the caller computes it
            self._error = f"no helper process: {err!r}"
            _broken = True  # a process that cannot be started now will not start later either
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
        check: Callable[[], None] | None = None,
        progress: Callable[[float], None] | None = None,
        *,
        wait_for_start: bool = False,
    ) -> Any:
        """Wait for the helper's result, relaying its progress and calling ``check`` every :data:`POLL_S`.

        ``check`` raises to stop waiting (a cancelled run: ``lambda: check_cancel(cancel)``); the helper is
        then stopped and the exception goes on.

        A helper that has not begun the job yet (it was still importing crustview) is not waited for: the
        job is dropped and :class:`Lost` raised, so that the caller computes it at once; unless
        ``wait_for_start``, which waits up to :data:`START_WAIT_S` for it to begin.

        Raises
        ------
        Lost
            The helper did not start, had not begun, died, imported another crustview, or the job failed
            (the message says which).
        Exception
            Whatever ``check`` raised (the helper is stopped).
        """
        global _broken
        if wait_for_start and self._starter.ident is not None:
            self._starter.join(START_WAIT_S)
        deadline = time.monotonic() + (START_WAIT_S if wait_for_start else 0.0)
        try:
            if self._starter.is_alive() or self._helper is None or self._error is not None:
                raise Lost(self._error or "the helper had not begun the job (it was still starting)")
            helper = self._helper
            while True:
                waiting = self._begun or time.monotonic() < deadline
                if helper.out.poll(POLL_S if waiting else 0):
                    try:
                        kind, payload = helper.out.recv()
                    except (EOFError, OSError) as err:  # the helper closed its end: it ended
                        try:
                            code = helper.proc.wait(5)  # an ended helper is reaped at once
                        except subprocess.TimeoutExpired:
                            code = None
                        if not helper.ready:  # it never got as far as importing crustview: none will
                            _broken = True
                        raise Lost(f"the helper process ended (exit code {code}) without a result: {err!r}") from err
                    except Exception as err:  # noqa: BLE001 - a message that does not unpickle here
                        raise Lost(f"the helper's message could not be read: {err!r}") from err
                    if kind == "done":
                        break
                    if kind == "ready":
                        helper.ready = True
                        if payload != _package_dir():
                            _broken = True
                            raise Lost(f"the helper imported crustview from {payload}, not {_package_dir()}")
                    elif kind == "started":
                        self._begun = True
                    else:
                        self._progress = max(self._progress, float(payload))
                elif not waiting:
                    raise Lost("the helper had not begun the job (it was still starting)")
                if progress is not None:
                    progress(self._progress)
                if check is not None:
                    check()
        except BaseException:
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
        helper.kill(wait=False)
        _forget_busy(helper)
        if not sending:
            helper.close()
        warm()
