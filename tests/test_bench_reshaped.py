"""bench_reshaped.py's pairs are the gap apart at one spacing, and its open scans have the one hole it cut."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_reshaped import build, one_hole, opened, paired, spacing  # noqa: E402

from crustview.core.analysis.topology import analyse  # noqa: E402
from crustview.io import read_mesh  # noqa: E402

RESOURCES = Path(__file__).resolve().parents[1] / "resources"


def _mesh(name: str) -> tuple[np.ndarray, np.ndarray]:
    mesh = read_mesh(RESOURCES / name)
    return np.asarray(mesh.points, float), np.asarray(mesh.simplices(2))


@pytest.mark.parametrize("gap", [1.5, 4.0])
def test_the_pair_is_the_gap_apart_at_one_spacing(gap: float) -> None:
    a, _ = _mesh("3holes.off")
    b, _ = _mesh("bumpy.off")
    moved = paired(a, b, gap)
    h = spacing(a)
    assert spacing(moved) == pytest.approx(h, rel=1e-9)
    assert float(cKDTree(a).query(moved)[0].min()) == pytest.approx(gap * h, rel=1e-9)
    # the second lies wholly beyond the first in x: neither reaches into the other
    assert moved[:, 0].min() - a[:, 0].max() == pytest.approx(gap * h, rel=1e-9)


def test_the_opened_mesh_has_one_hole_of_about_the_share() -> None:
    pts, tris = _mesh("bumpy.off")
    cut = opened(pts, tris, 0.05, seed=3)
    assert cut is not None
    kept, faces = cut
    top = analyse(faces, len(kept), 2)
    assert not top.closed_manifold and top.boundary_faces > 0
    # a sphere with one disc removed: a disc, (1, 0, 0), and every kept vertex in a face
    assert tuple(top.betti) == (1, 0, 0)
    assert np.array_equal(np.unique(faces), np.arange(len(kept)))
    # the ball held 5 % of the vertices, and a vertex outside it whose every face touches it goes too
    assert 0.90 * len(pts) < len(kept) <= 0.95 * len(pts)
    # the kept vertices are the mesh's own, unmoved
    assert cKDTree(pts).query(kept)[0].max() == 0.0


def test_one_hole_refuses_a_pinched_rim_and_two_rims() -> None:
    """Two triangles sharing one vertex: one component, one rim through the vertex twice (a pinch)."""
    bowtie = np.array([[0, 1, 2], [0, 3, 4]])
    assert not one_hole(bowtie, 5)
    # a strip of two triangles: one rim, a disc
    assert one_hole(np.array([[0, 1, 2], [1, 3, 2]]), 4)
    # an annulus (a band of 8 triangles between two squares): connected, two rims
    inner, outer = [0, 1, 2, 3], [4, 5, 6, 7]
    band = [
        t
        for i in range(4)
        for t in ([inner[i], outer[i], outer[(i + 1) % 4]], [inner[i], outer[(i + 1) % 4], inner[(i + 1) % 4]])
    ]
    assert not one_hole(np.array(band), 8)


def test_the_pair_truth_adds_the_objects_and_their_genera() -> None:
    a, ta = _mesh("3holes.off")
    b, tb = _mesh("bumpy.off")
    truth = {"closed": True, "components": 1, "boundary_edges": 0}
    meshes = [("3holes", a, ta, dict(truth, genus=3)), ("bumpy", b, tb, dict(truth, genus=0))]
    made = {name: (pts, faces, t) for name, pts, faces, t in build(meshes, [2.0], None, 0)}
    pts, faces, t = made["3holes+bumpy-gap2"]
    assert (t["components"], t["genus"]) == (2, 3)
    top = analyse(faces, len(pts), 2)
    assert top.closed_manifold and tuple(top.betti) == (2, 6, 2)


def test_pairs_none_means_no_pairs_and_a_bad_gap_is_one_line(tmp_path: Path, capsys) -> None:
    """``--pairs none`` (its help's word for no pairs) was a ValueError traceback; now it means no pairs (so with
    nothing else to make the run stops with argparse's one line), and a gap that is no number is one line too."""
    from bench_reshaped import main

    for pairs, said in (("none", "nothing to make"), ("1.5,x", "comma-separated numbers")):
        with pytest.raises(SystemExit) as ended:
            main(["--folder", str(tmp_path), "--pairs", pairs])
        assert ended.value.code == 2
        err = capsys.readouterr().err
        assert said in err and "Traceback" not in err
