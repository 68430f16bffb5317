"""Checks shared by the Delaunay backend tests."""

import numpy as np
import pytest

from crustview.core.delaunay.triangulation import circumcenters


def lattice(side: int, dim: int) -> np.ndarray:
    """The integer grid {0, ..., side - 1}^dim, one point per row: exactly degenerate input."""
    g = np.arange(float(side))
    return np.stack(np.meshgrid(*([g] * dim), indexing="ij"), axis=-1).reshape(-1, dim)


def assert_delaunay_of_a_box(pts: np.ndarray, simp: np.ndarray, volume: float) -> None:
    """The simplices fill a box of ``volume`` (no overlaps, no gaps) and every circumsphere is empty."""
    p = pts[simp]
    r = pts.shape[1]
    vol = np.abs(np.linalg.det(p[:, 1:] - p[:, :1])).sum() / float(np.prod(np.arange(1, r + 1)))
    assert vol == pytest.approx(volume)
    c = circumcenters(pts, simp)
    rad2 = ((p[:, 0] - c) ** 2).sum(axis=1)
    d2 = ((pts[None, :, :] - c[:, None, :]) ** 2).sum(axis=2)
    assert (d2 >= rad2[:, None] - 1e-9).all()
