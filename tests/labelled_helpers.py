"""Shared by the labelling tests: the Delaunay cells of a run, and a labelled noisy torus."""

from __future__ import annotations

import numpy as np

from crustview.core import reconstruct
from crustview.core.robust.label_repair import LabelEditor
from crustview.core.robust.labelling import Labelling
from crustview.core.samples.manifolds import get_manifold


def cells_of(rec):
    """(Delaunay points, cells, their circumcentres) of a run, as the labelling takes them."""
    m = len(rec.delaunay_simplices)
    return rec.delaunay_points, rec.delaunay_simplices, rec.voronoi_vertices[:m]


def noisy_torus_editor():
    """A torus of 1,500 samples with noise of about half the spacing (its raw cut pinches at 10 samples),
    its cells labelled: (run, labelling, editor, the noise's generator for further draws)."""
    m = get_manifold("torus")
    s = m.sample(1500, seed=2)
    rng = np.random.default_rng(1)
    rec = reconstruct(s.points + rng.normal(scale=0.06, size=s.points.shape), 2, mode="paper")
    lab = Labelling(rec.points, *cells_of(rec))
    return rec, lab, LabelEditor(lab), rng
