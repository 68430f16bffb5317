"""Shared test setup.

GUI tests run the real window under Xvfb (pytest-xvfb starts it).  The Qt
widget must render on screen: ``pyvista.OFF_SCREEN`` stays False (an
off-screen QtInteractor under Xvfb gives blank pictures).  Render-tier tests
create their own ``Plotter(off_screen=True)``.
"""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "xcb")

try:  # pyvista is optional for the pure tests
    import pyvista

    pyvista.OFF_SCREEN = False
    pyvista.global_theme.multi_samples = 0
except ImportError:  # pragma: no cover
    pyvista = None


@pytest.fixture(scope="session")
def torus_run():
    """A real reconstruction of the built-in torus (closed, ~3k triangles)."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold("torus")
    sample = m.sample(m.default_n, seed=0)
    rec = reconstruct(sample.points, m.d)
    return rec, sample


@pytest.fixture(scope="session")
def s3_run():
    """A real reconstruction of S^3 in R^4 (d = 3)."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold("s3")
    sample = m.sample(600, seed=0)
    rec = reconstruct(sample.points, m.d)
    return rec, sample


@pytest.fixture()
def window(qtbot, tmp_path):
    """The real main window, shown, with temporary settings."""
    from PySide6.QtCore import QSettings

    from crustview.qt.window import MainWindow

    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat)
    win = MainWindow(settings=settings)
    qtbot.addWidget(win, before_close_func=lambda w: w.plotter.close())
    win.resize(1200, 800)
    win.show()
    qtbot.waitExposed(win)
    yield win
    win.runner.shutdown()
