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


def test_an_empty_result_names_no_feature():
    """M_S empty (the paper's loop pruned everything): it lacks the whole object, which no feature is (its
    verdict, FAILED, says so); a new user read the cow head's 42 "uncertain components" as a count of parts."""
    assert features(OCTA_PTS, np.zeros((0, 3), np.int64), 2) == []
    # one simplex is enough for the samples it does not reach to be a part it may lack
    (f,) = [g for g in features(OCTA_PTS, np.array([[0, 1, 2]]), 2) if g.kind == "component"]
    assert f.uncertain and sorted(f.vertices.tolist()) == [3, 4, 5]


def _grid(nx: int, step: float, x0: float, start: int) -> tuple[np.ndarray, np.ndarray]:
    """An nx by nx grid of the plane z = 0 with corner (x0, 0), step ``step``, in triangles numbered from ``start``."""
    ii, jj = np.meshgrid(np.arange(nx), np.arange(nx), indexing="ij")
    pts = np.c_[x0 + step * ii.ravel(), step * jj.ravel(), np.zeros(nx * nx)]
    v = np.arange(nx * nx).reshape(nx, nx) + start
    a, b, c, d = v[:-1, :-1].ravel(), v[1:, :-1].ravel(), v[:-1, 1:].ravel(), v[1:, 1:].ravel()
    return pts, np.r_[np.c_[a, b, d], np.c_[a, d, c]]


def test_left_out_samples_are_clustered_in_the_surfaces_own_spacing_where_the_density_varies():
    """A dense patch (step 0.1, 900 samples: the median spacing) beside a sparse one (step 2.5).  Three
    left-out samples 3 apart above the sparse patch are one part (3 < 2 x 2.5, the spacing of the surface
    there), though 30 median spacings apart; the same three above the dense patch are three lone samples."""
    dense, t1 = _grid(30, 0.1, 0.0, 0)
    sparse, t2 = _grid(5, 2.5, 10.0, len(dense))
    line = np.array([[0.0, 0, 3.0], [3.0, 0, 3.0], [6.0, 0, 3.0]])
    surface = np.vstack([dense, sparse])
    tris = np.vstack([t1, t2])
    above_sparse = np.vstack([surface, line + [12.0, 5.0, 0]])
    (f,) = left_out(above_sparse, tris, 2)
    assert sorted(f.vertices.tolist()) == [len(surface), len(surface) + 1, len(surface) + 2]
    above_dense = np.vstack([surface, line + [0.0, 1.5, 0]])
    assert left_out(above_dense, tris, 2) == []
