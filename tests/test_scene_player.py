"""StepPlayer and the scene model against a real reconstruction."""

import numpy as np

from crustview.core.steps import RULES
from crustview.scene import SceneModel, StepPlayer


def test_player_moves_and_clamps(torus_run):
    rec, _ = torus_run
    ext = rec.extraction
    assert ext.n_steps > 5
    p = StepPlayer(ext)
    seen = []
    p.step_changed.connect(seen.append)
    p.next()
    p.next()
    p.prev()
    assert p.position == 1 and seen == [1, 2, 1]
    assert p.current_step is ext.steps[0]
    p.last()
    assert p.position == ext.n_steps
    p.next()
    assert p.position == ext.n_steps
    p.first()
    p.prev()
    assert p.position == 0 and p.current_step is None


def test_next_of_rule_finds_the_next_step_of_that_rule(torus_run):
    rec, _ = torus_run
    ext = rec.extraction
    p = StepPlayer(ext)
    for rule in RULES:
        p.first()
        j = p.next_of_rule(rule)
        want = next((s.index + 1 for s in ext.steps if s.rule == rule), None)
        assert j == want
        if j is not None:
            assert p.run_to_rule(rule) and ext.steps[p.position - 1].rule == rule
    p.last()
    assert p.next_of_rule(RULES[0]) is None


def test_play_ticks_and_stops_at_the_end(torus_run):
    rec, _ = torus_run
    p = StepPlayer(rec.extraction)
    p.tick()
    assert p.position == 0  # not playing
    p.play()
    states = []
    p.playing_changed.connect(states.append)
    while p.playing:
        p.tick(7)
    assert p.position == rec.extraction.n_steps and states == [False]


def test_model_open_faces_match_a_direct_count(torus_run):
    rec, sample = torus_run
    m = SceneModel()
    m.set_reconstruction(rec, truth=sample, source="torus")
    for i in (0, rec.extraction.n_steps // 2, rec.extraction.n_steps):
        faces, counts = m.open_faces(i)
        simp = rec.extraction.complex_at(i)
        # brute force: count each (d-1)-face
        from collections import Counter

        c = Counter()
        for s in simp:
            s = sorted(s)
            for a in range(len(s)):
                c[tuple(s[:a] + s[a + 1 :])] += 1
        want = {f: n for f, n in c.items() if n == 1 or n > 2}
        got = {tuple(int(v) for v in f): int(n) for f, n in zip(faces, counts)}
        assert got == want
    if rec.topology.closed_manifold:
        assert len(m.open_faces(rec.extraction.n_steps)[0]) == 0


def test_model_quantities(torus_run):
    rec, sample = torus_run
    m = SceneModel()
    m.set_reconstruction(rec, truth=sample, source="torus")
    err, label = m.point_values("normal error")
    assert err.shape == (rec.n,) and "deg" in label
    assert np.median(err) < 10  # Algorithm 1 is accurate on a dense torus
    dist, _ = m.point_values("pole distance")
    hull = rec.pole_index[:, 0] >= len(rec.delaunay_simplices)
    assert hull.any() and not hull.all()
    assert np.all(dist[~hull] > 0)
    assert np.all(np.isnan(dist[hull]))  # the first pole of a hull sample is at infinity
    assert m.point_values("none") is None
    # candidate rows and extraction ids are inverse maps
    for e in (0, 5, len(rec.extraction.simplices) - 1):
        row = m.candidate_row(e)
        assert row >= 0 and m.extraction_id(row) == e


def test_model_without_truth_has_no_normal_error(torus_run):
    rec, _ = torus_run
    m = SceneModel()
    m.set_reconstruction(rec, truth=None, source="file")
    assert m.point_values("normal error") is None


def test_a_reextraction_keeps_the_step_or_the_end_never_a_clamped_last_step(torus_run):
    from crustview.core import reextract

    rec, sample = torus_run
    other = reextract(rec, "cocone", rec.theta, mode="paper", prune_boundary=False)
    n, n_other = rec.extraction.n_steps, other.extraction.n_steps
    assert n_other < n - 2
    m = SceneModel()
    m.set_reconstruction(rec, truth=sample)
    m.player.set_step(n - 1)  # beyond the other run's steps
    m.set_reconstruction(other, truth=sample, keep_view=True)
    assert m.player.position == 0
    m.set_reconstruction(rec, truth=sample, keep_view=True)
    m.player.set_step(3)
    m.set_reconstruction(other, truth=sample, keep_view=True)
    assert m.player.position == 3
    m.set_reconstruction(rec, truth=sample, keep_view=True)
    m.player.last()
    m.set_reconstruction(other, truth=sample, keep_view=True)
    assert m.player.position == n_other


def test_a_switch_between_the_papers_steps_and_the_extensions_lands_on_the_result():
    """From the middle of a paper-mode replay to the robust extension (another sequence of steps): its
    end, the final M_S, not its step 0 (an empty M_S under a green verdict, a new user saw)."""
    from pathlib import Path

    from crustview.core import reconstruct, reextract
    from crustview.io import read_points

    pts = read_points(Path(__file__).parents[1] / "resources" / "horse-quads.obj")
    paper = reconstruct(pts, 2, mode="paper")
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    assert robust.extraction.steps[0].rule == "label-cells"  # the extension's own steps
    m = SceneModel()
    m.set_reconstruction(paper)
    m.player.set_step(paper.extraction.n_steps // 2)
    m.set_reconstruction(robust, keep_view=True)
    assert m.player.position == robust.extraction.n_steps
    m.player.set_step(0)
    m.set_reconstruction(paper, keep_view=True)  # and back: the paper's run from its end too
    assert m.player.position == paper.extraction.n_steps
