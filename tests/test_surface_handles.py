"""surface_handles: the handles features() gives, as found and tightened, from one basis search."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from crustview.core import reconstruct
from crustview.core.analysis.features import features, surface_handles
from crustview.core.samples.manifolds import get_manifold
from crustview.io import read_points


def _same(a, b) -> bool:
    return len(a) == len(b) and all(
        x.kind == y.kind
        and x.size_spacings == y.size_spacings
        and x.uncertain == y.uncertain
        and np.array_equal(x.vertices, y.vertices)
        and np.array_equal(x.location, y.location)
        and x.reason == y.reason
        for x, y in zip(a, b, strict=True)
    )


@pytest.mark.parametrize("source", ["torus", "fertility.off", "3holes.off"])
def test_both_measures_from_one_search_are_features_own(source):
    """The built-in torus and two scans of genus 4 and 3: the handles either way are the same objects in the
    same order as two calls of features() give."""
    if source == "torus":
        m = get_manifold("torus")
        rec = reconstruct(m.sample(m.default_n, seed=0).points, 2)
    else:
        rec = reconstruct(read_points(Path(__file__).parent.parent / "resources" / source), 2)
    pts = rec.points / rec.spacing
    measure = surface_handles(pts, rec.manifold)
    found, tight = measure(False), measure(True)
    assert found and tight  # each has handles: b1 > 0
    assert _same(found, features(pts, rec.manifold, 2, tighten_loops=False, handles_only=True))
    assert _same(tight, features(pts, rec.manifold, 2, tighten_loops=True, handles_only=True))
    assert _same(measure(False), found)  # measuring tightened first changed nothing the search holds


def test_a_sphere_and_nothing_have_no_handles():
    m = get_manifold("sphere")
    rec = reconstruct(m.sample(m.default_n, seed=0).points, 2)
    assert surface_handles(rec.points, rec.manifold)(True) == []
    assert surface_handles(rec.points, np.zeros((0, 3), np.int64))(False) == []


def test_an_open_surface_is_capped_the_same_way_both_times():
    """The torus with the stars of two far samples taken out: two holes, capped before the search
    (features._handles), and the same handles either way as features() gives."""
    m = get_manifold("torus")
    rec = reconstruct(m.sample(m.default_n, seed=0).points, 2)
    far = int(np.argmax(np.linalg.norm(rec.points - rec.points[0], axis=1)))
    open_torus = rec.manifold[~np.isin(rec.manifold, [0, far]).any(axis=1)]
    measure = surface_handles(rec.points, open_torus)
    found, tight = measure(False), measure(True)
    assert len(found) == len(tight) == 2  # the torus's two loops; a loop around a hole bounds its cap
    assert _same(found, features(rec.points, open_torus, 2, tighten_loops=False, handles_only=True))
    assert _same(tight, features(rec.points, open_torus, 2, tighten_loops=True, handles_only=True))
