"""bench_shapes.py's generated meshes have the topology they are built for and the anisotropy they claim."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_shapes import (  # noqa: E402
    decimated,
    holed_shell,
    implicit,
    lathe,
    lattice_ball,
    linked_tori,
    mesh_truth,
    plate,
    profile_cup,
    profile_torus,
    profile_vase,
)


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


@pytest.mark.parametrize(
    ("field", "cells", "betti"),
    [(holed_shell(5, 0.1, 0.3), 40, (1, 8, 1)), (plate(3, 0.18), 40, (1, 18, 1)), (linked_tori, 60, (2, 4, 2))],
)
def test_the_sharp_solids_have_the_topology_they_are_built_for(field, cells: int, betti: tuple) -> None:  # noqa: ANN001
    """A shell with 5 one-sided holes has genus 4, a slab with 3 x 3 holes genus 9, two linked tori are two
    objects of genus 1 (their meshes' own counts, from marching cubes)."""
    verts, faces = implicit(field, 1.3, cells)
    assert mesh_truth(verts, faces) == betti


def test_decimation_keeps_a_share_of_the_faces_and_only_used_vertices() -> None:
    """The quadric decimation keeps about the share of faces asked for, renumbers to the vertices its
    faces use, and here leaves the holed slab's topology (the bench checks it on every mesh)."""
    verts, faces = implicit(plate(3, 0.18), 1.3, 40)
    small_v, small_f = decimated(verts, faces, 0.3)
    assert 0.2 * len(faces) <= len(small_f) <= 0.4 * len(faces)
    assert sorted(np.unique(small_f).tolist()) == list(range(len(small_v)))
    assert mesh_truth(small_v, small_f) == (1, 18, 1)
