"""Two complexes compared: the core diff and `crustview compare`."""

from __future__ import annotations

import json

import numpy as np
import pytest

from crustview.core.analysis.complexdiff import diff_complexes


def _square():
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    return pts, np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def test_diff_counts_by_hand_and_vertex_matching_across_orders():
    pts, ring = _square()
    # B: the same square's points in another order, with one edge replaced by the diagonal 1-3
    perm = np.array([2, 0, 3, 1])  # B's row j is A's point perm[j]
    pb = pts[perm]
    inv = np.argsort(perm)
    b = inv[np.array([[0, 1], [1, 2], [2, 3], [1, 3]])]  # in A's numbering: 01, 12, 23, 13
    diff = diff_complexes(pts, ring, pb, b, 1)
    assert diff.matched
    assert len(diff.both) == 3 and diff.only_a.tolist() == [[0, 3]] and diff.only_b.tolist() == [[1, 3]]
    # a point (0, t) of A's edge 0-3 is t from B's edge 0-1, 1 - t from 2-3 and (1 - t)/sqrt 2 from the
    # diagonal x + y = 1: the largest min(t, (1 - t)/sqrt 2) is at t = 1/(1 + sqrt 2) = sqrt 2 - 1
    assert diff.hausdorff.a_to_b == pytest.approx(np.sqrt(2) - 1, abs=diff.hausdorff.error_bound + 1e-9)


def test_diff_without_shared_vertices_reports_only_the_distance():
    pts, ring = _square()
    diff = diff_complexes(pts, ring, pts + [0.0, 2.0], ring, 1)
    assert not diff.matched and diff.counts()["both"] is None
    assert diff.hausdorff.distance == pytest.approx(2.0, abs=diff.hausdorff.error_bound + 1e-9)


def test_cli_compare_saved_result_against_another_test(tmp_path, capsys):
    from crustview.__main__ import main
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_points, write_result

    s = get_manifold("sphere").sample(400, seed=0)
    write_points(tmp_path / "s.npy", s.points)
    rec = reconstruct(s.points, 2)
    write_result(tmp_path / "s.npz", rec)
    lit = reconstruct(s.points, 2, test="literal")
    assert (
        main(
            [
                "compare",
                str(tmp_path / "s.npz"),
                f"{tmp_path / 's.npy'}@d=2,test=literal",
                "--json",
                str(tmp_path / "c.json"),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    got = json.loads((tmp_path / "c.json").read_text())
    a = {tuple(r) for r in np.sort(rec.manifold_input_simplices(), axis=1)}
    b = {tuple(r) for r in np.sort(lit.manifold_input_simplices(), axis=1)}
    assert (got["both"], got["only_a"], got["only_b"]) == (len(a & b), len(a - b), len(b - a))
    assert f"{len(a & b)} simplices in both" in text
    assert "literal" in got["b"] and got["topology_a"]["closed_manifold"]
    # a result against itself: nothing differs, distance 0
    assert main(["compare", str(tmp_path / "s.npz"), str(tmp_path / "s.npz")]) == 0
    assert "0 only in A, 0 only in B; Hausdorff distance 0 " in capsys.readouterr().out


def test_cli_compare_errors_are_one_line(tmp_path, capsys):
    from crustview.__main__ import main

    assert main(["compare", str(tmp_path / "missing.npz"), str(tmp_path / "x.npz")]) == 2
    assert "does not exist" in capsys.readouterr().err
    np.save(tmp_path / "p.npy", np.random.default_rng(0).normal(size=(30, 3)))
    assert main(["compare", f"{tmp_path / 'p.npy'}@colour=red", f"{tmp_path / 'p.npy'}"]) == 2
    assert "@test=" in capsys.readouterr().err


def test_cli_compare_takes_d_from_a_meshs_faces(tmp_path, capsys):
    """A result against the triangle mesh it came from: the mesh's faces say d = 2 (a new user was asked for
    it); a point file still needs it, in one line."""
    from crustview.__main__ import main
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_result
    from crustview.meshfiles.off import write_off

    s = get_manifold("sphere").sample(300, seed=1)
    rec = reconstruct(s.points, 2)
    write_result(tmp_path / "s.npz", rec)
    write_off(tmp_path / "m.off", s.points, rec.manifold_input_simplices())
    assert main(["compare", str(tmp_path / "s.npz"), str(tmp_path / "m.off")]) == 0
    out = capsys.readouterr().out
    assert "m.off (mesh faces)" in out and f"{len(rec.manifold)} simplices in both, 0 only in A" in out
    np.savetxt(tmp_path / "p.xyz", s.points)
    assert main(["compare", str(tmp_path / "p.xyz"), str(tmp_path / "m.off")]) == 2
    assert "give d for 'p.xyz'" in capsys.readouterr().err
