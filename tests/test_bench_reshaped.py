"""bench_reshaped.py's pairs are the gap apart at one spacing, and its open scans have the one hole it cut."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_reshaped import opened, paired, spacing  # noqa: E402

from crustview.core.analysis.topology import analyse  # noqa: E402
from crustview.io import read_mesh  # noqa: E402

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def _mesh(name: str) -> tuple[np.ndarray, np.ndarray]:
    mesh = read_mesh(RESOURCES / name)
    return np.asarray(mesh.points, float), np.asarray(mesh.simplices(2))


@pytest.mark.parametrize("gap", [1.5, 4.0])
def test_the_pair_is_the_gap_apart_at_one_spacing(gap: float) -> None:
    a, _ = _mesh("3holes.off")
    b, _ = _mesh("bumpy.off")
    moved = paired(a, b, gap)
    h = spacing(a)
    assert spacing(moved) == pytest.approx(h, rel=1e-9)
    assert float(cKDTree(a).query(moved)[0].min()) == pytest.approx(gap * h, rel=1e-9)
    # the second lies wholly beyond the first in x: neither reaches into the other
    assert moved[:, 0].min() - a[:, 0].max() == pytest.approx(gap * h, rel=1e-9)


def test_the_opened_mesh_has_one_hole_of_about_the_share() -> None:
    pts, tris = _mesh("bumpy.off")
    cut = opened(pts, tris, 0.05, seed=3)
    assert cut is not None
    kept, faces = cut
    top = analyse(faces, len(kept), 2)
    assert not top.closed_manifold and top.boundary_faces > 0
    # a sphere with one disc removed: a disc, (1, 0, 0), and every kept vertex in a face
    assert tuple(top.betti) == (1, 0, 0)
    assert np.array_equal(np.unique(faces), np.arange(len(kept)))
    # the ball held 5 % of the vertices; the faces touching it take a ring more
    assert 0.90 * len(pts) < len(kept) <= 0.95 * len(pts)
    # the kept vertices are the mesh's own, unmoved
    assert cKDTree(pts).query(kept)[0].max() == 0.0
