"""A hole fill-hole's own bounds call a gap, left open, is uncertain (robust/unclosed.py), on a grid by hand."""

from __future__ import annotations

import numpy as np

from crustview.core.analysis.features import features
from crustview.core.robust.fill_hole import FILL_MAX_FACES
from crustview.core.robust.unclosed import unclosed_gaps


def _sheet_with_hole(size: int = 30, radius: float = 2.5) -> tuple[np.ndarray, np.ndarray]:
    """A unit grid of size x size squares, two triangles each, less those within ``radius`` of its middle."""
    ij = np.array([(i, j) for j in range(size + 1) for i in range(size + 1)], dtype=float)
    pts = np.c_[ij, np.zeros(len(ij))]
    v = lambda i, j: j * (size + 1) + i  # noqa: E731
    tris = []
    for j in range(size):
        for i in range(size):
            tris += [(v(i, j), v(i + 1, j), v(i + 1, j + 1)), (v(i, j), v(i + 1, j + 1), v(i, j + 1))]
    tris = np.array(tris)
    middle = np.linalg.norm(pts[tris].mean(axis=1)[:, :2] - size / 2, axis=1)
    return pts, tris[middle > radius]


def test_a_sure_hole_within_fill_holes_bounds_is_uncertain_and_the_outer_rim_is_not() -> None:
    pts, tris = _sheet_with_hole()
    holes = [f for f in features(pts, tris, 2) if f.kind == "hole"]
    assert len(holes) == 2 and not any(f.uncertain for f in holes)  # both sure by their size
    inner = min(holes, key=lambda f: f.size_spacings)
    assert inner.size_spacings > 4 and len(inner.vertices) <= FILL_MAX_FACES  # a rim loop: as many edges
    out = unclosed_gaps(pts, tris, holes, [], 1.0)
    flagged = [f for f in out if f.uncertain]
    assert len(flagged) == 1 and np.allclose(flagged[0].location, inner.location)
    assert "could not close it" in flagged[0].reason and "within its bounds" in flagged[0].reason
    # the outer rim (120 edges, 30 spacings across) is beyond fill-hole's bounds: a real boundary, still sure
    assert not next(f for f in out if f is not flagged[0]).uncertain


def test_an_opening_open_cap_kept_open_stays_sure() -> None:
    pts, tris = _sheet_with_hole()
    holes = [f for f in features(pts, tris, 2) if f.kind == "hole"]
    inner = min(holes, key=lambda f: f.size_spacings)
    out = unclosed_gaps(pts, tris, holes, [(inner.vertices[:3], 10.0)], 1.0)
    assert len(out) == len(holes) == 2
    kept = next(f for f in out if f.size_spacings == inner.size_spacings)  # the two rims share a centre
    assert not kept.uncertain and kept.reason == inner.reason  # untouched, not just unflagged
    assert not any(f.uncertain for f in out)


def test_a_3_manifolds_hole_is_judged_by_its_span_not_a_surfaces_face_count() -> None:
    """S^3 at 3 % of its reach, 1,200 samples (seed 6): a hole of 100-156 faces, 6.5 spacings across, was sure.

    The face bound (50) is a surface's rim loop's; a 3-manifold's rim is a sphere, whose face count grows with
    the square of its span: the span bound (18 spacings) decides, and the hole is uncertain.  Grown in a
    hyperplane of R^5 (``labelling=False``; codimension 2 for the growing path, as before session 37), which
    left the hole; the default labelling path closes it (test_core_labelled_hyper.py).
    """
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    s = get_manifold("s3").sample(1200, seed=6).points
    s = s + np.random.default_rng(306).normal(scale=0.03, size=s.shape)
    rec = reconstruct(np.c_[s, np.zeros(len(s))], 3, labelling=False)
    holes = [f for f in rec.features if f.kind == "hole"]
    assert not rec.topology.closed_manifold and holes
    big = max(holes, key=lambda f: f.size_spacings)
    assert big.size_spacings > 4 and big.uncertain and "more faces than it closes" in big.reason
