"""fill-hole in d >= 3 where no cone fits: the Delaunay faces on a hole's own samples that bound it (Z/2)."""

from __future__ import annotations

import itertools

import numpy as np

from crustview.core.analysis.topology import analyse
from crustview.core.robust.fill_chain import _solve_gf2
from crustview.core.robust.fill_cone import _is_sphere
from crustview.core.robust.patcher import Patcher


def _cross_polytope() -> tuple[np.ndarray, list[tuple[int, ...]]]:
    """S^3 as the boundary of the 4-dimensional cross-polytope: vertex 2i is +e_i, 2i + 1 is -e_i; 16 tetrahedra."""
    pts = np.vstack([s * np.eye(4)[i] for i in range(4) for s in (1, -1)])
    tets = [tuple(2 * i + c for i, c in enumerate(choice)) for choice in itertools.product((0, 1), repeat=4)]
    return pts, tets


def _alive(pt: Patcher) -> list[tuple[int, ...]]:
    return sorted(s for s, a in zip(pt.simp, pt.alive, strict=True) if a)


def test_gf2_solver_on_a_system_checked_by_hand() -> None:
    # x0 + x1 = 1, x1 + x2 = 0, x0 + x2 = 1: rank 2, solutions (1, 0, 0) and (0, 1, 1), kernel {(1, 1, 1)}
    rows, rhs = [0b011, 0b110, 0b101], [1, 0, 1]
    x, kernel = _solve_gf2(rows, rhs, 3)
    assert x in (0b001, 0b110) and kernel == [0b111]
    for r, b in zip(rows, rhs, strict=True):
        assert bin(r & x).count("1") % 2 == b and bin(r & kernel[0]).count("1") % 2 == 0
    assert _solve_gf2([0b1, 0b1], [1, 0], 1) is None  # x0 = 1 and x0 = 0


def test_a_hole_of_two_spheres_sharing_an_edge_is_closed_by_the_faces_that_bound_it() -> None:
    pts, tets = _cross_polytope()
    gone = [(0, 2, 4, 6), (0, 2, 5, 7)]  # +e1 +e2 +e3 +e4 and +e1 +e2 -e3 -e4: they share the edge +e1 +e2 only
    pt = Patcher(pts, [t for t in tets if t not in gone], np.array(tets), 1.0)
    (hole,) = pt.holes()
    hole = [tuple(f) for f in hole]
    assert len(hole) == 8 and not _is_sphere(hole)  # the edge (0, 2) in four of its faces: no cone is tried
    assert pt._chain(hole, "test hole")
    assert _alive(pt) == sorted(tets)
    top = analyse(np.array(_alive(pt)), len(pts), 3)
    assert top.closed_manifold and top.betti == (1, 0, 0, 1)
    assert any("Delaunay faces on its own samples that bound it" in entry[-1] for entry in pt.log)


def test_the_chain_closes_a_two_tetrahedron_hole_and_adds_nothing_where_the_faces_are_not_offered() -> None:
    pts, tets = _cross_polytope()
    gone = [(0, 2, 4, 6), (0, 2, 4, 7)]  # two tetrahedra sharing a face: a hole of 6 faces, a sphere
    pt = Patcher(pts, [t for t in tets if t not in gone], np.array(tets), 1.0)
    (hole,) = pt.holes()
    assert pt._chain([tuple(f) for f in hole], "test hole") and _alive(pt) == sorted(tets)
    # the same hole with one of the two tetrahedra not offered: three of its faces have no candidate, nothing is added
    pt = Patcher(pts, [t for t in tets if t not in gone], np.array([t for t in tets if t != gone[1]]), 1.0)
    before = _alive(pt)
    (hole,) = pt.holes()
    assert not pt._chain([tuple(f) for f in hole], "test hole")
    assert _alive(pt) == before and pt.log == []


def test_fill_cone_falls_back_to_the_chain_where_the_hole_is_no_sphere() -> None:
    """The hook in ``ConeFill._fill_cone``: two spheres sharing an edge get no cone, and the chain closes them."""
    pts, tets = _cross_polytope()
    gone = [(0, 2, 4, 6), (0, 2, 5, 7)]
    pt = Patcher(pts, [t for t in tets if t not in gone], np.array(tets), 1.0)
    (hole,) = pt.holes()
    assert pt._fill_cone([tuple(f) for f in hole], "test hole")
    assert _alive(pt) == sorted(tets) and all("bound it" in entry[-1] for entry in pt.log)


def test_the_chain_leaves_an_opening_open_cap_kept_alone() -> None:
    """A hole whose faces open-cap kept open (``keep_open``) is a real opening: no chain closes it."""
    pts, tets = _cross_polytope()
    gone = [(0, 2, 4, 6), (0, 2, 5, 7)]
    pt = Patcher(pts, [t for t in tets if t not in gone], np.array(tets), 1.0)
    (hole,) = pt.holes()
    pt.keep_open = frozenset(pt.boundary())
    assert not pt._chain([tuple(f) for f in hole], "test hole") and pt.log == []
