"""The compiled circumcentres (_centres.cpp) give the numpy code's values, bit for bit."""

import numpy as np
import pytest

from crustview.core.delaunay import triangulation as tri
from crustview.core.delaunay.triangulation import bounding_points, circumcenters_numpy, delaunay
from crustview.core.prepare import prepare_points
from crustview.core.samples.manifolds import get_manifold


def test_the_extension_is_built_and_agrees_with_numpy_here():
    # scripts/install.sh builds it; without it (or on a numpy that sums einsum otherwise) numpy runs
    assert tri._native_centres is not None
    assert tri.native_centres_ok()


@pytest.mark.parametrize("name,n", [("circle", 300), ("torus", 4000), ("flat-klein", 600), ("s3", 400)])
def test_native_centres_are_numpys_bit_for_bit(name, n):
    m = get_manifold(name)
    prep = prepare_points(m.sample(n, seed=0).points, m.d)
    b = bounding_points(prep.r)
    simp = delaunay(prep.work, b)
    pts = np.vstack([prep.work, b])
    ref = circumcenters_numpy(pts, simp)
    assert np.array_equal(tri.circumcenters(pts, simp), ref)
    assert np.array_equal(tri.circumcenters(pts, simp.astype(np.int64)), ref)


def test_degenerate_simplices_take_numpys_least_squares():
    rng = np.random.default_rng(1)
    pts = rng.normal(size=(40, 3))
    pts[5] = pts[1] + 0.5 * (pts[2] - pts[1])  # on the segment 1-2: simplex (0, 1, 2, 5) is flat
    pts[6] = pts[0] + pts[1] - pts[2]  # coplanar with 0, 1, 2
    simp = np.array([[0, 1, 2, 5], [0, 1, 2, 6], [3, 4, 7, 8], [0, 1, 2, 3]], dtype=np.int32)
    got = tri._circumcenters_native(pts, simp)
    assert np.array_equal(got, circumcenters_numpy(pts, simp))


def test_the_self_check_falls_back_to_numpy(monkeypatch):
    monkeypatch.setattr(tri, "_NATIVE_OK", [False])
    called = []
    monkeypatch.setattr(tri, "_circumcenters_native", lambda *a: called.append(a))
    pts = np.random.default_rng(2).normal(size=(30, 3))
    simp = delaunay(pts, np.empty((0, 3)))
    assert np.array_equal(tri.circumcenters(pts, simp), circumcenters_numpy(pts, simp)) and not called
