"""Samples M_S does not reach, as uncertain features (crustview.core.analysis.missing)."""

import numpy as np

from crustview.core.analysis.features import features
from crustview.core.analysis.missing import left_out

OCTA = np.array([[0, 2, 4], [0, 2, 5], [0, 3, 4], [0, 3, 5], [1, 2, 4], [1, 2, 5], [1, 3, 4], [1, 3, 5]])
OCTA_PTS = np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, -1.0, 0], [0, 0, 1.0], [0, 0, -1.0]])


def test_a_cluster_of_left_out_samples_is_an_uncertain_part_and_strays_are_not():
    """Four samples in no triangle, 0.3 apart (a piece M_S lacks), and two lone ones far from
    everything: one uncertain component at the four's centroid; the two are outliers, not a part."""
    cluster = np.array([[5.0, 0, 0], [5.3, 0, 0], [5.0, 0.3, 0], [5.3, 0.3, 0]])
    lone = np.array([[-9.0, 0, 0], [0, 9.0, 9.0]])
    pts = np.vstack([OCTA_PTS, cluster, lone])
    found = left_out(pts, OCTA, 2)
    assert len(found) == 1
    (f,) = found
    assert f.kind == "component" and f.uncertain
    assert sorted(f.vertices.tolist()) == [6, 7, 8, 9]
    assert np.allclose(f.location, cluster.mean(axis=0))
    assert "does not reach" in f.reason
    # features() lists it with the components
    assert any(g.kind == "component" and g.uncertain for g in features(pts, OCTA, 2))


def test_nothing_left_out_and_two_samples_are_no_part():
    assert left_out(OCTA_PTS, OCTA, 2) == []
    pts = np.vstack([OCTA_PTS, [[5.0, 0, 0], [5.2, 0, 0]]])  # two near samples: fewer than d + 1
    assert left_out(pts, OCTA, 2) == []
    assert len(left_out(pts, OCTA, 1)) == 1  # for a curve two samples are an edge's worth


def test_an_empty_result_reaches_no_sample():
    """M_S empty (the paper's loop pruned everything): the samples it does not reach are one part."""
    (f,) = features(OCTA_PTS, np.zeros((0, 3), np.int64), 2)
    assert f.kind == "component" and f.uncertain and sorted(f.vertices.tolist()) == list(range(6))
