"""``-d auto`` on a mesh file: its faces decide where local PCA of its vertices chose a d they cannot have."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from crustview.core.analysis.dimension import DimensionEstimate, estimate_dimension, with_faces
from crustview.meshfiles.mesh import MeshData


def _mesh(points, *blocks) -> MeshData:
    return MeshData(np.asarray(points, float), [np.asarray(b, np.int64) for b in blocks], Path("m.off"))


SQUARE = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
R4 = [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


@pytest.mark.parametrize(
    ("points", "blocks", "fits"),
    [
        (SQUARE, [[[0, 1, 2], [0, 2, 3]]], [2]),  # triangles in R^3
        (SQUARE, [[[0, 1], [1, 2]]], [1]),  # segments
        (SQUARE, [[[0, 1, 2, 3]]], [2]),  # a quad is two triangles; no tetrahedron lives in R^3 (d < k)
        (R4, [[[0, 1, 2, 3], [1, 2, 3, 4]]], [2, 3]),  # four vertices in R^4: quads or tetrahedra
        (SQUARE, [[[0, 1, 2]], [[2, 3]]], []),  # triangles and segments: no single d
        (SQUARE, [], []),  # no faces at all
    ],
)
def test_the_dimensions_a_files_faces_fit(points, blocks, fits):
    mesh = _mesh(points, *blocks)
    assert mesh.fitting_dimensions() == fits
    for d in fits:  # each listed d is one simplices() takes
        assert mesh.simplices(d).shape[1] == d + 1


def test_faces_overrule_an_estimate_they_do_not_fit_and_keep_one_they_do():
    pca = DimensionEstimate(1, 0.98, {1: 0.98, 2: 0.02}, 100.0, (6, 12), 600)
    taken = with_faces(pca, [2])
    assert (taken.d, taken.confidence, taken.samples_d) == (2, 1.0, 1)
    assert taken.votes == pca.votes  # what local PCA saw stays in the report
    assert "taken from the file's faces" in taken.sentence() and "1 large direction (98%" in taken.sentence()
    assert taken.as_dict()["decided_by"] == "the file's faces" and taken.as_dict()["local_pca_d"] == 1
    assert with_faces(pca, [1]) is pca and with_faces(pca, []) is pca  # faces that agree, or none
    assert with_faces(DimensionEstimate(1, 0.9), [2, 3]).d == 2  # several fit: the nearest to the estimate


def _rings_cylinder(n: int = 120, height: float = 6.0) -> tuple[np.ndarray, np.ndarray]:
    """A closed cylinder meshed as CAD tools do: vertices on its two end circles only (and each end's centre),
    its side in long thin triangles from circle to circle, each end a fan."""
    t = 2 * np.pi * np.arange(n) / n
    ring = np.c_[np.cos(t), np.sin(t)]
    pts = np.vstack([np.c_[ring, np.zeros(n)], np.c_[ring, np.full(n, height)], [[0, 0, 0], [0, 0, height]]])
    i = np.arange(n)
    j = (i + 1) % n
    side = np.vstack([np.c_[i, j, n + i], np.c_[j, n + j, n + i]])
    ends = np.vstack([np.c_[np.full(n, 2 * n), j, i], np.c_[np.full(n, 2 * n + 1), n + i, n + j]])
    return pts, np.vstack([side, ends])


def test_a_cad_cylinder_meshed_on_its_end_circles_is_reconstructed_as_a_surface(tmp_path):
    pts, tris = _rings_cylinder()
    assert estimate_dimension(pts).d == 1  # its vertices alone look like curves: the case this is about
    path = tmp_path / "cylinder.off"
    lines = ["OFF", f"{len(pts)} {len(tris)} 0"]
    lines += [" ".join(f"{c:.17g}" for c in p) for p in pts] + [f"3 {a} {b} {c}" for a, b, c in tris]
    path.write_text("\n".join(lines) + "\n")
    proc = subprocess.run(
        [sys.executable, "-m", "crustview", "reconstruct", str(path), "-d", "auto", "-o", str(tmp_path / "c.npz")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    assert "-d auto chose d = 2 (a surface), taken from the file's faces" in proc.stderr
    assert "Reconstructed a surface in R^3" in proc.stdout
    # the d its faces fit, given by hand: local PCA's 1 does not question it (the faces are the file's own word)
    from crustview.core.analysis.dimension import contradiction
    from crustview.io import read_mesh

    mesh = read_mesh(path)
    assert contradiction(mesh.points, 2, mesh) is None and contradiction(mesh.points, 2).d == 1
    # a strip of quads in R^4 fits d = 2 and d = 3: a given 3 is the file's word too, and was questioned by a
    # "d = 2, taken from the file's faces" on half the votes (a review)
    strip = tmp_path / "strip.off"
    n = 300
    verts = [f"{x} {y} 0 0" for x in range(n) for y in (0, 1)]
    quads = [f"4 {2 * i} {2 * i + 2} {2 * i + 3} {2 * i + 1}" for i in range(n - 1)]
    strip.write_text("\n".join(["nOFF", "4", f"{2 * n} {n - 1} 0", *verts, *quads]) + "\n")
    quad_mesh = read_mesh(strip)
    assert {2, 3} <= set(quad_mesh.fitting_dimensions())
    assert contradiction(quad_mesh.points, 3, quad_mesh) is None
