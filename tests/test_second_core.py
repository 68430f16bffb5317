"""The growing path begun in a helper process (crustview.core.util.second_core): the same result, sooner.

The suite's xdist workers turn the second process off (tests/conftest.py); these tests turn it on again.
"""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.errors import Cancelled, check_cancel
from crustview.core.robust import choose as choose_module
from crustview.core.robust.grown_path import grown_path
from crustview.core.util import second_core
from crustview.io import read_mesh

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


@pytest.fixture()
def two_processes(monkeypatch):
    """The second process allowed, as outside the test suite."""
    monkeypatch.delenv(second_core.PROCESSES_ENV, raising=False)
    if not second_core.enabled():
        pytest.fail("this machine has one core: the second process cannot be tested here")


def _reaped(proc, seconds: float = 5.0) -> bool:  # noqa: ANN001
    """Whether ``proc`` exits and is reaped within ``seconds`` by someone else (``returncode`` set by its wait)."""
    end = time.monotonic() + seconds
    while proc.returncode is None and time.monotonic() < end:
        time.sleep(0.01)
    return proc.returncode is not None


def _same_extraction(a, b) -> None:
    assert np.array_equal(a.simplices, b.simplices)
    assert np.array_equal(a.added_at, b.added_at) and np.array_equal(a.removed_at, b.removed_at)
    assert np.array_equal(a.in_candidates, b.in_candidates)
    assert [(s.rule, s.tau, s.added, s.removed, s.reason) for s in a.steps] == [
        (s.rule, s.tau, s.added, s.removed, s.reason) for s in b.steps
    ]
    assert np.array_equal([s.angle for s in a.steps], [s.angle for s in b.steps], equal_nan=True)
    assert a.stopped == b.stopped and a.notes == b.notes
    assert repr(a.removed_features) == repr(b.removed_features) and repr(a.disputed) == repr(b.disputed)


def test_switched_off_by_the_environment(monkeypatch):
    monkeypatch.setenv(second_core.PROCESSES_ENV, "1")
    assert not second_core.enabled()
    monkeypatch.setenv(second_core.PROCESSES_ENV, "0")
    assert second_core.enabled() == ((os.cpu_count() or 1) >= 2)


def test_a_run_whose_growing_path_is_taken_is_the_same_with_and_without_the_second_process(two_processes, monkeypatch):
    """The noisy decimated knight's labelled result is grown again (under SECOND_OPINION_N, a cut handle)."""
    pts = np.loadtxt(RESOURCES / "decimated-knight-n10.xyz")
    pts = np.vstack([pts, read_mesh(RESOURCES / "bumpy.off").points * 0.2 + [3.0, 0.0, 0.0]])
    assert len(pts) >= choose_module.SPECULATE_MIN_N
    second_core.Speculation(len, ((),)).result(wait_for_start=True)  # a helper ready, as after a run's warm-up
    begun, taken = [], []
    real = second_core.Speculation

    class Counted(real):  # the real class, counting the jobs begun and the results taken from the helper
        def __init__(self, *args, **kwargs):
            begun.append(args[0])
            super().__init__(*args, **kwargs)

        def result(self, *args, **kwargs):
            # waiting for the helper to begin: on a loaded machine (the suite's other worker drawing) it may
            # not have begun the job yet when the labelling is done, and the path then runs here (a clean
            # clone's suite failed so once in session 45): the comparison is of the helper's result
            out = super().result(*args, **{**kwargs, "wait_for_start": True})
            taken.append(out)
            return out

    monkeypatch.setattr(second_core, "Speculation", Counted)
    ahead = reconstruct(pts, 2)
    monkeypatch.setenv(second_core.PROCESSES_ENV, "1")
    here = reconstruct(pts, 2)
    assert begun == [grown_path] and len(taken) == 1  # the grown M_S came from the helper
    assert "grew M_S" in here.extraction.notes[0]
    _same_extraction(ahead.extraction, here.extraction)
    assert np.array_equal(ahead.manifold, here.manifold)
    assert ahead.topology.betti == here.topology.betti


def test_the_worker_gives_what_the_function_gives_here(two_processes):
    pts = read_mesh(RESOURCES / "elk.off").points
    rec = reconstruct(pts, 2, mode="paper")
    c = rec.candidates
    admitted = c.angles[rec.test] < rec.theta
    args = (rec.points, c.faces, c.angles[rec.test], admitted, rec.spacing)
    seen: list[float] = []
    ahead = second_core.Speculation(grown_path, args, with_progress=True)
    there = ahead.result(progress=seen.append, wait_for_start=True)
    _same_extraction(there, grown_path(*args))
    # the growth's fractions, relayed as they came: rising, inside [0, 1], and not only the start
    assert seen == sorted(seen) and 0.0 <= seen[0] and seen[-1] <= 1.0 and seen[-1] > 0.5


def test_a_cancel_while_waiting_stops_the_worker_at_once(two_processes):
    ahead = second_core.Speculation(time.sleep, (60,))
    ahead._starter.join()
    proc = ahead._helper.proc
    cancel = threading.Event()
    threading.Timer(0.3, cancel.set).start()
    t0 = time.perf_counter()
    with pytest.raises(Cancelled):
        ahead.result(lambda: check_cancel(cancel), wait_for_start=True)
    assert time.perf_counter() - t0 < 2  # polled every POLL_S, then killed
    assert _reaped(proc)  # the helper running the job is gone, reaped by the thread kill() left


