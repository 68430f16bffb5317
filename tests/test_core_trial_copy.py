"""``EditableComplex.trial_copy``: a copy to try an edit on, equal to ``copy.deepcopy`` and independent of it."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from crustview.core.robust.complex import _copied
from crustview.core.robust.patcher import Patcher


def _octahedron() -> tuple[np.ndarray, list[tuple[int, ...]]]:
    """The octahedron's 8 triangles over its 6 vertices (a sphere: every edge in two triangles)."""
    pts = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    tri = [tuple(sorted((x, y, z))) for x in (0, 1) for y in (2, 3) for z in (4, 5)]
    return pts, tri


def _same(a: object, b: object) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return type(a) is type(b) and a == b


def test_the_copy_of_an_edited_complex_is_its_deepcopy_and_edits_of_it_stay_in_it():
    pts, tri = _octahedron()
    pt = Patcher(pts, tri, np.zeros((0, 3), np.int64), 1.0)
    pt._delete(pt.index[(0, 2, 4)])  # a hole: the boundary set, the stars and the facet lists in use
    pt.log.append(("a rule", (0, 2, 4), (), (0,), math.nan, "a line"))
    for v in range(6):
        pt._star(v)  # every star made, so that a shared one would show
    pt._ids((1, 3))  # and a facet's list of simplices
    ref = copy.deepcopy(pt)
    new = pt.trial_copy()
    assert new.__dict__.keys() == ref.__dict__.keys()
    for key in ref.__dict__:
        assert _same(ref.__dict__[key], new.__dict__[key]), key
    # an edit of the copy: the original is still, attribute for attribute, what it was (its simplices, boundary,
    # stars, the facets' lists of simplices, the index and the log): nothing of it is shared with the copy
    new._delete(new.index[(1, 3, 5)])
    assert sum(new.alive) == 6 and sum(pt.alive) == 7
    for key in ref.__dict__:
        assert _same(ref.__dict__[key], pt.__dict__[key]), key
    assert (1, 3) in new.bset and (1, 3) not in pt.bset
    assert new.fmap[(1, 3)] is not pt.fmap[(1, 3)] and len(pt.fmap[(1, 3)]) == 2  # (1, 3)'s two triangles


def test_a_container_nested_deeper_than_the_complex_keeps_one_is_refused_not_shared():
    assert _copied({1: [2, 3]}, 2) == {1: [2, 3]}
    with pytest.raises(TypeError, match="nested deeper"):
        _copied({1: [[2]]}, 2)
    with pytest.raises(TypeError, match="no rule"):
        _copied(object(), 2)
