"""M_S against a ground-truth mesh: face recovery, topology, sampled Hausdorff distance."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from crustview.core import InputError, reconstruct
from crustview.core.analysis.compare import compare_complexes, compare_to_mesh, dense_samples, hausdorff

RESOURCES = Path(__file__).resolve().parents[1] / "resources"

# the regular octahedron: vertices +-e_i, 8 faces
OCTA = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
FACES = np.array([[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2], [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]])
# the edge e1-e3 (rows 0, 4) flipped to e2-(-e2): faces (e1,e2,e3), (e1,e3,-e2) become
# (e1,e2,-e2) in the plane z = 0 and (e3,e2,-e2) in the plane x = 0
FLIPPED = np.vstack([[[0, 2, 3], [4, 2, 3]], FACES[2:]])


def test_octahedron_against_itself():
    c = compare_complexes(OCTA, FACES, FACES[::-1, ::-1], 2)
    assert (c.mesh_faces, c.result_faces, c.recovered, c.extra) == (8, 8, 8, 0)
    assert c.recovered_share == 1.0
    assert c.hausdorff.distance == 0.0  # identical complexes are sampled identically
    for top in (c.mesh_topology, c.result_topology):
        assert top.closed_manifold and top.betti == (1, 0, 1) and c.genus(top) == 0


def test_octahedron_with_a_flipped_edge():
    """Worked on paper: the new edge passes through the origin, 1/sqrt(3) from every face
    plane; the old edge's midpoint (1/2, 0, 1/2) is 1/2 from both new triangles."""
    c = compare_complexes(OCTA, FACES, FLIPPED, 2, step=0.02)
    assert (c.recovered, c.extra, c.mesh_faces) == (6, 2, 8)
    assert c.recovered_share == pytest.approx(0.75)
    assert c.result_topology.closed_manifold and c.result_topology.betti == (1, 0, 1)  # a flip keeps S^2
    h = c.hausdorff
    assert h.error_bound < 0.012
    assert abs(h.b_to_a - 1 / math.sqrt(3)) <= h.error_bound
    assert abs(h.a_to_b - 0.5) <= h.error_bound
    assert h.distance == max(h.a_to_b, h.b_to_a)


def test_octahedron_with_a_face_missing():
    """The hole's farthest point is its centre, an inradius 1/sqrt(6) from its edges."""
    c = compare_complexes(OCTA, FACES, FACES[1:], 2, step=0.02)
    assert (c.recovered, c.extra) == (7, 0)
    assert not c.result_topology.closed_manifold and c.result_topology.betti == (1, 0, 0)
    assert c.genus(c.result_topology) is None
    assert abs(c.hausdorff.a_to_b - 1 / math.sqrt(6)) <= c.hausdorff.error_bound
    assert c.hausdorff.b_to_a == 0.0  # the disc lies on the octahedron


def test_empty_result_is_infinitely_far():
    c = compare_complexes(OCTA, FACES, np.empty((0, 3), int), 2)
    assert c.recovered == 0 and c.hausdorff.distance == math.inf
    assert json.dumps(c.as_dict(), allow_nan=True)


def test_dense_samples_cover_within_their_bound():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(4, 5))  # a tetrahedron in R^5 and its faces
    for simp in (np.array([[0, 1]]), np.array([[0, 1, 2]]), np.array([[0, 1, 2, 3]])):
        samples, delta = dense_samples(pts, simp, 0.3)
        w = rng.dirichlet(np.ones(simp.shape[1]), size=3000)
        probe = w @ pts[simp[0]]
        nearest = np.min(np.linalg.norm(probe[:, None] - samples[None], axis=2), axis=1)
        assert nearest.max() <= delta and delta <= 0.3


def test_hausdorff_of_two_parallel_segments():
    pts = np.array([[0, 0], [1, 0], [0, 0.25], [1, 0.25]], dtype=float)
    h = hausdorff(pts, np.array([[0, 1]]), np.array([[2, 3]]))
    assert h.a_to_b == pytest.approx(0.25) and h.b_to_a == pytest.approx(0.25)