def test_a_worker_that_dies_is_lost_and_the_path_runs_here(two_processes):
    dead = second_core.Speculation(os._exit, (3,))
    with pytest.raises(second_core.Lost, match="exit code 3"):
        dead.result(wait_for_start=True)
    pts = np.loadtxt(RESOURCES / "decimated-knight-n10.xyz")
    rec = reconstruct(pts, 2, mode="paper")
    c = rec.candidates
    args = (rec.points, c.faces, c.angles[rec.test], c.angles[rec.test] < rec.theta, rec.spacing)
    dying = second_core.Speculation(os._exit, (3,))
    dying._starter.join()
    dying._helper.proc.wait(30)  # the helper began the job and died of it
    lost = choose_module._grown(*args, None, None, dying)
    _same_extraction(lost, grown_path(*args))


def test_a_worker_whose_function_fails_says_how(two_processes):
    with pytest.raises(second_core.Lost, match="ValueError"):
        second_core.Speculation(int, ("not a number",)).result(wait_for_start=True)


def test_discarding_an_unneeded_worker_ends_it(two_processes):
    ahead = second_core.Speculation(time.sleep, (60,))
    ahead._starter.join()
    proc = ahead._helper.proc
    assert proc.poll() is None  # running the job
    ahead.discard()
    assert ahead._helper is None and _reaped(proc)
    ahead.discard()  # twice is harmless


def test_a_run_cancelled_during_the_labelling_leaves_no_worker_behind(two_processes, monkeypatch):
    procs = []
    real = second_core.Speculation

    class Watched(real):  # the real class, keeping each helper's process
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self._starter.join()
            procs.append(self._helper.proc)

    monkeypatch.setattr(second_core, "Speculation", Watched)
    pts = np.loadtxt(RESOURCES / "decimated-knight-n10.xyz")
    pts = np.vstack([pts, read_mesh(RESOURCES / "bumpy.off").points * 0.2 + [3.0, 0.0, 0.0]])
    cancel = threading.Event()
    seen = []

    def progress(stage: str, fraction: float) -> None:
        seen.append((stage, fraction))
        if stage == "extraction" and fraction > 0.1:  # the labelling has begun, and the worker with it
            cancel.set()

    with pytest.raises(Cancelled):
        reconstruct(pts, 2, progress=progress, cancel=cancel)
    assert any(stage == "extraction" for stage, _ in seen)
    assert len(procs) == 1 and _reaped(procs[0])  # the helper running the growing path was stopped


def test_a_script_without_a_main_guard_runs_once(two_processes, tmp_path):
    """The helper is a fresh ``python -I -c``: it never runs the caller's main script again."""
    import subprocess
    import sys

    marker = tmp_path / "ran.txt"
    script = tmp_path / "plain.py"
    script.write_text(
        "import numpy as np\n"
        "from crustview.core import reconstruct\n"
        "from crustview.core.util import second_core\n"
        "from crustview.io import read_mesh\n"
        f"open({str(marker)!r}, 'a').write('body ran\\n')\n"
        "print('helper', second_core.Speculation(len, ((1, 2),)).result(wait_for_start=True), flush=True)\n"
        f"pts = np.loadtxt({str(RESOURCES / 'decimated-knight-n10.xyz')!r})\n"
        f"pts = np.vstack([pts, read_mesh({str(RESOURCES / 'bumpy.off')!r}).points * 0.2 + [3.0, 0.0, 0.0]])\n"
        "rec = reconstruct(pts, 2)\n"
        "print('grown', 'grew M_S' in rec.extraction.notes[0], flush=True)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != second_core.PROCESSES_ENV}
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines() == ["helper 2", "grown True"]
    assert marker.read_text() == "body ran\n"


def _recording_helpers(monkeypatch) -> list:
    """The helpers started from here on (none left idle by an earlier test is reused)."""
    second_core._stop_all()
    made: list = []

    class Recorded(second_core._Helper):
        def __init__(self) -> None:
            super().__init__()
            made.append(self)

    monkeypatch.setattr(second_core, "_Helper", Recorded)
    return made


def test_the_helper_imports_the_callers_crustview_whatever_the_current_folder(two_processes, tmp_path, monkeypatch):
    """A ``crustview`` folder where the caller stands does not shadow the one the caller runs (-I, its path)."""
    made = _recording_helpers(monkeypatch)
    fake = tmp_path / "crustview"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('the wrong crustview')\n")
    monkeypatch.chdir(tmp_path)
    assert second_core.Speculation(len, ((1, 2, 3),)).result(wait_for_start=True) == 3
    assert len(made) == 1  # a helper started here, in the folder holding the fake, ran the job
    assert second_core.enabled()


def test_idle_helpers_stay_few(two_processes, monkeypatch):
    """Two jobs at once take two helpers; given back, one stays idle (IDLE_MAX) and the other is stopped."""
    made = _recording_helpers(monkeypatch)
    first, second = (second_core.Speculation(time.sleep, (0.5,)) for _ in range(2))
    assert first.result(wait_for_start=True) is None and second.result(wait_for_start=True) is None
    assert len(made) == 2 == second_core.IDLE_MAX + 1
    with second_core._lock:
        idle = [h for h in second_core._idle if h.alive()]
        busy = len(second_core._busy)
    assert len(idle) == second_core.IDLE_MAX and busy == 0
    (stopped,) = [h for h in made if h not in idle]
    assert _reaped(stopped.proc)
    for _ in range(3):  # warming with one idle helper starts none
        second_core.warm()
    time.sleep(0.5)
    assert len(made) == 2
