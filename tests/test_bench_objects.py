"""bench_objects.py places its two objects the gap it says apart, with the pair's Betti numbers."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_objects import pair  # noqa: E402

from crustview.core.samples.manifolds import get_manifold  # noqa: E402


@pytest.mark.parametrize(("kind", "betti"), [("spheres", (2, 0, 2)), ("sphere-torus", (2, 2, 2)), ("tori", (2, 4, 2))])
@pytest.mark.parametrize("gap", [1.0, 6.0])
def test_the_two_objects_are_the_gap_apart(kind: str, betti: tuple, gap: float) -> None:
    pts, b = pair(kind, gap, 0.0, seed=1)
    assert b == betti
    first = get_manifold("sphere" if kind != "tori" else "torus").default_n
    a, c = pts[:first], pts[first:]
    h = float(np.median(np.concatenate([cKDTree(x).query(x, k=2)[0][:, 1] for x in (a, c)])))
    closest = float(cKDTree(a).query(c)[0].min())
    # every point of the second is gap h or more beyond the first's largest x; round objects sampled
    # about h apart have their closest two points within a spacing or two of that
    assert gap * h * (1 - 1e-9) <= closest <= (gap + 2) * h
