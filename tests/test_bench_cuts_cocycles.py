"""The truth test of ``benchmarks/bench_cuts.py``: which loops are non-trivial, on meshes checkable by hand."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_cuts import Cocycles  # noqa: E402


def grid_torus(a: int, b: int, offset: int = 0) -> np.ndarray:
    """The a x b grid on the torus, each square cut in two triangles; vertex (i, j) is offset + i * b + j."""

    def v(i: int, j: int) -> int:
        return offset + (i % a) * b + (j % b)

    faces = []
    for i in range(a):
        for j in range(b):
            faces += [[v(i, j), v(i + 1, j), v(i + 1, j + 1)], [v(i, j), v(i + 1, j + 1), v(i, j + 1)]]
    return np.array(faces, np.int64)


def test_the_torus_has_two_cocycles_and_its_two_circles_are_non_trivial():
    c = Cocycles(16, grid_torus(4, 4))
    assert len(c.cocycles) == 2  # 2g, g = 1
    assert c.nontrivial([0, 4, 8, 12])  # i runs around: one circle
    assert c.nontrivial([0, 1, 2, 3])  # j runs around: the other
    assert c.nontrivial([0, 5, 10, 15])  # the diagonal: their sum, non-trivial too
    assert not c.nontrivial([0, 4, 5])  # a triangle's boundary
    assert not c.nontrivial([0, 4, 5, 1])  # a square's
    assert not c.nontrivial([0, 4, 8, 12, 0, 4, 8, 12])  # one circle twice: zero mod 2
    # a step that is not an edge follows the mesh's shortest path: on the 5 x 5 torus the only two-edge
    # path from (0, 0) to (2, 0) runs through (1, 0), so [0, 10, 15, 20] is the whole i circle
    five = Cocycles(25, grid_torus(5, 5))
    assert five.nontrivial([0, 10, 15, 20])
    assert not five.nontrivial([0, 10, 5])  # there and back along the same path


def test_the_octahedron_has_none():
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    c = Cocycles(6, faces)
    assert c.cocycles == []
    assert not c.nontrivial([0, 2, 1, 3])


def test_two_tori_one_file_and_a_loop_across_them():
    faces = np.vstack([grid_torus(4, 4), grid_torus(3, 5, offset=16)])
    c = Cocycles(31, faces)
    assert len(c.cocycles) == 4
    assert c.nontrivial([16, 21, 26])  # the second torus's i circle
    assert not c.nontrivial([16, 17, 22])
    assert c.nontrivial([0, 16, 1]) is None  # 0 -> 16 is no path of the mesh
