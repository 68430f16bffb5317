"""When a file's mesh can judge M_S: holes below the sample's resolution, and meshes that are no manifold."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.compare import compare_to_mesh
from crustview.io import read_mesh
from crustview.scene.describe import verdict

BUMPY = Path(__file__).parents[1] / "resources" / "bumpy.off"


@pytest.fixture(scope="module")
def bumpy():
    """The bumpy sphere's mesh (closed, genus 0) and the default reconstruction of its vertices."""
    mesh = read_mesh(BUMPY)
    tris = np.asarray(mesh.simplices(2), np.int64)
    rec = reconstruct(np.asarray(mesh.points, float), 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 0, 1)
    return tris, rec


def _judged(rec, faces):
    cmp = compare_to_mesh(rec, faces)
    return cmp, verdict(rec, SimpleNamespace(comparison=cmp, manifold=None))


def test_a_mesh_missing_one_triangle_does_not_make_a_closed_result_wrong(bumpy):
    tris, rec = bumpy
    cmp, (level, text) = _judged(rec, tris[1:])  # a pinhole: a rim of three edges
    assert cmp.mesh_topology.betti == (1, 0, 0) and not cmp.mesh_topology.closed_manifold
    u = cmp.unresolved
    assert u is not None and (u.count, u.edges, u.betti) == (1, 3, (1, 0, 1))
    assert u.longest < 2 * np.pi
    assert level == "ok", text
    assert "but for 1 hole the sample cannot show (a rim of 3 edges" in text
    assert cmp.as_dict()["mesh_holes_below_resolution"]["betti_closed"] == [1, 0, 1]


def test_a_real_opening_in_the_mesh_still_makes_a_closed_result_wrong(bumpy):
    tris, rec = bumpy
    pts = rec.input_points
    # every triangle with a corner in the top tenth of the sphere: a cap many spacings across
    top = pts[:, 2] > np.quantile(pts[:, 2], 0.9)
    open_mesh = tris[~top[tris].any(axis=1)]
    cmp, (level, text) = _judged(rec, open_mesh)
    assert cmp.mesh_topology.betti == (1, 0, 0) and cmp.unresolved is None
    assert level == "bad" and text.startswith("M_S is WRONG: Betti (1, 0, 1) ≠ mesh (1, 0, 0)"), text


def test_a_mesh_that_is_no_manifold_judges_nothing_and_says_so(bumpy):
    tris, rec = bumpy
    a, b = tris[0][:2]
    fin = np.array([[a, b, c] for c in np.setdiff1d(tris[5], [a, b])[:1]])  # a third triangle at one edge
    cmp, (level, text) = _judged(rec, np.vstack([tris, fin]))
    assert cmp.mesh_topology.nonmanifold_faces == 1
    assert level == "ok" and "the file's mesh is not a manifold (1 edge in three faces or more)" in text, text
