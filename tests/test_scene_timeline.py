"""Per-step counts of a replay against the complex at each position."""

import numpy as np

from crustview.scene import SceneModel
from crustview.scene.timeline import rule_codes, timeline


def brute(model, i):
    faces, counts = model.open_faces(i)
    return int(model.rec.extraction.alive(i).sum()), int((counts == 1).sum()), int((counts > 2).sum())


def test_timeline_matches_the_complex_at_every_sampled_step(torus_run):
    rec, sample = torus_run
    m = SceneModel()
    m.set_reconstruction(rec, truth=sample)
    tl = m.timeline()
    n = rec.extraction.n_steps
    assert tl.n_steps == n
    for i in sorted({0, 1, 2, n // 3, n // 2, n - 1, n}):
        assert (tl.size[i], tl.boundary[i], tl.nonmanifold[i]) == brute(m, i), i
    assert tl.nonmanifold[0] > 0 and tl.nonmanifold[n] == 0 and tl.boundary[n] == 0


def test_timeline_of_a_robust_run_that_adds_simplices():
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.io import read_points

    # a real scan the paper's loop cannot close: the robust extension grows the surface
    pts = read_points(Path(__file__).parents[1] / "resources" / "horse-quads.obj")
    rec = reconstruct(pts, 2)
    ext = rec.extraction
    assert any(s.added for s in ext.steps)
    m = SceneModel()
    m.set_reconstruction(rec)
    tl = timeline(ext)
    for i in range(0, ext.n_steps + 1, max(1, ext.n_steps // 40)):
        assert (tl.size[i], tl.boundary[i], tl.nonmanifold[i]) == brute(m, i), i
    codes = rule_codes(ext)
    assert [codes.names[c] for c in codes.codes] == [s.rule for s in ext.steps]
    assert np.array_equal(tl.size, [ext.alive(i).sum() for i in range(ext.n_steps + 1)])
