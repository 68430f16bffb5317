"""The scene model: one reconstruction, its layers, projection, steps, selection.

Qt-free and VTK-free.  Widgets and render adapters subscribe to its signals.
"""

from __future__ import annotations

import numpy as np
from psygnal import Signal

from ..core.result import Reconstruction
from . import geometry as geo
from .layers import Layer, default_layers
from .player import StepPlayer
from .projection import Projection
from .quantities import normal_error, pole_distance
from .selection import Selection
from .tour import GrandTour


class SceneModel:
    """Everything the viewer shows, independent of how it is drawn.

    Attributes
    ----------
    rec : Reconstruction or None
    truth : object or None
        The built-in ``Sample`` the points came from (``.tangents``,
        ``.manifold``), when known.
    source : str
        What was reconstructed (manifold name or file path).
    layers : dict of str to Layer
    projection : Projection
    tour : GrandTour
    player : StepPlayer
    selection : Selection
    test, theta : str, float
        Candidate test and threshold the candidates layer displays (the run
        panel's values; the extraction itself used ``rec.test, rec.theta``).
    """

    #: Emitted after a new reconstruction (or re-extraction) was set.
    reconstruction_changed = Signal()
    #: Emitted when the displayed candidate test or threshold changes.
    candidates_changed = Signal()

    def __init__(self) -> None:
        self.rec: Reconstruction | None = None
        self.kept_view = False
        self.truth = None
        self.source = ""
        self.layers: dict[str, Layer] = default_layers()
        self.projection = Projection(3)
        self.tour = GrandTour(self.projection)
        self.player = StepPlayer()
        self.selection = Selection()
        self.test = "cocone"
        self.theta = np.pi / 8
        self._cache: dict[str, object] = {}

    # -- setting data ----------------------------------------------------
    def set_reconstruction(self, rec: Reconstruction, truth=None, source: str = "", keep_view: bool = False) -> None:
        """Show ``rec``; ``keep_view`` keeps projection and step (re-extraction)."""
        same_space = self.rec is not None and self.rec.k == rec.k
        position = self.player.position if keep_view else 0
        #: Whether the last result kept the view (a re-extraction): the camera stays too.
        self.kept_view = bool(keep_view and same_space)
        self.rec = rec
        self.truth = truth
        self.source = source or self.source
        self.test = rec.test
        self.theta = float(rec.theta)
        self._cache = {}
        if not keep_view:
            self.selection.sample = self.selection.simplex = None
            self.selection.face = None
        if not (keep_view and same_space):
            self.tour.pause()
            self.tour.reset()
            self.projection.reset(rec.k, origin=rec.points.mean(axis=0))
        if not keep_view:
            m = self.layers["manifold"]
            m.shrink = 0.8 if rec.d >= 3 else 1.0
            # a curve is thin: a darker, wider line keeps it visible on the light background
            m.color, m.size = ("#b35806", 4.0) if rec.d == 1 else ("#e9b872", 3.0)
            self.layers["removed"].shrink = m.shrink
            self.layers["points"].size = 5.0 if rec.n < 2000 else (3.5 if rec.n < 10000 else 1.5)
            # tens of thousands of samples hide the surface: start with them off
            self.layers["points"].visible = rec.n <= 10000
            # segments read well; discs and axis frames clutter, so start those hidden
            self.layers["normals"].visible = rec.n <= 3000 and rec.k - rec.d == 1
        self.player.set_extraction(rec.extraction, position)
        self.reconstruction_changed.emit()
        self.selection.changed.emit()

    def set_candidate_display(self, test: str | None = None, theta: float | None = None) -> None:
        """Change the test / threshold the candidates layer shows."""
        if test is not None:
            self.test = test
        if theta is not None:
            self.theta = float(theta)
        self.candidates_changed.emit()

    # -- derived data (cached per reconstruction) --------------------------
    def _cached(self, key: str, fn):
        if key not in self._cache:
            self._cache[key] = fn()
        return self._cache[key]

    @property
    def spacing(self) -> np.ndarray:
        """Local spacing of each sample (mean distance to 2 nearest samples)."""
        assert self.rec is not None
        return self._cached("spacing", lambda: geo.local_spacing(self.rec.points))

    @property
    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """Clipping box in R^k around the samples."""
        assert self.rec is not None
        return self._cached("box", lambda: geo.data_box(self.rec.points, 0.15))

    @property
    def radius(self) -> float:
        """Largest distance of a sample from the projection origin."""
        assert self.rec is not None
        return self._cached(
            "radius", lambda: float(np.linalg.norm(self.rec.points - self.projection.origin, axis=1).max() or 1.0)
        )

    def point_values(self, colorby: str) -> tuple[np.ndarray, str] | None:
        """Scalar per sample for a colouring of the points layer, with its label."""
        rec = self.rec
        if rec is None or colorby == "none":
            return None
        if colorby == "normal error":
            if self.truth is None or getattr(self.truth, "tangents", None) is None:
                return None
            return self._cached("nerr", lambda: normal_error(rec, self.truth.tangents)), "normal error (deg)"
        if colorby == "pole distance":
            return self._cached("pdist", lambda: pole_distance(rec, self.spacing)), "pole distance / spacing"
        if colorby == "local spacing":
            return self.spacing, "local spacing"
        return None

    def candidate_mask(self) -> np.ndarray:
        """Rows of ``candidates.faces`` the candidates layer shows."""
        assert self.rec is not None
        return self.rec.candidates.mask(self.test, self.theta)

    @property
    def extraction_facets(self) -> tuple[np.ndarray, np.ndarray]:
        """(d-1)-faces of the extraction's simplices and their incidence."""
        assert self.rec is not None
        return self._cached("facets", lambda: geo.facets(self.rec.extraction.simplices))

    def open_faces(self, position: int | None = None):
        """(d-1)-faces that are boundary (1 simplex) or non-manifold (> 2).

        Returns ``(faces, counts)`` sorted with non-manifold faces first.
        """
        assert self.rec is not None
        i = self.player.position if position is None else position
        faces, inc = self.extraction_facets
        counts = geo.face_counts(inc, self.rec.extraction.alive(i), len(faces))
        bad = np.flatnonzero((counts == 1) | (counts > 2))
        order = np.argsort(~(counts[bad] > 2), kind="stable")
        bad = bad[order]
        return faces[bad], counts[bad]

    def candidate_row(self, ext_id: int) -> int:
        """Row of ``candidates.faces`` of extraction simplex ``ext_id`` (-1 if none)."""
        assert self.rec is not None
        row = self.rec.extraction.simplices[ext_id]
        return int(geo.find_rows(self.rec.candidates.faces, row[None])[0])

    def extraction_id(self, face_row: int) -> int:
        """Extraction simplex of candidate row ``face_row`` (-1 if not in T_S)."""
        assert self.rec is not None
        row = self.rec.candidates.faces[face_row]
        return int(geo.find_rows(self.rec.extraction.simplices, row[None])[0])
