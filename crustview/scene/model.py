"""The scene model: one reconstruction, its layers, projection, steps, selection.

Qt-free and VTK-free.  Widgets and render adapters subscribe to its signals.
"""

from __future__ import annotations

import numpy as np
from psygnal import Signal

from ..core.analysis.quality import SamplingQuality, sampling_quality
from ..core.analysis.theorems import TheoremChecks, check_theorems
from ..core.result import Reconstruction
from ..core.steps import Cascade
from . import geometry as geo
from .coloring import coordinate_values, default_coloring
from .features import uncertain_features
from .fileattrs import FILE_COLORINGS, applies, file_values
from .layers import Layer, default_layers
from .player import StepPlayer
from .projection import Projection
from .quantities import normal_error, pole_distance
from .selection import Selection
from .timeline import RuleCodes, Timeline, rule_codes, timeline
from .tour import GrandTour

#: New data shows its samples up to this many (more would cover M_S entirely).
SAMPLES_SHOWN = 60_000


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
    #: Emitted when the highlighted prune cascade changes (None: none).
    cascade_changed = Signal(object)
    #: Emitted when the theorem checks (:meth:`check_theorems`) were computed.
    theorems_changed = Signal()
    #: Emitted when the slicing hyperplane moves or its half-space cut is switched.
    slice_changed = Signal()
    #: Emitted when a comparison (:meth:`set_comparison`) is set or dropped.
    comparison_changed = Signal()

    def __init__(self) -> None:
        self.rec: Reconstruction | None = None
        self.kept_view = False
        self.truth = None
        self.source = ""
        #: Colours, intensity and normals of the opened file, per input row (:mod:`crustview.attributes`).
        self.file_attributes: dict = {}
        self.layers: dict[str, Layer] = default_layers()
        self.projection = Projection(3)
        self.tour = GrandTour(self.projection)
        self.player = StepPlayer()
        self.selection = Selection()
        self.test = "cocone"
        self.theta = np.pi / 8
        self._cache: dict[str, object] = {}
        self._quality: tuple[int, SamplingQuality] | None = None
        #: The prune cascade highlighted by the cascade layer (from ``rec.extraction.cascades()``).
        self.cascade: Cascade | None = None
        #: Theorems 2 and 10 measured on the shown reconstruction (built-ins only, on request).
        self.theorems: TheoremChecks | None = None
        #: Offset of the slicing hyperplane along :meth:`slice_normal`, from the projection origin.
        self.slice_offset = 0.0
        #: Whether M_S is cut to the half-space below the slicing hyperplane (while the slice is shown).
        self.slice_cut = False
        #: The shown M_S compared with another complex (:mod:`crustview.scene.comparison`), or None.
        self.comparison = None
        #: Settings of the last file that a new one turned off (see :meth:`set_reconstruction`).
        self.reset_notes: list[str] = []
        #: Layers the last file had hidden that new data shows again (its result: M_S).
        self.shown_notes: list[str] = []

    # -- setting data ----------------------------------------------------
    def set_reconstruction(
        self,
        rec: Reconstruction,
        truth=None,
        source: str = "",
        keep_view: bool = False,
        quality: SamplingQuality | None = None,
    ) -> None:
        """Show ``rec``; ``keep_view`` keeps projection and step (re-extraction).

        ``quality``: the samples' :func:`~crustview.core.analysis.quality.sampling_quality`
        when it was computed already (in the worker thread).
        """
        if quality is not None:
            self._quality = (id(rec.delaunay_simplices), quality)
        same_space = self.rec is not None and self.rec.k == rec.k
        # new data opens on its result (the final M_S); Home or Play replays from T_S
        position = self._kept_position(rec) if keep_view else rec.extraction.n_steps
        #: Whether the last result kept the view (a re-extraction): the camera stays too.
        self.kept_view = bool(keep_view and same_space)
        self.rec = rec
        self.truth = truth
        self.source = source or self.source
        self.test = rec.test
        self.theta = float(rec.theta)
        self._cache = {}
        self.cascade = None
        self.theorems = None
        self.comparison = None  # it compared the previous M_S
        self.reset_notes = []
        self.shown_notes = []
        if not keep_view:
            self.slice_offset = 0.0
            if self.slice_cut:
                self.slice_cut = False
                self.reset_notes.append("the slice cut")
            if self.layers["holes"].visible:
                self.layers["holes"].visible = False
                self.reset_notes.append("Holes of T_S")
        self.selection.feature = None  # a feature of the last result (a re-extraction has its own)
        if not keep_view:
            self.selection.sample = self.selection.simplex = None
            self.selection.face = None
        if not (keep_view and same_space):
            self.tour.pause()
            self.tour.reset()
            self.projection.reset(rec.k, origin=rec.points.mean(axis=0))
        if not keep_view:
            m = self.layers["manifold"]
            if not m.visible:  # new data opens on its result, also after the last file's M_S was hidden
                m.visible = True
                self.shown_notes.append(m.title)
            m.shrink = 0.8 if rec.d >= 3 else 1.0
            m.colorby = default_coloring(rec.k)  # in R^4: the depth the projection drops
            # a curve is thin: a darker, wider line keeps it visible on the light background
            m.color, m.size = ("#b35806", 4.0) if rec.d == 1 else ("#e9b872", 3.0)
            self.layers["removed"].shrink = m.shrink
            self.layers["points"].size = 5.0 if rec.n < 2000 else (3.5 if rec.n < 10000 else 1.5)
            # the samples are part of the result: shown up to a big scan's size (small dots),
            # off only where they would cover the whole surface
            self.layers["points"].visible = rec.n <= SAMPLES_SHOWN
            # segments read well; discs and axis frames clutter, so start those hidden
            self.layers["normals"].visible = rec.n <= 3000 and rec.k - rec.d == 1
        for layer in self.layers.values():  # a colouring this data cannot have (x4 in R^3) is not kept
            if layer.colorings and layer.colorby not in self.colorings(layer.name):
                self.reset_notes.append(f"{layer.title} coloured by {layer.colorby}")
                layer.colorby = "none" if "none" in layer.colorings else layer.colorings[0]
        # a non-orientable surface shows the loop along which its normal flips
        self.layers["orientation"].visible = bool(len(self.one_sided_loop()))
        # what the sample does not support is shown whenever there is any (issue 18)
        self.layers["uncertain"].visible = bool(uncertain_features(rec))
        self.player.set_extraction(rec.extraction, position)
        self.reconstruction_changed.emit()
        self.selection.changed.emit()

    def colorings(self, name: str) -> tuple[str, ...]:
        """The colourings of layer ``name`` that apply to the shown data (menus offer only these).

        Coordinates up to k, the hidden depth from R^4 on, and the ones that need
        a built-in's true manifold (true epsilon, Theorem 2, distance to M) or its
        true tangents (normal error) only when there is one.
        """
        offered = self.layers[name].colorings
        rec = self.rec
        if rec is None:
            return offered
        builtin = self.builtin is not None
        tangents = getattr(self.truth, "tangents", None) is not None
        out = []
        for c in offered:
            if c.startswith("x") and c[1:].isdigit() and int(c[1:]) > rec.k:
                continue
            if c == "hidden depth" and rec.k < 4:
                continue
            if c in ("true epsilon", "Thm 2 error / bound", "distance to M") and not builtin:
                continue
            if c == "normal error" and not tangents:
                continue
            if c in FILE_COLORINGS and not applies(rec, self.file_attributes, c):
                continue
            out.append(c)
        return tuple(out)

    def slice_normal(self) -> np.ndarray:
        """Normal of the slicing hyperplane: the direction the view hides (k >= 4), else the view's depth axis."""
        p = self.projection
        if p.k >= 4:
            return p.hidden
        return p.basis[:, min(2, p.k - 1)] / max(np.linalg.norm(p.basis[:, min(2, p.k - 1)]), 1e-12)

    @property
    def slicing(self) -> bool:
        """Whether the slice is shown (its layer is visible)."""
        return bool(self.layers["slice"].visible) and self.rec is not None

    def slice_values(self) -> np.ndarray:
        """Signed distance of every sample from the slicing hyperplane."""
        assert self.rec is not None
        return (self.rec.points - self.projection.origin) @ self.slice_normal() - self.slice_offset

    def set_slice(self, offset: float | None = None, cut: bool | None = None) -> None:
        """Move the slicing hyperplane to ``offset`` and/or switch the half-space cut."""
        if offset is not None:
            self.slice_offset = float(offset)
        if cut is not None:
            self.slice_cut = bool(cut)
        self.slice_changed.emit()

    def _kept_position(self, rec: Reconstruction) -> int:
        """Where a re-extraction starts.

        The same step if the new run has it, its end if the old one was at its
        end (showing M_S), else step 0 (never a clamped, arbitrary last step).
        Where one of the two runs is the paper's loop and the other the robust
        extension's (other rules, another sequence of steps): its end (the
        extension's step 0 may be an empty M_S, once shown under a green verdict
        after a switch from the middle of a paper-mode replay).
        """
        old, n_old, n_new = self.player.position, self.player.n_steps, rec.extraction.n_steps
        if (old == n_old and old > 0) or (self.rec is not None and _paper_steps(self.rec) != _paper_steps(rec)):
            return n_new
        return old if old <= n_new else 0

    def set_comparison(self, comparison) -> bool:
        """Show ``comparison``, a :class:`~crustview.scene.comparison.Comparison` of the shown result, or None.

        One made for another result is ignored (returns False).
        """
        if comparison is not None and comparison.rec is not self.rec:
            return False
        self.comparison = comparison
        if comparison is not None:
            self.layers["compare"].visible = True  # a comparison just made is seen, even if its layer was off
        self.comparison_changed.emit()
        return True

    def set_cascade(self, cascade: Cascade | None) -> None:
        """Highlight ``cascade`` (one of :meth:`cascades`), or nothing."""
        self.cascade = cascade
        self.cascade_changed.emit(cascade)

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

    @property
    def quality(self) -> SamplingQuality:
        """Estimated sampling quality per sample (:mod:`crustview.core.analysis.quality`).

        Computed on first use and kept across re-extractions (it depends only
        on the Delaunay, the poles and the normals, which they share).
        """
        assert self.rec is not None
        key = id(self.rec.delaunay_simplices)
        if self._quality is None or self._quality[0] != key:
            self._quality = (key, sampling_quality(self.rec))
        return self._quality[1]

    def known_quality(self) -> SamplingQuality | None:
        """:attr:`quality` when it is already at hand for this result (never computes it: no wait on a draw)."""
        key = None if self.rec is None else id(self.rec.delaunay_simplices)
        return self._quality[1] if self._quality is not None and self._quality[0] == key else None

    def cascades(self) -> list[Cascade]:
        """Prune cascades of the shown extraction, largest first (empty for a robust run that fell back)."""
        assert self.rec is not None
        return self._cached("cascades", self.rec.extraction.cascades)

    def cascade_simplices(self, cascade: Cascade | None = None) -> np.ndarray:
        """Ids (rows of ``extraction.simplices``) of every simplex removed by ``cascade``'s steps."""
        assert self.rec is not None
        c = self.cascade if cascade is None else cascade
        if c is None:
            return np.zeros(0, dtype=np.int64)
        steps = self.rec.extraction.steps
        ids = [np.asarray(steps[i].removed, dtype=np.int64) for i in np.asarray(c.steps)]
        return np.concatenate(ids) if ids else np.zeros(0, dtype=np.int64)

    def one_sided_loop(self) -> np.ndarray:
        """Rows of ``rec.manifold`` along a loop where the normal flips (:mod:`.orientation`).

        Empty unless M_S is a non-orientable surface.
        """
        assert self.rec is not None
        rec = self.rec

        def compute():
            if rec.d != 2 or rec.topology.orientable is not False:
                return np.zeros(0, dtype=np.int64)
            from .orientation import one_sided_loop

            return one_sided_loop(np.asarray(rec.manifold))

        return self._cached("one_sided", compute)

    def holes(self) -> np.ndarray:
        """The (d-1)-faces of T_S in a single simplex before extraction, shape (h, d).

        ``rec.extraction.holes`` when the core recorded them, otherwise counted
        on T_S for the extraction's test and threshold.
        """
        assert self.rec is not None
        rec = self.rec

        def compute():
            if rec.extraction.holes is not None:
                return np.asarray(rec.extraction.holes, dtype=np.int64).reshape(-1, rec.d)
            faces, inc = geo.facets(rec.candidates.select(rec.test, rec.theta))
            return faces[np.bincount(inc.ravel(), minlength=len(faces)) == 1]

        return self._cached("holes", compute)

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
        if colorby in FILE_COLORINGS:
            return file_values(rec, self.file_attributes, colorby)
        if colorby == "epsilon":
            return self.quality.epsilon, "estimated epsilon"
        if colorby in ("true epsilon", "Thm 2 error / bound"):
            th = self.theorems
            if th is None:
                return None
            if colorby == "true epsilon":
                return th.epsilon, "true epsilon"
            with np.errstate(divide="ignore", invalid="ignore"):
                return th.normal_error / th.bound, "normal error / Thm 2 bound"
        return coordinate_values(rec.points, self.projection, colorby)

    @property
    def builtin(self):
        """The built-in manifold the samples came from (noise-free), or None."""
        t = self.truth
        if t is None or getattr(t, "manifold", None) is None or getattr(t, "noise", 0.0):
            return None
        return t.manifold

    def check_theorems(self, progress=None, cancel=None) -> TheoremChecks | None:
        """Measure Theorems 2 and 10 (:mod:`crustview.core.analysis.theorems`) for a built-in; None otherwise.

        ``progress`` and ``cancel`` go to :func:`~crustview.core.analysis.theorems.check_theorems`.
        This blocks (seconds); the window runs :meth:`theorem_job` in its worker instead.
        """
        if self.rec is None or self.builtin is None:
            return None
        if self.theorems is None:
            self.set_theorems(self.rec, self.theorem_job()(progress, cancel))
        return self.theorems

    def theorem_job(self):
        """``job(progress, cancel) -> TheoremChecks`` for the shown result, safe to run in another thread.

        It holds the reconstruction it was made for; hand its result to :meth:`set_theorems`.
        """
        rec, manifold, tangents = self.rec, self.builtin, getattr(self.truth, "tangents", None)
        if rec is None or manifold is None:
            raise ValueError("the theorem checks need a noise-free sample of a built-in manifold")

        def job(progress=None, cancel=None) -> TheoremChecks:
            return check_theorems(rec, manifold, tangents, progress=progress, cancel=cancel)

        job.rec = rec  # type: ignore[attr-defined]
        return job

    def set_theorems(self, rec: Reconstruction, checks: TheoremChecks) -> bool:
        """Show ``checks`` if they were measured on the shown ``rec``; False (ignored) otherwise."""
        if rec is not self.rec:
            return False
        self.theorems = checks
        self.theorems_changed.emit()
        return True

    def manifold_values(self, colorby: str) -> tuple[np.ndarray, str] | None:
        """Scalar per row of ``extraction.simplices`` for a colouring of M_S (NaN: none), with its label."""
        rec, th = self.rec, self.theorems
        if rec is None or th is None or colorby != "distance to M":
            return None

        def compute():
            rows = geo.find_rows(rec.extraction.simplices, np.asarray(rec.manifold))
            out = np.full(len(rec.extraction.simplices), np.nan)
            ok = rows >= 0
            out[rows[ok]] = th.ms_distance[ok]
            return out

        return self._cached("ms_distance", compute), "distance of M_S to M"

    def candidate_mask(self) -> np.ndarray:
        """Rows of ``candidates.faces`` the candidates layer shows."""
        assert self.rec is not None
        cands = self.rec.candidates
        last = getattr(self, "_mask_memo", None)
        # one mask kept (read-only): every step asks for its count, the test and theta rarely change
        if last is None or last[0] is not cands or last[1] != (self.test, self.theta):
            mask = cands.mask(self.test, self.theta)
            mask.flags.writeable = False
            last = self._mask_memo = (cands, (self.test, self.theta), mask)
        return last[2]

    @property
    def extraction_facets(self) -> tuple[np.ndarray, np.ndarray]:
        """(d-1)-faces of the extraction's simplices and their incidence."""
        assert self.rec is not None
        return self._cached("facets", lambda: geo.facets(self.rec.extraction.simplices))

    def rule_codes(self) -> RuleCodes:
        """The rule of every recorded step, as small integers."""
        assert self.rec is not None
        return self._cached("rules", lambda: rule_codes(self.rec.extraction))

    def timeline(self) -> Timeline:
        """|M_S|, boundary and non-manifold faces at every step position."""
        assert self.rec is not None
        return self._cached("timeline", lambda: timeline(self.rec.extraction, self.extraction_facets[1]))

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


def _paper_steps(rec: Reconstruction) -> bool:
    """Whether every step of ``rec`` is one of the paper's Algorithm 3 (pruning and resolving)."""
    from ..core.steps import RULE_PRUNE, RULE_RESOLVE

    return all(s.rule in (RULE_PRUNE, RULE_RESOLVE) for s in rec.extraction.steps)
