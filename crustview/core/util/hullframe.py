"""Coordinates in the affine hull of a sample that lies in a proper affine subspace of R^k.

A 3-manifold given in R^5 with a constant fifth coordinate is a hypersurface of its hull, a 4-flat: its
Delaunay cells are 4-simplices there (:mod:`crustview.core.prepare` triangulates in the hull's own
coordinates), and the robust extension labels them inside or outside as for any hypersurface
(:func:`crustview.core.reconstruct.reextract`).  The labelling works in the hull's coordinates; the
features it measures on the way are lifted back to R^k.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class HullFrame:
    """An orthonormal frame of an affine subspace: a point of it and a basis of its directions.

    Attributes
    ----------
    centre : ndarray of shape (k,)
    basis : ndarray of shape (k, r)
        Orthonormal columns.
    """

    centre: np.ndarray
    basis: np.ndarray

    def down(self, x: np.ndarray) -> np.ndarray:
        """Coordinates in the frame of points of R^k (their orthogonal projection onto the subspace)."""
        return (np.asarray(x, dtype=float) - self.centre) @ self.basis

    def up(self, y: np.ndarray) -> np.ndarray:
        """The points of R^k with these coordinates in the frame."""
        return self.centre + np.asarray(y, dtype=float) @ self.basis.T

    def framed(self, rec, scale: float):
        """``rec`` as if its samples had been given in the frame's coordinates (for the report's checks).

        Its points, Delaunay vertices and circumcentres in the frame (``rec``'s coordinates divided by
        ``scale`` are the ones the frame was fitted to; the copy keeps that scale), k and the hull's
        dimension r, and one normal per sample within the flat: the vector of Algorithm 1's normal basis that
        projects most onto the flat, normalised (the normal space of a hypersurface of the flat holds the
        flat's own orthogonal complement and that one line; the basis's first vector points to the pole,
        which lies in the flat).  Only what the report reads is moved; the copy is not a result of its own.
        """

        def down(x: np.ndarray) -> np.ndarray:
            return self.down(np.asarray(x) / scale) * scale

        r = self.basis.shape[1]
        proj = np.einsum("kr,nkc->nrc", self.basis, np.asarray(rec.normals))  # (n, r, k - d)
        # the normal basis's vector that projects most onto the flat (the flat's own complement projects to 0;
        # a batched SVD gives the same line at 60 times the cost: 0.67 s for 300,000 samples)
        length = np.linalg.norm(proj, axis=1)
        best = np.take_along_axis(proj, np.argmax(length, axis=1)[:, None, None], axis=2)
        best /= np.maximum(length.max(axis=1), 1e-300)[:, None, None]
        return replace(
            rec,
            points=down(rec.points),
            bounding_points=down(rec.bounding_points),
            voronoi_vertices=down(rec.voronoi_vertices),
            normals=best,
            k=r,
            subspace_dim=r,
        )

    def lift_scaled(self, found: list, scale: float) -> list:
        """Features with locations in the frame at ``scale`` (as the report gives them), in R^k at that scale."""
        return [replace(f, location=self.up(np.asarray(f.location) / scale) * scale) for f in found]

    def lift_features(self, ext) -> None:
        """The features an extraction measured in the frame, in R^k, in place.

        ``ext``'s ``features``, ``removed_features``, ``named_features`` and ``disputed`` are replaced by their
        lifted copies.
        """

        def lift(found):
            return None if found is None else [replace(f, location=self.up(f.location)) for f in found]

        ext.features = lift(ext.features)
        ext.removed_features = lift(ext.removed_features)
        ext.named_features = lift(getattr(ext, "named_features", []))
        ext.disputed = lift(ext.disputed)


def hull_frame(points: np.ndarray, r: int) -> HullFrame:
    """The frame of the r-dimensional affine subspace that best fits ``points`` (their mean and principal axes).

    For points that lie in an r-flat (up to rounding) it is that flat, and the frame's coordinates are an
    isometric copy of the points: distances, angles and Delaunay balls are the same.
    """
    p = np.asarray(points, dtype=float)
    centre = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - centre, full_matrices=False)
    return HullFrame(centre, np.ascontiguousarray(vt[:r].T))
