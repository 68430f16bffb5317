"""Linear projection of R^k to the 3-D view.

Every layer keeps its data in R^k; drawing applies one ``k x 3`` matrix with
orthonormal columns to all of them.  2-D data is shown flat (third column 0).
"""

from __future__ import annotations

import numpy as np
from psygnal import Signal

#: What the grand tour's description adds in the window (its angles are there to read and move).
TOUR_SLIDERS = " (its angles are on the rotation sliders)"


def _orthonormal_columns(basis: np.ndarray, k: int) -> np.ndarray:
    """Validate a ``(k, 3)`` basis and re-orthonormalise its non-zero columns."""
    basis = np.asarray(basis, dtype=float)
    if basis.shape != (k, 3):
        raise ValueError(f"projection basis must have shape ({k}, 3), got {basis.shape}")
    m = min(k, 3)
    q, r = np.linalg.qr(basis[:, :m])
    q = q * np.sign(np.where(np.diag(r) == 0, 1.0, np.diag(r)))  # keep orientation
    out = np.zeros((k, 3))
    out[:, :m] = q
    return out


def givens(k: int, i: int, j: int, angle: float) -> np.ndarray:
    """Rotation of R^k by ``angle`` (radians) in the coordinate plane (x_i, x_j)."""
    if not (0 <= i < k and 0 <= j < k and i != j):
        raise ValueError(f"plane ({i}, {j}) is not a coordinate plane of R^{k}")
    g = np.eye(k)
    c, s = np.cos(angle), np.sin(angle)
    g[i, i] = c
    g[j, j] = c
    g[i, j] = -s
    g[j, i] = s
    return g


