"""The rim of an open 3-complex: which samples' links are discs (analysis/solidholes.py), by hand."""

from __future__ import annotations

import itertools

import numpy as np

from crustview.core.analysis.solidholes import pinched_rim_vertices


def _ball(offset: int = 0) -> np.ndarray:
    """The boundary of a 4-simplex on vertices offset..offset+4, less one tetrahedron: a 3-ball of 4 tetrahedra."""
    tets = [t for t in itertools.combinations(range(5), 4) if t != (1, 2, 3, 4)]
    return np.array(tets) + offset


def test_a_ball_has_disc_links_in_any_vertex_order() -> None:
    ball = _ball()
    assert pinched_rim_vertices(ball).tolist() == []
    assert pinched_rim_vertices(ball[:, ::-1]).tolist() == []  # rows as they come, not sorted


def test_two_balls_sharing_one_vertex_pinch_it() -> None:
    """Rim vertex 1 of one ball is the inner vertex of the other: its link is a disc and a 2-sphere, not one disc."""
    other = _ball(4)
    other[other == 4] = 1  # the second ball's vertex 0 (numbered 4 after the offset) becomes the first's 1
    both = np.vstack([_ball(), other])
    assert pinched_rim_vertices(both).tolist() == [1]
