"""Grand tour: a smooth walk through random projections of R^k.

The tour moves the projection frame along the geodesic of SO(k) from the
current frame to a random target frame, then picks a new target.  Only the
model lives here; a timer in the Qt layer calls :meth:`GrandTour.advance`.
"""

from __future__ import annotations

import numpy as np
from psygnal import Signal
from scipy.linalg import expm, logm

from .projection import Projection


def random_frame(k: int, m: int, rng: np.random.Generator) -> np.ndarray:
    """A uniformly random ``(k, m)`` matrix with orthonormal columns."""
    q, r = np.linalg.qr(rng.standard_normal((k, m)))
    return q * np.sign(np.diag(r))


def _complete(frame: np.ndarray) -> np.ndarray:
    """Extend orthonormal columns to an orthonormal basis of R^k."""
    k, m = frame.shape
    if m == k:
        return frame.copy()
    q, _ = np.linalg.qr(np.hstack([frame, np.eye(k)]))
    full = q[:, :k]
    full[:, :m] = frame  # qr may flip signs of the given columns
    # re-orthogonalise the completion against the given frame
    rest = full[:, m:] - frame @ (frame.T @ full[:, m:])
    rest, _ = np.linalg.qr(rest)
    return np.hstack([frame, rest])


def geodesic(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Real skew matrix ``L`` with ``expm(L) @ a == b`` (a rotation of R^k).

    ``a`` and ``b`` are ``(k, m)`` frames with orthonormal columns.
    """
    fa = _complete(a)
    b = b.copy()
    fb = _complete(b)
    if np.linalg.det(fb) * np.linalg.det(fa) < 0:
        if fb.shape[1] > b.shape[1]:
            fb[:, -1] *= -1
        else:  # no free column: flip the target's last axis instead
            b[:, -1] *= -1
            fb[:, b.shape[1] - 1] *= -1
    q = fb @ fa.T
    lg = np.real(logm(q))
    return 0.5 * (lg - lg.T)


class GrandTour:
    """Animated tour of a :class:`Projection` through random frames.

    Parameters
    ----------
    projection : Projection
        The projection the tour drives.
    speed : float
        Angular speed in radians per second.
    seed : int
        Seed of the random targets (tours are reproducible).
    """

    #: Emitted with True/False when the tour starts or pauses.
    playing_changed = Signal(bool)

    def __init__(self, projection: Projection, speed: float = 0.4, seed: int = 0) -> None:
        self.projection = projection
        self.speed = float(speed)
        self.rng = np.random.default_rng(seed)
        self.playing = False
        self._start: np.ndarray | None = None
        self._log: np.ndarray | None = None
        self._length = 0.0
        self._t = 0.0
        self._last: np.ndarray | None = None

    @property
    def m(self) -> int:
        return min(self.projection.k, 3)

    def play(self) -> None:
        if not self.playing:
            self.playing = True
            self.playing_changed.emit(True)

    def pause(self) -> None:
        if self.playing:
            self.playing = False
            self.playing_changed.emit(False)

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def _new_target(self) -> None:
        k = self.projection.k
        self._start = self.projection.basis[:, : self.m]
        target = random_frame(k, self.m, self.rng)
        self._log = geodesic(self._start, target)
        self._length = float(np.linalg.norm(self._log) / np.sqrt(2.0)) or 1e-9
        self._t = 0.0

    def advance(self, dt: float) -> np.ndarray:
        """Move ``dt`` seconds along the tour and update the projection.

        Returns the new basis.  Works whether or not the tour is playing (the
        Qt timer only calls it while playing).
        """
        moved = self._last is not None and not np.allclose(self.projection.basis[:, : self.m], self._last, atol=1e-9)
        if self._log is None or self._t >= 1.0 or self._start is None or moved:
            self._new_target()
        assert self._log is not None and self._start is not None
        self._t = min(1.0, self._t + self.speed * dt / self._length)
        frame = expm(self._t * self._log) @ self._start
        basis = np.zeros((self.projection.k, 3))
        basis[:, : self.m] = frame
        self.projection.follow_basis(basis, "grand tour")  # the rotation sliders follow the tour
        self._last = self.projection.basis[:, : self.m]
        return basis

    def reset(self) -> None:
        """Forget the current target (after the projection was set by hand)."""
        self._log = None
        self._start = None
        self._last = None
