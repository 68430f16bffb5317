"""The shape's name from its topology, against the built-ins' truth."""

import pytest

from crustview.core import reconstruct
from crustview.core.samples.manifolds import MANIFOLDS, projective_plane_points
from crustview.scene.shapes import name_of, shape_name

TRUE_NAMES = {
    "circle": "circle",
    "ellipse": "circle",
    "trefoil": "circle",
    "hopf-link": "2 circles",
    "circle-r4": "circle",
    "sphere": "sphere",
    "ellipsoid": "sphere",
    "sphere-r4": "sphere",
    "torus": "torus",
    "clifford-torus": "torus",
    "torus-r5": "torus",
    "flat-klein": "Klein bottle",
    "s3": "S³ (a Z/2-homology 3-sphere)",
}


def test_every_builtin_truth_has_its_name():
    assert set(TRUE_NAMES) == set(MANIFOLDS)
    for name, m in MANIFOLDS.items():
        assert shape_name(m.d, m.betti, m.orientable) == TRUE_NAMES[name], name


def test_surface_classification_names():
    assert shape_name(2, (1, 1, 1), False) == "projective plane"
    assert shape_name(2, (1, 4, 1), True) == "genus-2 surface"
    assert shape_name(2, (1, 3, 1), False).startswith("non-orientable surface of genus 3")
    assert shape_name(1, (3, 3), True) == "3 circles"
    assert shape_name(2, (1, 2, 1), True, closed=False) == "not a closed manifold"


@pytest.mark.parametrize("name", ["hopf-link", "flat-klein", "clifford-torus", "sphere"])
def test_reconstructed_builtins_get_their_true_name(name, default_run):
    rec, _ = default_run(name)  # reconstruct(m.sample(m.default_n, seed=0).points, m.d), shared per process
    assert name_of(rec.topology, rec.d) == TRUE_NAMES[name]


def test_s3_and_the_torus_fixtures(s3_run, torus_run):
    for rec, sample in (s3_run, torus_run):
        t = sample.manifold
        assert name_of(rec.topology, rec.d) == shape_name(t.d, t.betti, t.orientable)


@pytest.mark.slow
def test_projective_plane_in_r4_is_named():
    rec = reconstruct(projective_plane_points(1000), 2)
    assert name_of(rec.topology, rec.d) == "projective plane", rec.topology
