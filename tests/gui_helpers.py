"""Shared by the GUI tests: loading a built-in, answering modal dialogs, screen positions."""

from __future__ import annotations

from collections.abc import Callable


def on_next_dialog(answer: Callable, kind: type | None = None, interval: int = 20) -> list:
    """Run ``answer(dialog)`` on the next modal dialog (of class ``kind``, if given).

    Polls from the event loop, so the call that opens the dialog can block in
    ``exec()``.  Returns a list that receives the dialog once answered.
    """
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication

    done: list = []

    def poll() -> None:
        dlg = QApplication.activeModalWidget()
        if dlg is None or (kind is not None and not isinstance(dlg, kind)):
            QTimer.singleShot(interval, poll)
            return
        answer(dlg)
        done.append(dlg)

    QTimer.singleShot(interval, poll)
    return done


def answer_file_dialog(path) -> list:
    """Type ``path`` into the next modal file dialog and accept it."""
    from PySide6.QtWidgets import QFileDialog

    return on_next_dialog(lambda dlg: (dlg.selectFile(str(path)), dlg.accept()), QFileDialog)


def wait_idle(qtbot, win, timeout: int = 60_000) -> None:
    """Wait until the window's worker is done, and fail with its error if it left no result."""
    qtbot.waitUntil(lambda: not win.runner.busy, timeout=timeout)
    assert win.model.rec is not None, win.last_error


def load(qtbot, win, name: str = "torus", n: int | None = None, timeout: int = 60_000):
    """Load built-in ``name`` in the window, wait for its result and return it."""
    assert win.load_builtin(name, n)
    wait_idle(qtbot, win, timeout)
    qtbot.wait(50)
    return win.model.rec


def display_xy(win, xyz) -> tuple[float, float]:
    """Display coordinates of world point ``xyz`` in the window's 3D view."""
    ren = win.plotter.renderer
    ren.SetWorldPoint(*xyz, 1.0)
    ren.WorldToDisplay()
    x, y, _ = ren.GetDisplayPoint()
    return x, y
