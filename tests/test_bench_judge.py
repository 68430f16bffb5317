"""bench_scans.py's judgement of a wrong result's flags: do they name the kind that is wrong?

Worked out by hand on small triangle sets and hand-made rows (no reconstruction): ``rims`` counts boundary
curves and says whether one is pinched, and ``Row.unnamed`` lists the kinds (components, handles, holes) in
which a wrong result differs from the truth without an uncertain feature of that kind.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from _kinds import rims  # noqa: E402
from bench_scans import Case, Row  # noqa: E402

#: The boundary of a tetrahedron: closed, no rim.
TETRA = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])


def _grid(n: int) -> np.ndarray:
    """The triangles of an n x n grid of unit squares over the (n + 1)^2 vertices i * (n + 1) + j."""
    out = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = i * (n + 1) + j, (i + 1) * (n + 1) + j, (i + 1) * (n + 1) + j + 1, i * (n + 1) + j + 1
            out += [(a, b, c), (a, c, d)]
    return np.array(out)


def test_rims_are_counted_as_boundary_curves() -> None:
    assert rims(TETRA, 4) == (0, False)
    assert rims(TETRA[:3], 4) == (1, False)  # one face taken out: one triangle-shaped hole
    assert rims(TETRA[:1], 4) == (1, False)  # a lone triangle has one rim
    two = np.r_[TETRA[:1], TETRA[:1] + 4]  # two lone triangles
    assert rims(two, 8) == (2, False)
    assert rims(np.zeros((0, 3), np.int64), 0) == (0, False)


def test_an_annulus_has_two_rims_and_a_pinch_is_said() -> None:
    grid = _grid(3)  # 16 vertices, 18 triangles; the middle square is squares (1, 1): triangles 8 and 9
    annulus = np.delete(grid, [8, 9], axis=0)
    assert rims(annulus, 16) == (2, False)
    # a square at a corner of the middle one taken out too: the two holes meet at vertex 5, one curve
    pinched = np.delete(grid, [0, 1, 8, 9], axis=0)
    count, pinch = rims(pinched, 16)
    assert count == 1 and pinch


def _row(truth, betti, closed, rims_, uncertain, case_betti=(), case_rims=(0, False), small=0, used=10) -> Row:
    case = Case("x", np.zeros((10, 3)), truth, 0.0, case_betti, small, None, case_rims)
    return Row(case, "crustview", betti, closed, used, 10, 0 if closed else 3, uncertain, rims=rims_)


def test_a_false_handle_beside_a_flagged_planar_rim_is_unnamed() -> None:
    """The hand at 0.3 h, noise draw 51: the truth open, genus 1, one rim (Betti (1, 2, 0)); the result open
    with one rim and Betti (1, 4, 0), genus 2, its only flag a hole (the wrist's planar rim)."""
    truth = {"closed": False}
    flagged = {"handle": 0, "hole": 1, "component": 0}
    row = _row(truth, (1, 4, 0), False, (1, False), flagged, (1, 2, 0), (1, False))
    assert not row.right and row.flagged
    assert row.unnamed == ["handle"]
    named = _row(truth, (1, 4, 0), False, (1, False), dict(flagged, handle=1), (1, 2, 0), (1, False))
    assert named.unnamed == []


def test_each_kind_of_a_closed_truth_is_judged() -> None:
    truth = {"closed": True, "components": 7, "genus": 2}
    # seven objects fused into one of genus 5, flagged by handles and holes only: the components are unnamed
    assert _row(truth, (1, 10, 1), True, (0, False), {"handle": 14, "hole": 14}).unnamed == ["component"]
    # three pieces of genus 0 for seven of genus 2, nothing flagged but a handle
    assert _row(truth, (3, 0, 3), True, (0, False), {"handle": 1}).unnamed == ["component"]
    assert _row(truth, (3, 0, 3), True, (0, False), {}).unnamed == ["component", "handle"]
    # the right topology is never judged
    assert _row(truth, (7, 4, 7), True, (0, False), {}).right
    assert _row(truth, (7, 4, 7), True, (0, False), {}).unnamed is None


def test_an_open_result_of_a_closed_truth_says_so_itself() -> None:
    """A closed truth whose result is not closed: the result calls itself NOT a closed manifold, which names
    its holes; its handles still need a flag of their own."""
    truth = {"closed": True, "components": 1, "genus": 0}
    row = _row(truth, (1, 0, 0), False, (1, False), {})
    assert row.flagged and row.unnamed == []
    extra_handle = _row(truth, (1, 2, 0), False, (1, False), {})  # genus 1 and a hole, for a sphere
    assert extra_handle.unnamed == ["handle"]


def test_an_open_truth_closed_over_is_an_unnamed_hole() -> None:
    """The holes cut into a mesh and closed by the labelling (bench_reshaped --opened): quiet, and with an
    unrelated flag still unnamed."""
    truth = {"closed": False}
    quiet = _row(truth, (1, 0, 1), True, (0, False), {}, (1, 0, 0), (1, False))
    assert not quiet.right and not quiet.flagged
    other = _row(truth, (1, 0, 1), True, (0, False), {"handle": 2}, (1, 0, 0), (1, False))
    assert other.unnamed == ["hole"]


def test_rims_under_a_spacing_may_close_but_not_open() -> None:
    """A truth with one real opening and two rims under a spacing (Betti (1, 2, 0), three rims): a result
    that keeps only the opening is not wrong in its holes; one with a fourth hole is."""
    truth = {"closed": False}
    kept_one = _row(truth, (1, 0, 0), False, (1, False), {}, (1, 2, 0), (3, False), small=2)
    assert not kept_one.right  # its Betti numbers are not the mesh's, which has the tiny holes too
    assert kept_one.unnamed == []
    four = _row(truth, (1, 3, 0), False, (4, False), {}, (1, 2, 0), (3, False), small=2)
    assert four.unnamed == ["hole"]


def test_pinched_rims_and_odd_counts_judge_handles_and_holes_together() -> None:
    """Two holes through one vertex are one curve: Betti (1, 1, 0) with one rim reads as half a handle.
    Either flag names the pair of kinds; neither leaves it unnamed."""
    truth = {"closed": False}
    for flags in ({"hole": 1}, {"handle": 1}):
        row = _row(truth, (1, 1, 0), False, (1, True), flags, (1, 0, 0), (1, False))
        assert row.unnamed == []
    row = _row(truth, (1, 1, 0), False, (1, True), {}, (1, 0, 0), (1, False))
    assert row.unnamed == ["handle or hole"]
    # a non-manifold truth (the owl's mesh: b1 3 with 5 rims, a handle count of -1)
    owl = _row(truth, (1, 0, 0), False, (1, False), {"hole": 1}, (1, 3, 0), (5, False), small=4)
    assert owl.unnamed == []


def test_rows_that_cannot_be_judged_say_none() -> None:
    truth = {"closed": True, "components": 1, "genus": 1}
    assert _row(truth, (1, 0, 1), True, None, {}).unnamed is None  # a peer: no faces, no rims
    assert _row(truth, (0, 0, 0), True, (0, False), {}, used=0).unnamed is None  # an empty M_S (FAILED)
    no_truth = Row(
        Case("x", np.zeros((10, 3)), truth, 0.0), "crustview", (1, 0, 1), True, 10, 10, 0, {}, rims=(0, False)
    )
    assert no_truth.unnamed is None  # a case whose true rims were not counted
