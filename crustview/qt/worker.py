"""Running reconstructions off the GUI thread, with progress and Cancel."""

from __future__ import annotations

import sys
import threading
import time
import traceback
from collections.abc import Callable

from PySide6.QtCore import QObject, QThread, Signal, Slot

from ..core.errors import Cancelled, CrustviewError


def user_message(err: BaseException) -> str:
    """One clear sentence for the user; never a traceback."""
    if isinstance(err, CrustviewError):
        return str(err)
    if isinstance(err, MemoryError):
        return "The computation ran out of memory; try fewer points or a surface instead of a curve."
    name = type(err).__name__
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    if "qhull" in name.lower() or "QH" in text[:8]:
        return f"Qhull could not triangulate these points ({text[:160]})."
    return f"Unexpected error ({name}): {text[:200]}"


class _Worker(QObject):
    progress = Signal(str, float)
    done = Signal(object)
    failed = Signal(str)
    cancelled = Signal()

    def __init__(self, fn: Callable, cancel: threading.Event) -> None:
        super().__init__()
        self.fn = fn
        self.cancel = cancel
        self._last = (None, -1.0, 0.0)

    def _progress(self, stage: str, fraction: float) -> None:
        # throttle: the core may report very often
        now = time.monotonic()
        s, f, t = self._last
        if stage != s or fraction - f >= 0.01 or now - t > 0.1 or fraction >= 1.0:
            self._last = (stage, fraction, now)
            self.progress.emit(str(stage), float(fraction))

    @Slot()
    def run(self) -> None:
        try:
            result = self.fn(self._progress, self.cancel)
        except Cancelled:
            self.cancelled.emit()
        except BaseException as err:  # noqa: BLE001 - shown to the user as a sentence
            if not isinstance(err, CrustviewError):
                traceback.print_exc(file=sys.stderr)
            if self.cancel.is_set():
                self.cancelled.emit()
            else:
                self.failed.emit(user_message(err))
        else:
            if self.cancel.is_set():
                self.cancelled.emit()
            else:
                self.done.emit(result)


class Runner(QObject):
    """Runs one job at a time in a QThread.

    ``start(fn)`` calls ``fn(progress, cancel)`` in the worker thread, where
    ``progress(stage, fraction)`` may be called often and ``cancel`` is a
    :class:`threading.Event`.  Exactly one of :attr:`done`, :attr:`failed`,
    :attr:`cancelled` is emitted (in the GUI thread), then :attr:`finished`.
    """

    started = Signal(str)
    progress = Signal(str, float)
    done = Signal(object)
    failed = Signal(str)
    cancelled = Signal()
    finished = Signal()

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._thread: QThread | None = None
        self._worker: _Worker | None = None
        self._cancel = threading.Event()
        self.label = ""

    @property
    def busy(self) -> bool:
        return self._thread is not None

    def start(self, fn: Callable, label: str = "") -> bool:
        """Start ``fn``; returns False when a job is already running."""
        if self.busy:
            return False
        self._cancel = threading.Event()
        self.label = label
        thread = QThread()
        worker = _Worker(fn, self._cancel)
        worker.moveToThread(thread)
        thread.started.connect(worker.run)
        worker.progress.connect(self.progress)
        worker.done.connect(self._on_done)
        worker.failed.connect(self._on_failed)
        worker.cancelled.connect(self._on_cancelled)
        self._thread, self._worker = thread, worker
        thread.start()
        self.started.emit(label)
        return True

    # bound methods of this QObject: queued into the GUI thread
    @Slot(object)
    def _on_done(self, result) -> None:
        self._stop_thread()
        self.done.emit(result)
        self.finished.emit()

    @Slot(str)
    def _on_failed(self, message: str) -> None:
        self._stop_thread()
        self.failed.emit(message)
        self.finished.emit()

    @Slot()
    def _on_cancelled(self) -> None:
        self._stop_thread()
        self.cancelled.emit()
        self.finished.emit()

    def _stop_thread(self) -> None:
        thread = self._thread
        self._thread = None
        self._worker = None
        if thread is not None:
            thread.quit()
            thread.wait()

    def cancel(self) -> None:
        """Ask the running job to stop (it raises Cancelled at its next check)."""
        self._cancel.set()

    def shutdown(self, timeout_ms: int = 5000) -> None:
        """Cancel and wait for the thread (used when the window closes)."""
        if self._thread is not None:
            self._cancel.set()
            self._thread.quit()
            self._thread.wait(timeout_ms)
