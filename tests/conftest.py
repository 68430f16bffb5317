"""Shared test setup.

GUI tests run the real window under Xvfb (pytest-xvfb starts it).  The Qt
widget must render on screen: ``pyvista.OFF_SCREEN`` stays False (an
off-screen QtInteractor under Xvfb gives blank pictures).  Render-tier tests
create their own ``Plotter(off_screen=True)``.
"""

from __future__ import annotations

import contextlib
import os

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "xcb")
if os.environ.get("PYTEST_XDIST_WORKER") is not None:
    # Mesa's software rasteriser (llvmpipe) draws with one thread per core by default: with two xdist
    # workers on two cores that is four drawing threads, and the suite spent about 9 % more CPU time
    # (590 s against 539 s of user and system time in one run each here) for the same pictures
    os.environ.setdefault("LP_NUM_THREADS", "1")
    # and a reconstruction begins its growing path in a helper process where a core is free
    # (crustview/core/util/second_core.py): under pytest -n 2 none is.  tests/test_second_core.py turns it on
    os.environ.setdefault("CRUSTVIEW_PROCESSES", "1")

try:  # pyvista is optional for the pure tests
    import pyvista

    pyvista.OFF_SCREEN = False
    pyvista.global_theme.multi_samples = 0
except ImportError:  # pragma: no cover
    pyvista = None


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """Run in one process when no ``-n`` is given: ``--dist worksteal`` (``pyproject.toml``'s addopts, for
    ``-n 2``) without workers made pytest-xdist run the tests in a session whose Qt application aborted."""
    if getattr(config.option, "dist", "no") != "no" and not getattr(config.option, "numprocesses", None):
        if not getattr(config.option, "tx", None):
            config.option.dist = "no"


def pytest_configure(config):
    """Compile crustview's modules to ``__pycache__`` before the xdist workers and the command-line tests'
    subprocesses (about 100) import them.

    Where ``PYTHONDONTWRITEBYTECODE`` is set (as on this project's CI machines) nothing else writes them,
    and on a fresh clone each of those processes compiled every module it imported (about 0.07 s each).
    Compiling takes about 0.2 s; up-to-date files are skipped.
    """
    if hasattr(config, "workerinput"):  # an xdist worker: the controller has done it
        return
    import compileall
    import importlib.util

    spec = importlib.util.find_spec("crustview")
    for folder in spec.submodule_search_locations if spec is not None else ():
        try:
            compileall.compile_dir(folder, quiet=2)
        except OSError:  # a read-only install: the processes compile in memory, as before
            pass


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


