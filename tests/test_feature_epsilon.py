"""The estimated epsilon where each listed feature is (issue 18: "and the estimated eps there")."""

from __future__ import annotations

import json
import math

import numpy as np

from crustview.core import reconstruct
from crustview.core.analysis.quality import feature_epsilon, sampling_quality
from crustview.report import report_dict


def _circle(n: int) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.c_[np.cos(t), np.sin(t)]


def test_a_contact_below_the_spacing_says_its_epsilon_is_beyond_what_reconstruction_needs():
    """Two unit circles of 60 samples 0.02 apart (a fifth of a spacing): the sample does not resolve the gap,
    and the feature at it says so twice: a gap under GAP_MIN spacings, and an estimated epsilon beyond 1/2
    (the medial axis between the circles is 0.01 from the contact samples, their cells' spacing 0.05).  The
    rest of the sample is the regular 60-gon's, eps = tan(pi / 60) (the Voronoi cell's half-width over the
    distance to its pole at the centre)."""
    c = _circle(60)
    rec = reconstruct(np.vstack([c, c + [2.02, 0]]), 1)
    rep = report_dict(rec)
    json.dumps(rep)
    listed = rep["uncertain_features"]
    assert listed and all(f["kind"] == "component" for f in listed)
    regular = math.tan(math.pi / 60)
    assert math.isclose(rep["sampling_quality"]["epsilon_median"], regular, rel_tol=0.01)
    for f in listed:
        assert f["size_spacings"] < 2 and f["epsilon"] > 0.5 and f["epsilon"] > 10 * regular
        assert f["epsilon_max"] >= f["epsilon"]
    # the same numbers as the sampling quality over the feature's own samples
    q = sampling_quality(rec)
    got = feature_epsilon(q.epsilon, rec.uncertain_features[0].vertices)
    assert (listed[0]["epsilon"], listed[0]["epsilon_max"]) == (got["epsilon"], got["epsilon_max"])


def test_apart_nothing_is_listed_and_a_feature_without_a_finite_estimate_says_none():
    c = _circle(60)
    rep = report_dict(reconstruct(np.vstack([c, c + [5.0, 0]]), 1))
    assert rep["uncertain_features"] == [] and rep["removed_features"] == []
    assert feature_epsilon(np.array([np.nan, np.nan]), np.array([0, 1])) == {"epsilon": None, "epsilon_max": None}
    assert feature_epsilon(np.array([0.3]), np.array([], dtype=int)) == {"epsilon": None, "epsilon_max": None}


def test_a_loop_that_ends_where_it_began_counts_that_sample_once():
    """cut-handle keeps loops as the search found them, closed walks [a, b, c, a]: the median is over three
    samples (0.2), not four (0.15)."""
    eps = np.array([0.1, 0.2, 0.9])
    assert feature_epsilon(eps, np.array([0, 1, 2, 0])) == {"epsilon": 0.2, "epsilon_max": 0.9}


def test_a_surface_in_a_flat_of_r4_has_the_epsilon_it_has_in_r3():
    """The same torus sample in R^3 and in the 3-flat x4 = 0.7 of R^4: Algorithm 1 runs in the flat either
    way, and the estimated epsilon takes the medial axis on both sides there too (a review found the flat's
    3.5 times smaller: the other side's pole was left out in codimension 2)."""
    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold("torus")
    pts = m.sample(m.default_n, seed=0).points
    flat = reconstruct(np.c_[pts, np.full(len(pts), 0.7)], 2)
    space = reconstruct(pts, 2)
    assert flat.subspace_dim == 3 and flat.k == 4
    qa, qb = sampling_quality(space), sampling_quality(flat)
    oa, ob = np.argsort(space.point_input), np.argsort(flat.point_input)  # the same input rows
    # the height (distance to the nearest pole, either side) is the same to rounding; the cell's radius is
    # sampled along 16 tangent directions of each sample's own basis, which the flat turns (within 6 % here)
    assert np.allclose(qa.height[oa], qb.height[ob], rtol=1e-5)
    assert math.isclose(np.nanmedian(qa.epsilon), np.nanmedian(qb.epsilon), rel_tol=0.01)
