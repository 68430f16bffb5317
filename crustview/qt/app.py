"""Starting the viewer: ``run_app()``."""

from __future__ import annotations

import os
import sys
import traceback

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QApplication


def _excepthook(window):
    """Report unexpected exceptions in the window instead of crashing."""

    def hook(etype, value, tb):
        traceback.print_exception(etype, value, tb, file=sys.stderr)
        try:
            from .worker import user_message

            window.show_error(user_message(value))
        except Exception:  # noqa: BLE001 - last resort: stderr only
            pass

    return hook


def run_app(
    path: str | os.PathLike | None = None, d: int | None = None, demo: bool = True, mode: str | None = None
) -> int:
    """Open the main window and run the Qt event loop.

    Parameters
    ----------
    path : path-like, optional
        A point file to open at start.
    d : int, optional
        Its intrinsic dimension; asked for when None.
    demo : bool
        Without ``path``, start on the built-in demo (a torus in R^3,
        reconstructed, replay at step 0).
    mode : {"robust", "paper"}, optional
        Extraction mode for ``path`` (``crustview view --paper``); it also
        overrides the mode saved in a result ``.npz``.  None: the Run panel's
        mode, or the saved one.

    Returns
    -------
    int
        The application's exit status.
    """
    from .window import MainWindow

    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("crustview")
    app.setOrganizationName("crustview")
    window = MainWindow()
    screen = app.primaryScreen()
    geo = screen.availableGeometry() if screen is not None else None
    window.fit_to_screen(geo.width() if geo else 1600, geo.height() if geo else 1000)
    window.show()
    sys.excepthook = _excepthook(window)
    if path is not None:
        if mode is not None:
            window.run_panel.set_mode(mode)
        QTimer.singleShot(0, lambda: window.open_file(path, d, mode=mode))
    elif demo:
        QTimer.singleShot(0, window.load_demo)
    return int(app.exec())
