"""bench_shapes.py's generated meshes have the topology they are built for and the anisotropy they claim."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_shapes import implicit, lathe, lattice_ball, mesh_truth, profile_cup, profile_torus, profile_vase  # noqa: E402


@pytest.mark.parametrize(
    ("profile", "loop", "betti"),
    [(profile_vase(), False, (1, 0, 1)), (profile_cup(0.12), False, (1, 0, 1)), (profile_torus(), True, (1, 2, 1))],
)
def test_a_turned_mesh_is_closed_with_its_profile_s_topology(profile: np.ndarray, loop: bool, betti: tuple) -> None:
    verts, faces = lathe(profile, 48, 3.0, closed_loop=loop)
    assert mesh_truth(verts, faces) == betti


def test_rings_are_the_ratio_farther_apart_than_the_vertices_along_them() -> None:
    # the torus: every ring has the same radius range, so along / across spacings are easy to tell apart
    verts, faces = lathe(profile_torus(), 96, 3.0, closed_loop=True)
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [0, 2]]])
    length = np.linalg.norm(verts[e[:, 0]] - verts[e[:, 1]], axis=1)
    along = np.isclose(verts[e[:, 0], 2], verts[e[:, 1], 2])  # both ends on one ring (same height)
    # rings at the tube's top and bottom share heights with their neighbours only there; the ratio of the
    # medians is what the generator promises, up to the resampling's rounding and the stagger
    ratio = np.median(length[~along]) / np.median(length[along])
    assert 2.4 <= ratio <= 3.6


def test_a_mesh_with_a_boundary_has_no_truth() -> None:
    verts, faces = lathe(profile_vase(), 24, 1.5)
    assert mesh_truth(verts, faces[1:]) is None


def test_the_lattice_ball_has_genus_twice_its_lines_less_one() -> None:
    verts, faces = implicit(lattice_ball(3), 1.2, 40)
    assert mesh_truth(verts, faces) == (1, 2 * (2 * 3 - 1), 1)
    h = np.median(cKDTree(verts).query(verts, k=2)[0][:, 1])
    assert 0 < h < 0.1