class Projection:
    """A ``k x 3`` orthonormal basis, plus per-plane rotation angles.

    The displayed basis is ``R @ base`` where ``base`` comes from a coordinate
    choice, PCA or the grand tour, and ``R`` is the product of rotations in
    the coordinate planes ``(i, j)`` by :attr:`angles` (sorted by plane).

    Parameters
    ----------
    k : int
        Ambient dimension (>= 2).

    Examples
    --------
    >>> p = Projection(4)
    >>> p.set_coordinates(0, 2, 3)
    >>> p.project(np.eye(4))[:, 1]
    array([0., 0., 1., 0.])
    """

    #: Emitted after every change of the basis.
    changed = Signal()

    def __init__(self, k: int = 3) -> None:
        self._init(k)

    def _init(self, k: int) -> None:
        if k < 2:
            raise ValueError(f"ambient dimension must be at least 2, got {k}")
        self.k = int(k)
        self.origin = np.zeros(self.k)
        self._base = np.eye(self.k, 3)
        self._angles: dict[tuple[int, int], float] = {}
        self._basis = self._base.copy()
        self.source = "coordinates (1, 2, 3)" if k >= 3 else "plane (1, 2)"
        #: Radius of the 3-sphere (about :attr:`origin`) of the stereographic view; 0: linear view.
        self.stereo_radius = 0.0

    def reset(self, k: int, origin: np.ndarray | None = None) -> None:
        """Start over in R^k: first three coordinates, given origin."""
        self._init(k)
        if origin is not None:
            self.origin = np.asarray(origin, dtype=float).reshape(self.k)
        self.changed.emit()

    # -- reading ---------------------------------------------------------
    @property
    def basis(self) -> np.ndarray:
        """The current ``(k, 3)`` basis (a copy)."""
        return self._basis.copy()

    @property
    def angles(self) -> dict[tuple[int, int], float]:
        """Rotation angle (radians) per coordinate plane ``(i, j)``, ``i < j``."""
        return dict(self._angles)

    @property
    def flat(self) -> bool:
        """True when the data is 2-D and shown in the plane z = 0."""
        return self.k < 3

    def project(self, x: np.ndarray) -> np.ndarray:
        """Project points of shape ``(..., k)`` to ``(..., 3)`` view coordinates.

        Linear (``(x - origin) @ basis``), or, with :attr:`stereographic` on,
        the stereographic projection of the 4-space spanned by the basis and
        the :attr:`hidden` direction, from the pole ``origin + r * hidden``.
        """
        x = np.asarray(x, dtype=float)
        if x.shape[-1] != self.k:
            raise ValueError(f"expected points with {self.k} coordinates, got shape {x.shape}")
        y = (x - self.origin) @ self._basis
        if not self.stereographic:
            return y
        r = self.stereo_radius
        h = (x - self.origin) @ self.hidden
        # points at the pole go to infinity: stop at 20 radii
        return y * (r / np.maximum(r - h, r / 20.0))[..., None]

    @property
    def stereographic(self) -> bool:
        """Whether the view is the stereographic projection (k >= 4 only)."""
        return self.stereo_radius > 0 and self.k >= 4

    def set_stereographic(self, radius: float) -> None:
        """Stereographic view of a 3-sphere of ``radius`` about :attr:`origin` (0: linear view)."""
        if radius and self.k < 4:
            raise ValueError("the stereographic view needs points in R^4 or more")
        self.stereo_radius = float(max(radius, 0.0))
        self.changed.emit()

    @property
    def hidden(self) -> np.ndarray:
        """The unit direction the view drops: orthogonal to the basis (k >= 4; zeros otherwise).

        For k > 4 it is the complement direction along which the basis was last
        rotated least, taken from an orthonormal completion of the basis.
        """
        if self.k < 4:
            return np.zeros(self.k)
        q, _ = np.linalg.qr(np.column_stack([self._basis, np.eye(self.k)]))
        u = q[:, 3]
        u = u - self._basis @ (self._basis.T @ u)
        u /= np.linalg.norm(u)
        return u if u[np.argmax(np.abs(u))] > 0 else -u

    def axis_labels(self, digits: int = 2, tol: float = 0.005) -> list[str]:
        """Each view axis as a combination of the ambient coordinates.

        Returns strings like ``"0.71 x1 + 0.71 x3"`` (coordinates 1-based).
        """
        labels = []
        for c in range(3):
            col = self._basis[:, c]
            terms = []
            for i in np.argsort(-np.abs(col), kind="stable"):
                if abs(col[i]) < tol:
                    continue
                v = col[i]
                if abs(abs(v) - 1) < tol:
                    coef = "-" if v < 0 else ""
                else:
                    coef = f"{v:.{digits}f} "
                terms.append(f"{coef}x{i + 1}")
            labels.append(" + ".join(terms).replace("+ -", "- ") if terms else "0")
        return labels

    def state(self) -> dict:
        """Everything that fixes the view, as plain lists (for session files).

        ``k``, ``origin``, ``base`` (k x 3), ``angles`` (rows ``[i, j, radians]``),
        ``source`` and ``stereo_radius``; :meth:`restore` takes it back.
        """
        return {
            "k": self.k,
            "origin": self.origin.tolist(),
            "base": self._base.tolist(),
            "angles": [[i, j, a] for (i, j), a in sorted(self._angles.items())],
            "source": self.source,
            "stereo_radius": self.stereo_radius,
        }

    def restore(self, state: dict) -> None:
        """Show the view of :meth:`state` again (same ``k`` only).

        Raises
        ------
        ValueError
            When the state is for another ambient dimension or malformed.
        """
        k = int(state["k"])
        if k != self.k:
            raise ValueError(f"the saved projection is for R^{k}, the data is in R^{self.k}")
        origin = np.asarray(state["origin"], dtype=float).reshape(-1)
        if origin.shape != (k,):
            raise ValueError(f"the saved projection origin has {origin.size} coordinates, not {k}")
        base = _orthonormal_columns(np.asarray(state["base"], dtype=float), k)
        angles = {}
        for i, j, a in state.get("angles", []):
            givens(k, int(i), int(j), 0.0)  # validates the plane
            angles[(min(int(i), int(j)), max(int(i), int(j)))] = float(a) if i < j else -float(a)
        self.origin = origin
        self._base = base
        self._angles = angles
        self.source = str(state.get("source", "custom"))
        self.stereo_radius = float(state.get("stereo_radius", 0.0)) if k >= 4 else 0.0
        self._update()

    # -- changing --------------------------------------------------------
    def set_origin(self, origin: np.ndarray) -> None:
        """Point of R^k that is drawn at the view origin (usually the data centre)."""
        origin = np.asarray(origin, dtype=float).reshape(-1)
        if origin.shape != (self.k,):
            raise ValueError(f"origin must have {self.k} coordinates, got {origin.shape}")
        self.origin = origin
        self.changed.emit()

    @property
    def description(self) -> str:
        """The base of the projection, and the planes it is rotated in (for labels)."""
        if self.source == "grand tour":
            return "grand tour" + TOUR_SLIDERS
        planes = [f"x{i + 1}-x{j + 1}" for (i, j), a in sorted(self._angles.items()) if a]
        return self.source + (", rotated in " + ", ".join(planes) if planes else "")

    def set_base(self, basis: np.ndarray, source: str = "custom") -> None:
        """Replace the base basis and reset the plane rotations."""
        self._base = _orthonormal_columns(basis, self.k)
        self._angles = {}
        self.source = source
        self._update()

    def set_coordinates(self, i: int, j: int, h: int | None = None) -> None:
        """Show ambient coordinates ``i, j, h`` (0-based) as the view x, y, z."""
        idx = [i, j] + ([] if h is None else [h])
        if len(set(idx)) != len(idx) or not all(0 <= a < self.k for a in idx):
            raise ValueError(f"need distinct coordinates in 0..{self.k - 1}, got {idx}")
        b = np.zeros((self.k, 3))
        for c, a in enumerate(idx[:3]):
            b[a, c] = 1.0
        self.set_base(b, "coordinates (" + ", ".join(str(a + 1) for a in idx) + ")")

    def set_pca(self, points: np.ndarray) -> None:
        """Principal axes of ``points`` (largest variance first)."""
        x = np.asarray(points, dtype=float)
        x = x - x.mean(axis=0)
        _, _, vt = np.linalg.svd(x, full_matrices=False)
        b = np.zeros((self.k, 3))
        m = min(self.k, 3)
        b[:, :m] = vt[:m].T
        self.set_base(b, "PCA")

    def set_angle(self, i: int, j: int, angle: float) -> None:
        """Set the rotation angle (radians) in the coordinate plane ``(i, j)``."""
        if i > j:
            i, j, angle = j, i, -angle
        givens(self.k, i, j, 0.0)  # validates the plane
        self._angles[(i, j)] = float(angle)
        self._update()

    def rotate(self, i: int, j: int, angle: float) -> None:
        """Rotate the current basis by ``angle`` more in the plane ``(i, j)``."""
        key = (min(i, j), max(i, j))
        sign = 1.0 if i < j else -1.0
        self.set_angle(key[0], key[1], self._angles.get(key, 0.0) + sign * angle)

    def planes(self) -> list[tuple[int, int]]:
        """Every coordinate plane ``(i, j)``, ``i < j``, in the order rotations are applied."""
        return [(i, j) for i in range(self.k) for j in range(i + 1, self.k)]

    def _rotation(self, angles: dict[tuple[int, int], float]) -> np.ndarray:
        r = np.eye(self.k)
        for (i, j), a in sorted(angles.items()):
            if a:
                r = givens(self.k, i, j, a) @ r
        return r

    def follow_basis(self, basis: np.ndarray, source: str = "custom", max_planes: int = 15) -> None:
        """Show ``basis`` as plane rotations of the coordinate basis, so the angles follow it.

        The angles are fitted (least squares, from the current angles, so a
        moving basis such as the grand tour's gives continuous angles).  With
        more than ``max_planes`` planes, or when the fit misses, this is
        :meth:`set_base`.
        """
        from scipy.optimize import least_squares

        target = _orthonormal_columns(basis, self.k)
        planes = self.planes()
        if self.k < 3 or len(planes) > max_planes:
            self.set_base(target, source)
            return
        start = (
            np.array([self._angles.get(p, 0.0) for p in planes])
            if np.allclose(self._base, np.eye(self.k, 3))
            else np.zeros(len(planes))
        )
        e = np.eye(self.k, 3)

        def residual(a: np.ndarray) -> np.ndarray:
            return (self._rotation(dict(zip(planes, a))) @ e - target).ravel()

        fit = least_squares(residual, start, xtol=1e-12, ftol=1e-12, gtol=1e-12)
        if np.abs(residual(fit.x)).max() > 1e-6:
            self.set_base(target, source)
            return
        wrapped = (fit.x + np.pi) % (2 * np.pi) - np.pi
        self._base = e.copy()
        self._angles = dict(zip(planes, (float(a) for a in wrapped)))
        self.source = source
        self._update()

    def _update(self) -> None:
        r = self._rotation(self._angles)
        b = r @ self._base
        if self.k < 3:
            b[:, self.k :] = 0.0
        self._basis = b
        self.changed.emit()