def test_compare_to_mesh_maps_duplicate_rows_to_samples():
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    ring = np.c_[np.cos(t), np.sin(t)]
    pts = np.vstack([ring, ring[:5]])  # rows 40..44 repeat rows 0..4
    rec = reconstruct(pts, 1)
    assert rec.n == 40
    nxt = (np.arange(40) + 1) % 40
    faces = np.c_[np.arange(40), nxt]
    faces[:4] = np.c_[np.arange(40, 44), np.arange(41, 45)]  # the same edges through the copies
    c = compare_to_mesh(rec, np.vstack([faces, [[0, 40]]]))  # (0, 40) collapses onto one sample
    assert c.collapsed_faces == 1 and c.mesh_faces == 40
    assert c.recovered == 40 and c.extra == 0 and c.hausdorff.distance == 0.0


@pytest.mark.parametrize(
    "faces, match",
    [
        (np.array([[0, 1, 2]]), "shape"),
        (np.array([[0, 99]]), "refer to vertex 99"),
        (np.array([[0.0, 1.0]]), "integer"),
    ],
)
def test_compare_to_mesh_rejects_bad_faces(faces, match):
    t = np.linspace(0, 2 * np.pi, 30, endpoint=False)
    rec = reconstruct(np.c_[np.cos(t), np.sin(t)], 1)
    with pytest.raises(InputError, match=match):
        compare_to_mesh(rec, faces)


def test_a_real_mesh_bumpy():
    """bumpy.off: 1250 vertices, 2496 triangles, a closed genus-0 surface (its README)."""
    from crustview.io import read_mesh

    mesh = read_mesh(RESOURCES / "bumpy.off")
    faces = mesh.simplices(2)
    rec = reconstruct(mesh.points, 2)
    c = compare_to_mesh(rec, faces)
    assert c.mesh_faces == 2496 and c.collapsed_faces == 0
    assert c.mesh_topology.closed_manifold and c.genus(c.mesh_topology) == 0
    assert c.result_faces == rec.topology.n_simplices == c.recovered + c.extra
    assert 0 < c.recovered < c.mesh_faces  # some of the scan's diagonals differ
    assert c.result_topology.closed_manifold and c.genus(c.result_topology) == 0  # the same sphere
    # every recovered face lies on the mesh; the distance is a fraction of the sample spacing
    assert 0 < c.hausdorff.distance < 2 * rec.spacing


def test_a_real_mesh_of_genus_three_against_itself():
    from crustview.io import read_mesh

    mesh = read_mesh(RESOURCES / "3holes.off")
    faces = mesh.simplices(2)
    c = compare_complexes(mesh.points, faces, faces, 2)
    assert c.mesh_faces == 7200 and c.mesh_topology.betti == (1, 6, 1) and c.genus(c.mesh_topology) == 3
    assert c.hausdorff.distance == 0.0


def test_a_hausdorff_estimate_coarser_than_its_value_is_said_as_an_upper_bound():
    """A new user read "0.01175 ± 0.042" as a misprint: where the grids' covering radius exceeds the sampled
    value, only the upper bound is said."""
    from crustview.core.analysis.compare import HausdorffEstimate

    assert HausdorffEstimate(0.01175, 0.01, 0.01175, 0.042, 0.01, (9, 9)).words() == "at most 0.0538"
    assert HausdorffEstimate(1.5, 1.5, 1.0, 0.25, 0.1, (9, 9)).words() == "1.5 ± 0.25"
    # a bound of half the value or more says little beside it: the bound alone
    assert HausdorffEstimate(0.09458, 0.09458, 0.05, 0.093, 0.01, (9, 9)).words() == "at most 0.188"
    assert HausdorffEstimate(0.2, 0.2, 0.1, 0.099, 0.01, (9, 9)).words() == "0.2 ± 0.099"
    assert HausdorffEstimate(float("inf"), float("inf"), 0.0, 0.0, 0.0, (0, 0)).words() == "none"
    # a sampled 0 is no proof of the same complex (a small fold hides between grid points): the bound, rounded up
    assert HausdorffEstimate(0.0, 0.0, 0.0, 0.01, 0.01, (9, 9)).words() == "at most 0.01"
    assert HausdorffEstimate(0.01174, 0.01174, 0.01, 0.042, 0.01, (9, 9)).words() == "at most 0.0538"
