"""Colouring by position in R^k: a coordinate, or the depth the projection hides (Qt-free)."""

from __future__ import annotations

import numpy as np

from .projection import Projection

#: Colourings by position that the sample and simplex layers offer.
COORDINATE_COLORINGS = ("hidden depth", "x1", "x2", "x3", "x4", "x5")


def coordinate_values(points: np.ndarray, projection: Projection, how: str) -> tuple[np.ndarray, str] | None:
    """Value of each point for colouring ``how``, with a label; None when it does not apply.

    Parameters
    ----------
    points : ndarray of shape (n, k)
    projection : Projection
        Gives the hidden direction (the one the view drops, k >= 4) and the origin.
    how : str
        ``"hidden depth"``: signed distance along :attr:`Projection.hidden`
        from the origin; ``"x<i>"``: the i-th coordinate (1-based).
    """
    points = np.asarray(points, dtype=float)
    k = points.shape[1]
    if how == "hidden depth":
        if k < 4:
            return None
        u = projection.hidden
        terms = " + ".join(f"{c:.2f} x{i + 1}" for i, c in enumerate(u) if abs(c) > 0.005).replace("+ -", "- ")
        return (points - projection.origin) @ u, f"hidden depth ({terms})"
    if how.startswith("x") and how[1:].isdigit():
        i = int(how[1:]) - 1
        if 0 <= i < k:
            return points[:, i].copy(), f"coordinate {how}"
    return None


def default_coloring(k: int) -> str:
    """The simplices' colouring a new reconstruction starts with: the hidden depth in R^4 and up."""
    return "hidden depth" if k >= 4 else "none"
