"""What the uncertain-features layer draws, on an octahedron checkable by hand."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from crustview.core.analysis.features import Feature
from crustview.scene.features import feature_lines

OCTA = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
POINTS = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)


def _rec():
    # the three arrays feature_lines reads, of a closed octahedron (no boundary edges)
    return SimpleNamespace(points=POINTS, manifold=OCTA, d=2)


def _edges(pts, lines):
    return {tuple(sorted(map(tuple, pts[e].round(6).tolist()))) for e in lines}


def test_a_kept_cap_is_drawn_as_the_outline_of_its_faces():
    # a cap kept closed on samples 0, 1, 2, 4: its faces (0 2 4) and (2 1 4) share edge 2-4
    cap = Feature("hole", POINTS[[0, 1, 2, 4]].mean(axis=0), 3.0, True, np.array([0, 1, 2, 4]), "kept", removed=True)
    pts, lines, markers = feature_lines(_rec(), [cap])
    want = {tuple(sorted(map(tuple, POINTS[[a, b]].tolist()))) for a, b in [(0, 2), (0, 4), (1, 2), (1, 4)]}
    assert _edges(pts, lines) == want and len(markers) == 0


def test_a_hole_with_no_rim_and_not_kept_is_a_marker_at_its_location():
    hole = Feature("hole", np.array([0.5, 0.5, 0.5]), 3.0, True, np.array([0, 2, 4]), "no rim")
    pts, lines, markers = feature_lines(_rec(), [hole])
    assert len(lines) == 0 and len(markers) == 1
    np.testing.assert_allclose(pts[markers[0]], [0.5, 0.5, 0.5])


def test_a_curves_gap_is_drawn_between_its_two_ends_not_at_its_midpoint():
    # a half circle's gap: its ends (1, 0) and (-1, 0); a marker at the midpoint would sit at the centre
    t = np.linspace(0, np.pi, 5)
    pts2 = np.c_[np.cos(t), np.sin(t)]
    rec = SimpleNamespace(points=pts2, manifold=np.c_[np.arange(4), np.arange(1, 5)], d=1)
    gap = Feature("hole", np.zeros(2), 4.0, True, np.array([0, 4]), "gap of an open curve")
    pts, lines, markers = feature_lines(rec, [gap])
    assert len(markers) == 0 and _edges(pts, lines) == {((-1.0, 0.0), (1.0, 0.0))}


def test_a_disputed_handle_is_a_marker_not_a_loop_through_its_region():
    """A disputed handle's vertices are where two results differ (foot bones: hundreds of samples in no
    order): drawn as a loop they criss-crossed the model; it is its location, as a marker.  A handle that is
    not disputed is still its loop."""
    region = np.array([0, 4, 1, 5, 2, 3])
    disputed = Feature("handle", np.array([0.1, 0.2, 0.3]), 9.0, True, region, "differ here", disputed=True)
    pts, lines, markers = feature_lines(_rec(), [disputed])
    assert len(lines) == 0 and len(markers) == 1
    np.testing.assert_allclose(pts[markers[0]], [0.1, 0.2, 0.3])
    loop = Feature("handle", np.zeros(3), 9.0, True, np.array([0, 2, 1, 3]), "a loop")
    pts, lines, markers = feature_lines(_rec(), [loop])
    assert len(lines) == 4 and len(markers) == 0


def test_a_hole_of_a_3_manifold_is_drawn_as_the_edges_of_its_boundary_faces():
    """The 3-sphere of a 4-simplex's boundary less the tetrahedron (1 2 3 4): its hole's four faces, six edges."""
    pts4 = np.vstack([np.eye(4), np.full((1, 4), -0.3)])
    tets = np.array([[j for j in range(5) if j != i] for i in range(1, 5)])  # every tetrahedron but (1, 2, 3, 4)
    rec = SimpleNamespace(points=pts4, manifold=tets, d=3)
    hole = Feature("hole", pts4[1:].mean(axis=0), 2.0, True, np.array([1, 2, 3, 4]), "one missing tetrahedron")
    pts, lines, markers = feature_lines(rec, [hole])
    want = {tuple(sorted(map(tuple, pts4[[a, b]].round(6).tolist()))) for a in range(1, 5) for b in range(a + 1, 5)}
    assert _edges(pts, lines) == want and len(markers) == 0
