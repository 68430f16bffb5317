"""bench_scans.py's judgement of a wrong result's flags: do they name the kind that is wrong?

Worked out by hand on small triangle sets and hand-made rows (no reconstruction): ``rims`` counts boundary
curves, and ``Row.unnamed`` lists the kinds (components, handles, holes) in which a wrong result differs
from the truth without an uncertain feature of that kind.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_scans import Case, Row, rims  # noqa: E402

#: The boundary of a tetrahedron: closed, no rim.
TETRA = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])


def test_rims_are_counted_as_boundary_curves() -> None:
    assert rims(TETRA, 4) == 0
    assert rims(TETRA[:3], 4) == 1  # one face taken out: one triangle-shaped hole
    assert rims(TETRA[:1], 4) == 1  # a lone triangle has one rim
    two = np.r_[TETRA[:1], TETRA[:1] + 4]  # two lone triangles
    assert rims(two, 8) == 2
    assert rims(np.zeros((0, 3), np.int64), 0) == 0


def _row(truth: dict, betti: tuple, closed: bool, rims_: int, uncertain: dict, case_betti=(), case_rims=0) -> Row:
    case = Case("x", np.zeros((10, 3)), truth, 0.0, case_betti, 0, None, case_rims)
    return Row(case, "crustview", betti, closed, 10, 10, 0 if closed else 3, uncertain, rims=rims_)


def test_a_false_handle_beside_a_flagged_planar_rim_is_unnamed() -> None:
    """The hand at 0.3 h, noise draw 51: the truth open, genus 1, one rim (Betti (1, 2, 0)); the result open
    with one rim and Betti (1, 4, 0), genus 2, its only flag a hole (the wrist's planar rim)."""
    truth = {"closed": False}
    flagged = {"handle": 0, "hole": 1, "component": 0}
    row = _row(truth, (1, 4, 0), False, 1, flagged, case_betti=(1, 2, 0), case_rims=1)
    assert not row.right and row.flagged
    assert row.unnamed == ["handle"]
    named = _row(truth, (1, 4, 0), False, 1, dict(flagged, handle=1), case_betti=(1, 2, 0), case_rims=1)
    assert named.unnamed == []


def test_a_closed_result_for_a_closed_truth_names_each_kind_it_misses() -> None:
    truth = {"closed": True, "components": 7, "genus": 2}
    # seven objects fused into one of genus 5, flagged by handles and holes only: the components are unnamed
    row = _row(truth, (1, 10, 1), True, 0, {"handle": 14, "hole": 14, "component": 0})
    assert row.unnamed == ["component"]
    # the right topology is never unnamed
    assert _row(truth, (7, 4, 7), True, 0, {}).right
    assert _row(truth, (7, 4, 7), True, 0, {}).unnamed == []


def test_an_open_result_of_a_closed_truth_says_so_itself() -> None:
    """A closed truth whose result is not closed: the result calls itself NOT a closed manifold, which names
    its holes; its handles still need a flag of their own."""
    truth = {"closed": True, "components": 1, "genus": 0}
    row = _row(truth, (1, 0, 0), False, 1, {})
    assert row.flagged and row.unnamed == []
    extra_handle = _row(truth, (1, 2, 0), False, 1, {})  # genus 1 and a hole, for a sphere
    assert extra_handle.unnamed == ["handle"]


def test_an_open_truth_closed_over_is_an_unnamed_hole() -> None:
    """The holes cut into a mesh and closed by the labelling (bench_reshaped --opened): quiet, and with an
    unrelated flag still unnamed."""
    truth = {"closed": False}
    quiet = _row(truth, (1, 0, 1), True, 0, {}, case_betti=(1, 0, 0), case_rims=1)
    assert not quiet.right and not quiet.flagged
    other = _row(truth, (1, 0, 1), True, 0, {"handle": 2}, case_betti=(1, 0, 0), case_rims=1)
    assert other.unnamed == ["hole"]
