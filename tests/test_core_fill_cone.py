"""fill-hole in d >= 3: a hole of a 3-manifold closed by a cone from one of its vertices, all or nothing."""

from __future__ import annotations

import itertools

import numpy as np

from crustview.core.analysis.topology import analyse
from crustview.core.robust.patcher import Patcher


def _boundary_of_4_simplex() -> tuple[np.ndarray, list[tuple[int, ...]]]:
    """S^3 as the boundary of a 4-simplex: 5 points of R^4 and its 5 tetrahedra (checkable on paper)."""
    pts = np.vstack([np.eye(4), np.full((1, 4), -0.3)])
    return pts, [tuple(t) for t in itertools.combinations(range(5), 4)]


def _closed(pt: Patcher) -> bool:
    alive = np.array([s for s, a in zip(pt.simp, pt.alive, strict=True) if a])
    top = analyse(alive, 5, 3)
    return top.closed_manifold and top.betti == (1, 0, 0, 1)


def test_one_missing_tetrahedron_is_put_back_when_no_delaunay_face_may_close_it() -> None:
    pts, tets = _boundary_of_4_simplex()
    # no Delaunay face to offer: only the cone can close the hole (its 4 faces, one tetrahedron's boundary)
    pt = Patcher(pts, tets[1:], np.empty((0, 4), np.int64), 1.0)
    (hole,) = pt.holes()
    assert len(hole) == 4
    assert pt.fill(hole)
    assert _closed(pt) and (0, 1, 2, 3) in pt.index
    assert pt.log[-1][0] == "fill-hole" and "cone" in pt.log[-1][-1]


def test_two_missing_tetrahedra_are_closed_by_a_cone_from_a_vertex() -> None:
    pts, tets = _boundary_of_4_simplex()
    pt = Patcher(pts, tets[2:], np.empty((0, 4), np.int64), 1.0)
    (hole,) = pt.holes()
    assert len(hole) == 6  # two tetrahedra's 8 faces less the one they share
    assert pt.fill(hole)
    assert _closed(pt)
    assert sum(entry[0] == "fill-hole" for entry in pt.log) == 2


class _NoCone(Patcher):
    """A Patcher whose cones never fit (fault injection: the erosion's undo is what is tested)."""

    def _fill_cone(self, hole, why):  # noqa: ANN001, ANN202
        return False


def test_an_erosion_that_does_not_close_the_hole_is_undone() -> None:
    pts, tets = _boundary_of_4_simplex()
    pt = _NoCone(pts, tets[1:], np.empty((0, 4), np.int64), 1.0)
    before = sorted(s for s, a in zip(pt.simp, pt.alive, strict=True) if a)
    (hole,) = pt.holes()
    assert not pt.fill(hole)
    assert sorted(s for s, a in zip(pt.simp, pt.alive, strict=True) if a) == before
    assert pt.log == [] and sorted(pt.boundary()) == sorted(hole)
    assert sorted(pt.index) == before