@pytest.fixture(scope="session")
def default_run():
    """``default_run(name)``: a built-in's ``reconstruct(m.sample(m.default_n, seed=0).points, m.d)`` and its
    sample, computed once per process and shared by the tests that only read them (the sampling, naming and
    theorem tests ask for the same ones).  Their arrays are read-only: a test writing into one fails."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    runs: dict = {}

    def run(name: str):
        if name not in runs:
            m = get_manifold(name)
            sample = m.sample(m.default_n, seed=0)
            rec = reconstruct(sample.points, m.d)
            _read_only(rec)
            sample.points.flags.writeable = False
            sample.tangents.flags.writeable = False
            runs[name] = (rec, sample)
        return runs[name]

    return run


@pytest.fixture(scope="session")
def camelhead_run():
    """``reconstruct`` of resources/camelhead.off (an open scan, 11,381 samples, d = 2), once per process,
    with its arrays read-only (the robust, labelling and description tests only read it)."""
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.io import read_mesh

    rec = reconstruct(read_mesh(Path(__file__).resolve().parents[1] / "resources" / "camelhead.off").points, 2)
    _read_only(rec)
    return rec


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


# ---------------------------------------------------------------- the GUI tests' shared reconstructions
#: Per process (each xdist worker has its own): reconstruct's result and progress calls by arguments.
_RUNS: dict = {}
#: sampling_quality's result by the id of a remembered reconstruction (kept alive in _RUNS).
_QUALITY: dict = {}
#: The copies handed out on repeats, by id (kept alive, so ids stay unique), and their originals.
_COPIES: dict = {}


def _run_key(points, d, kwargs) -> tuple:
    import hashlib

    import numpy as np

    pts = np.ascontiguousarray(points)
    digest = hashlib.blake2b(pts.tobytes(), digest_size=16).hexdigest()
    return (pts.shape, str(pts.dtype), digest, d, tuple(sorted(kwargs.items())))


def _remembered(reconstruct):
    """``reconstruct`` computing each distinct run once; a repeat replays its progress calls and checks cancel."""
    import dataclasses

    from crustview.core.errors import Cancelled

    def run(points, d, *, progress=None, cancel=None, **kwargs):
        key = _run_key(points, d, kwargs)
        if key not in _RUNS:
            calls: list = []

            def record(stage, fraction):
                calls.append((stage, fraction))
                if progress is not None:
                    progress(stage, fraction)

            rec = reconstruct(points, d, progress=record, cancel=cancel, **kwargs)
            _read_only(rec)
            _RUNS[key] = (rec, calls)
            return rec
        rec, calls = _RUNS[key]
        for stage, fraction in calls:
            if cancel is not None and cancel.is_set():
                raise Cancelled("reconstruction cancelled")
            if progress is not None:
                progress(stage, fraction)
        copy = dataclasses.replace(rec)  # a new object, as every run gives (tests check "rec is not old")
        _COPIES[id(copy)] = (copy, rec)
        return copy

    return run


def _read_only(rec) -> None:
    """Make the shared result's arrays read-only: a viewer that wrote into one would fail its test."""
    import dataclasses

    import numpy as np

    for holder in (rec, rec.candidates):
        for field in dataclasses.fields(holder):
            value = getattr(holder, field.name)
            if isinstance(value, np.ndarray):
                value.flags.writeable = False


def _remembered_quality(quality):
    def run(rec, progress, cancel=None):
        if id(rec) in _COPIES and _COPIES[id(rec)][0] is rec:
            rec = _COPIES[id(rec)][1]
        if not any(rec is hit for hit, _ in _RUNS.values()):
            return quality(rec, progress, cancel)
        if id(rec) not in _QUALITY:
            _QUALITY[id(rec)] = quality(rec, progress, cancel)
        else:
            progress("quality", 1.0)
        return _QUALITY[id(rec)]

    return run


@pytest.fixture(autouse=True)
def _shared_reconstructions(request, monkeypatch):
    """In the GUI tests, the window's worker reconstructs each distinct input once per process.

    The GUI tests load the same built-ins again and again (the torus about 40
    times); the sampling and the reconstruction are the core tests' subject,
    so each distinct seeded sample is drawn once per process too.  A repeat
    gets a shallow copy of the same ``Reconstruction`` (its arrays made
    read-only, so a viewer writing into one fails) after
    the first run's progress calls, replayed in the worker, so stages,
    progress bars and Cancel behave as in a run.  A test marked
    ``fresh_runs`` always reconstructs.
    """
    if not request.node.path.name.startswith("test_gui_") or request.node.get_closest_marker("fresh_runs"):
        yield
        return
    from crustview.core.samples.sampling import TestManifold
    from crustview.qt import running

    monkeypatch.setattr(running, "reconstruct", _remembered(running.reconstruct))
    monkeypatch.setattr(running, "_quality", _remembered_quality(running._quality))
    monkeypatch.setattr(TestManifold, "sample", _remembered_sample(TestManifold.sample))
    yield


#: Per process: a built-in's seeded sample by its arguments (the GUI tests load the torus about 40 times).
_SAMPLES: dict = {}


def _remembered_sample(sample):
    """``TestManifold.sample`` drawing each distinct seeded sample once; a repeat gets a copy of the first.

    The copy is a new ``Sample`` holding the first one's arrays, made read-only (a viewer that wrote into
    one would fail its test).  An unseeded sample (``seed=None``) is drawn every time.
    """
    import dataclasses

    def draw(self, n, *, seed=0, **kwargs):
        if seed is None:
            return sample(self, n, seed=seed, **kwargs)
        key = (self.name, n, seed, tuple(sorted(kwargs.items())))
        if key not in _SAMPLES:
            first = sample(self, n, seed=seed, **kwargs)
            first.points.flags.writeable = False
            first.tangents.flags.writeable = False
            _SAMPLES[key] = first
        return dataclasses.replace(_SAMPLES[key])

    return draw


