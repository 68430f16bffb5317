"""Algorithm 3's compiled loop (core/paper/_prune.cpp) against the Python loop, step for step."""

from __future__ import annotations

import math
import threading
from pathlib import Path

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.errors import Cancelled
from crustview.core.paper import compiled_loop
from crustview.core.paper.extraction import extract
from crustview.core.samples.manifolds import get_manifold


def test_the_compiled_loop_is_built():
    """The install builds it (scripts/install.sh); without it every comparison below would mean nothing."""
    assert compiled_loop._prune is not None


RESOURCES = Path(__file__).parents[1] / "resources"


def assert_same_extraction(a, b) -> None:
    """Every step's every field (NaN angles equal), removed_at, the stop and the notes."""
    assert len(a.steps) == len(b.steps)
    for x, y in zip(a.steps, b.steps):
        assert (x.index, x.rule, x.tau, x.kept, x.removed, x.reason, x.added, x.cause) == (
            y.index,
            y.rule,
            y.tau,
            y.kept,
            y.removed,
            y.reason,
            y.added,
            y.cause,
        )
        assert type(x.angle) is type(y.angle) is float
        assert x.angle == y.angle or (math.isnan(x.angle) and math.isnan(y.angle))
        assert all(type(v) is int for v in (*y.tau, *y.kept, *y.removed, y.cause))
    assert a.removed_at.dtype == b.removed_at.dtype and np.array_equal(a.removed_at, b.removed_at)
    assert np.array_equal(a.simplices, b.simplices) and np.array_equal(a.holes, b.holes)
    assert (a.stopped, a.notes) == (b.stopped, b.notes)


def both(points, tset, **kwargs):
    return extract(points, tset, compiled=False, **kwargs), extract(points, tset, **kwargs)


# (manifold, n, test): closed results, empty ones, prune and resolve steps, codimension 1 to 3
CASES = [
    ("trefoil", 300, "literal"),
    ("torus", None, "cocone"),
    ("sphere", 500, "literal"),
    ("clifford-torus", None, "cocone"),
    ("flat-klein", None, "cocone-all"),
    ("sphere-r4", None, "cocone"),
    ("s3", 300, "literal"),
    ("circle-r4", None, "literal"),
]


@pytest.mark.parametrize(("name", "n", "test"), CASES)
def test_compiled_loop_takes_the_python_loops_steps_on_builtins(name, n, test):
    m = get_manifold(name)
    rec = reconstruct(m.sample(n or m.default_n, seed=0).points, m.d, mode="paper")
    tset = rec.candidates.select(test, rec.theta)
    rules = set()
    for prune_boundary in (True, False):
        for stop in (False, True):
            a, b = both(rec.points, tset, prune_boundary=prune_boundary, stop_when_sample_lost=stop)
            assert_same_extraction(a, b)
            rules |= {s.rule for s in a.steps}
    assert rules  # every case takes steps


def test_compiled_loop_takes_the_python_loops_steps_on_scans():
    # the horse's T_S has facets in 3, 4 and more triangles (resolve steps with cascades) and is eaten
    # from its holes; the casting's loses samples (stop_when_sample_lost)
    from crustview.io import read_mesh

    resolves = 0
    runs = {"horse-quads.obj": ({}, {"prune_boundary": False}, {"stop_when_sample_lost": True})}
    runs["casting.off"] = ({}, {"stop_when_sample_lost": True})  # 18,791 prunes and 319 resolves to closed
    for file, options in runs.items():
        pts = np.asarray(read_mesh(RESOURCES / file).points, float)
        rec = reconstruct(pts, 2, mode="paper")
        tset = rec.candidates.select(rec.test, rec.theta)
        for kwargs in options:
            a, b = both(rec.points, tset, **kwargs)
            assert_same_extraction(a, b)
            resolves += sum(s.rule == "resolve-nonmanifold" for s in a.steps)
    assert resolves > 10


def test_compiled_loop_reports_progress_and_cancels_where_the_python_loop_does():
    m = get_manifold("torus")
    rec = reconstruct(m.sample(m.default_n, seed=0).points, m.d, mode="paper")
    tset = rec.candidates.select("literal", rec.theta)
    calls: list[list[float]] = [[], []]
    for compiled, out in zip((False, True), calls):
        extract(rec.points, tset, compiled=compiled, progress=out.append)
    assert calls[0] == calls[1] and len(calls[0]) > 1

    class Counting:
        """Set after its third question: both loops must stop at the same step."""

        def __init__(self) -> None:
            self.asked = 0
            self.event = threading.Event()

        def is_set(self) -> bool:
            self.asked += 1
            return self.asked >= 3

    asked = []
    for compiled in (False, True):
        cancel = Counting()
        with pytest.raises(Cancelled):
            extract(rec.points, tset, compiled=compiled, cancel=cancel)
        asked.append(cancel.asked)
    assert asked == [3, 3]


def test_non_finite_vectors_take_the_python_loop(monkeypatch):
    # a NaN angle would make the heap's order depend on how ties compare: the reference runs instead
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]])
    tris = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4], [1, 2, 3]])
    ran = []
    monkeypatch.setattr(compiled_loop, "run", lambda *a, **k: ran.append(1))
    extract(pts, tris)
    assert ran == [1]
    ran.clear()
    bad = pts.copy()
    bad[4] = np.nan
    extract(bad, tris)
    assert ran == []