# ---------------------------------------------------------------- timed tests run alone under xdist
#: Where a ``timing`` test finds this run's lock files (set in its setup, used around its call).
_TIMING_LOCKS = pytest.StashKey[object]()


@pytest.fixture(autouse=True)
def _timed_tests_run_alone(request, tmp_path_factory):
    """Under pytest-xdist, the call of a test marked ``timing`` runs while no other worker runs a test.

    Every other test holds a shared lock on a file of this run's base temporary
    folder (common to the workers) for its setup, call and teardown; a
    ``timing`` test takes it exclusively for its call only (in
    ``pytest_runtest_call`` below), so it waits for the other worker's current
    test and the other worker waits for it.  Its setup (the window, a long
    reconstruction of a module fixture) and teardown measure nothing and run
    beside the other worker's tests.  A gate lock, held while a test asks for
    the main lock, keeps a waiting ``timing`` test from being starved.
    Without xdist it does nothing.
    """
    if os.environ.get("PYTEST_XDIST_WORKER") is None:
        yield
        return
    folder = tmp_path_factory.getbasetemp().parent
    if request.node.get_closest_marker("timing") is not None:
        request.node.stash[_TIMING_LOCKS] = folder
        yield
        return
    with _locked(folder, exclusive=False):
        yield


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    folder = item.stash.get(_TIMING_LOCKS, None)
    if folder is None:
        return (yield)
    with _locked(folder, exclusive=True):
        return (yield)


@contextlib.contextmanager
def _locked(folder, exclusive: bool):
    import fcntl

    with open(folder / "crustview-timing.gate", "a") as gate, open(folder / "crustview-timing.lock", "a") as lock:
        fcntl.flock(gate, fcntl.LOCK_EX)
        fcntl.flock(lock, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        if not exclusive:
            fcntl.flock(gate, fcntl.LOCK_UN)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
            fcntl.flock(gate, fcntl.LOCK_UN)


def pytest_collection_modifyitems(config, items):
    """The readers' fuzz tests first, the ``timing`` tests last, otherwise collection order.

    The fuzz tests run before any window or reconstruction exists in the process, as they do in a serial
    run (in a worker that had run GUI tests before, the PCD case with a 1,111,111-value field went over its
    256 MiB and 5 s bounds).  The ``timing`` tests' calls run while the other xdist worker waits: at the end,
    that wait takes the place of the other worker's idle time after its last test (when pytest-xdist's
    last chunks of tests end at different times), instead of adding to the run (about 5 s of a 200 s run
    here).  The timing tests' module fixtures (``long_run``, ``fertility_run``) serve only them, so they
    are still built once.
    """
    items.sort(key=lambda item: (not item.get_closest_marker("fuzz"), bool(item.get_closest_marker("timing"))))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """pytest-xdist's ``load`` scheduling, sending tests two at a time once half of them are left.

    By default a worker that asks for more tests gets up to a quarter of those left, so near the end one
    worker could hold a queue of some fifteen GUI tests while the other ran out of tests (and waited the
    ``timing`` tests out) and went idle: 8-15 s of a 205-225 s run here.  Earlier chunks stay large, so
    a module's tests (and its module fixtures) mostly stay on one worker.  An explicit
    ``--maxschedchunk`` is left as given.
    """
    if config.getvalue("dist") != "load" or config.getoption("maxschedchunk") is not None:
        return None
    from xdist.scheduler import LoadScheduling

    class EvenEnd(LoadScheduling):
        def check_schedule(self, node, duration=0):
            if self.collection is not None and len(self.pending) <= len(self.collection) // 2:
                self.maxschedchunk = 2
            super().check_schedule(node, duration)

    return EvenEnd(config, log)
