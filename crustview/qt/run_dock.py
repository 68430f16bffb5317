"""Run panel: d, candidate test, angle theta, Reconstruct, progress and Cancel."""

from __future__ import annotations

import math
import time

import numpy as np
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLayout,
    QProgressBar,
    QPushButton,
    QSizePolicy,
    QSlider,
    QSpinBox,
    QVBoxLayout,
    QWidget,
)

from ..core.paper.candidates import SCORE_LIMIT
from ..core.result import CANDIDATE_TESTS, EXTRACTION_MODES
from ..scene.describe import TEST_WORDS
from ..scene.model import SceneModel

#: The Run panel's choice of normal planes: (label, value of ``reconstruct(normals=...)``).
NORMAL_LABELS = (("Algorithm 1 (paper)", "paper"), ("smoothed (noise)", "smoothed"))
NORMAL_WORDS = {v: k for k, v in NORMAL_LABELS}
#: Label of each extraction mode in the Run panel.
MODE_LABELS = {"robust": "robust (default)", "paper": "paper's Algorithm 3"}

#: Stage names of the core, in words.
#: A stage that reports no progress for this long shows a busy bar and its elapsed seconds.
STALL_SECONDS = 1.0
#: The bar is drawn again at most once in this many seconds while a job reports (25 times a second, smooth to
#: the eye); the last report always shows, at most this late.  Each redraw of the panel's bar and its copy in
#: the status bar is synchronous: 1.5-2 ms under Xvfb, 4.4 s over the GUI tests' 2,553 reports when every
#: report redrew them (one per percent of each stage and one every 0.1 s: :mod:`.worker` sends no more).
PROGRESS_FRAME_SECONDS = 0.04

STAGES = {
    "prepare": "preparing points",
    "delaunay": "Delaunay triangulation",  # by CGAL or Qhull: the Information panel names which
    "normals": "normal planes (Algorithm 1)",
    "candidates": "candidate complex (Algorithm 2)",
    "extraction": "manifold extraction (Algorithm 3)",
    "topology": "topology report",
    "compare": "comparison with the mesh",
    "quality": "sampling quality (estimated ε)",
}


class RunPanel(QWidget):
    """Parameters of a run and its progress.

    Emits :attr:`reconstruct_requested` with ``(d, test, theta_radians,
    prune_boundary)`` and :attr:`cancel_requested`; the extraction mode is
    read from :attr:`mode`.  Moving the test or theta updates the candidates
    layer of the model at once (the extraction is redone on Reconstruct);
    toggling "prune boundary faces" or choosing another extraction re-extracts
    the current result at once (only Algorithm 3 runs again).
    """

    reconstruct_requested = Signal(int, str, float, bool)
    cancel_requested = Signal()
    #: The progress bar changed (a copy in the status bar follows it).
    progress_shown = Signal()

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        form = QFormLayout()
        form.setContentsMargins(0, 0, 0, 0)
        self.d = QSpinBox(self)
        self.d.setRange(1, 9)
        self.d.setValue(2)
        self.d.setToolTip("Intrinsic dimension d of the manifold (1 = curve, 2 = surface, ...); 1 <= d < k")
        form.addRow("dimension d", self.d)
        self.test = QComboBox(self)
        self.test.addItems(list(CANDIDATE_TESTS))
        for i, t in enumerate(CANDIDATE_TESTS):
            self.test.setItemData(
                i, f"{t}: a d-face is a candidate when {TEST_WORDS.get(t, t)}", Qt.ItemDataRole.ToolTipRole
            )
        self.test.setToolTip(
            "<p>Candidate test of Algorithm 2 (all three are computed; switching re-runs only Algorithm 3):</p>"
            "<p><b>cocone</b> (default): the dual Voronoi cell meets the tangent cocone of <i>some</i> vertex "
            "of the face, the paper's quantifier.<br>"
            "<b>cocone-all</b>: the cell meets the cocone of <i>every</i> vertex (Cocone's rule).<br>"
            "<b>literal</b>: the paper's test as printed, the angle between the cell and AN_s, "
            "orientation only.</p>"
        )
        form.addRow("candidate test", self.test)
        row = QHBoxLayout()
        self.theta = QSlider(Qt.Orientation.Horizontal, self)
        self.theta.setRange(1, int(round(np.degrees(SCORE_LIMIT) * 2)))  # half degrees
        self.theta.setValue(45)
        self.theta.setToolTip(
            "Angle threshold θ of the candidate test (paper: π/8 = 22.5°); "
            "the candidates layer follows at once, Reconstruct re-extracts"
        )
        # θ typed in a box too (the slider alone gave values like 31.0° from a drag)
        self.theta_box = QDoubleSpinBox(self)
        self.theta_box.setRange(0.5, self.theta.maximum() / 2.0)
        self.theta_box.setSingleStep(0.5)
        self.theta_box.setDecimals(1)
        self.theta_box.setSuffix("°")
        self.theta_box.setKeyboardTracking(False)  # typing 31.5 goes to 31.5, not to 3 first
        self.theta_box.setToolTip("Type θ in degrees (to 0.5°) and press Enter; the slider follows")
        self.theta_box.valueChanged.connect(lambda v: self.theta.setValue(int(round(v * 2))))
        row.addWidget(self.theta)
        row.addWidget(self.theta_box)
        form.addRow("angle θ", row)
        self.prune = QCheckBox("prune boundary faces (paper)", self)
        self.prune.setChecked(True)
        self.prune.setToolTip(
            "<p>On (the paper): Algorithm 3 removes every simplex at a (d-1)-face that has a single "
            "simplex. On a scan with holes (e.g. the Stanford bunny) this cascades until everything "
            "is removed.</p><p>Off: boundary faces are kept, so a sample with holes shows as an open "
            "surface; the result is then not a closed manifold (extraction stops 'open').</p>"
            "<p>Toggling re-runs only Algorithm 3 on the current result.</p>"
        )
        form.addRow("", self.prune)
        self.extraction = QComboBox(self)
        for m in EXTRACTION_MODES:
            self.extraction.addItem(MODE_LABELS.get(m, m), m)
        self.extraction.setToolTip(
            "<p><b>robust</b> (default): the paper's Algorithm 3, and where it cannot give a closed "
            "manifold through every sample, an extension: for a hypersurface (a surface in R³, a "
            "3-manifold in R⁴, or of the flat the sample spans) the Delaunay cells are "
            "labelled inside or outside (label-cells, repair-vertex, sculpt-sample; in R³ also cut-handle, "
            "join-parts, open-cap), "
            "and M_S is also grown across boundaries (seed, grow, grow-relaxed, fill-hole, drop-stray, "
            "insert-sample) where the labelling leaves doubt; elsewhere it is grown. "
            "The result is identical whenever the "
            "paper's loop succeeds.</p><p><b>paper's Algorithm 3</b>: exactly as printed (prune sharp "
            "and boundary faces, resolve non-manifold faces); its prune cascades are listed in the "
            "Information panel.</p><p>Switching re-runs only Algorithm 3 on the current result.</p>"
        )
        form.addRow("extraction", self.extraction)
        self.normals = QComboBox(self)
        for label, value in NORMAL_LABELS:
            self.normals.addItem(label, value)
        self.normals.setToolTip(
            "<p><b>Algorithm 1</b> (the paper): each sample's normal plane from its poles, the far "
            "Voronoi vertices.</p><p><b>smoothed</b>: those planes averaged over the samples within two "
            "spacings (crustview.core.robust.smooth_normals): steadier under scanner noise, where single "
            "poles are off by tens of degrees; on a sparse sample it blurs thin parts. The Normal planes "
            "layer and the colouring by normal error show the difference.</p>"
            "<p>Changing it needs a new run (Reconstruct): the candidates depend on the planes.</p>"
        )
        self.normals.currentIndexChanged.connect(lambda *_: self.update_stale())
        form.addRow("normals", self.normals)
        lay = QVBoxLayout(self)
        lay.setContentsMargins(6, 4, 6, 4)
        # the dock grows when the out-of-date note appears instead of squashing the fields
        lay.setSizeConstraint(QLayout.SizeConstraint.SetMinimumSize)
        for w in (self.d, self.test, self.theta, self.prune, self.extraction, self.normals):
            w.setMinimumHeight(w.sizeHint().height())
        lay.addLayout(form)
        buttons = QHBoxLayout()
        self.run = QPushButton("Reconstruct", self)
        self.run.setToolTip(
            "Run the reconstruction with these parameters (only Algorithm 3 again when just the test or θ changed)"
        )
        self.cancel = QPushButton("Cancel", self)
        self.cancel.setEnabled(False)
        self.cancel.setToolTip("Stop the running reconstruction; the previous result stays")
        buttons.addWidget(self.run)
        buttons.addWidget(self.cancel)
        lay.addLayout(buttons)
        self.stale = QLabel(self)
        self.stale.setWordWrap(True)
        self.stale.setStyleSheet("QLabel { background: #fff3cd; color: #6b4e00; padding: 3px; border-radius: 3px; }")
        self.stale.setVisible(False)
        # as tall as its text: the dock's spare height goes below the bar, not into an amber block
        self.stale.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Maximum)
        lay.addWidget(self.stale)
        self.progress = QProgressBar(self)
        self.progress.setRange(0, 1000)
        self.progress.setTextVisible(True)
        self.progress.setFormat("idle")
        self.progress.setValue(0)
        #: (stage words, when it started, when it last reported) while busy
        self._stage: tuple[str, float, float] | None = None
        #: A job runs (its Cancel may already be pressed: then :attr:`cancelling`).
        self.busy = False
        #: Cancel was pressed and the job has not stopped yet (it stops at its next check).
        self.cancelling = False
        self.stall_timer = QTimer(self)
        self.stall_timer.setInterval(250)
        self.stall_timer.timeout.connect(self._stalled)
        #: the last report not drawn yet (stage in words, fraction), drawn by this timer
        self._pending: tuple[str, float] | None = None
        self._drawn_at = -math.inf
        self.frame_timer = QTimer(self)
        self.frame_timer.setSingleShot(True)
        self.frame_timer.timeout.connect(self._draw_progress)
        lay.addWidget(self.progress)
        # the bar's text in full, wrapped, where the bar is too narrow for it (a long verdict: never cut off)
        self.full_text = QLabel(self)
        self.full_text.setWordWrap(True)
        self.full_text.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.full_text.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Maximum)
        self.full_text.setVisible(False)
        lay.addWidget(self.full_text)
        for w in (self.run, self.cancel, self.progress):
            w.setMinimumHeight(w.sizeHint().height())
        self.run.clicked.connect(self._request)
        self.cancel.clicked.connect(self.cancel_requested)
        self.cancel_requested.connect(self._cancelling)  # the status bar's Cancel too
        self.theta.valueChanged.connect(self._theta_moved)
        self.test.currentTextChanged.connect(self._test_changed)
        self.prune.toggled.connect(self._prune_toggled)
        self.extraction.currentIndexChanged.connect(self._mode_changed)
        model.reconstruction_changed.connect(self.sync)
        self._theta_moved(self.theta.value())

    @property
    def mode(self) -> str:
        """The chosen extraction mode, ``"robust"`` or ``"paper"``."""
        return str(self.extraction.currentData())

    def set_mode(self, mode: str) -> None:
        """Choose an extraction mode (re-extracts the current result when it differs)."""
        i = self.extraction.findData(mode)
        if i >= 0:
            self.extraction.setCurrentIndex(i)

    def _mode_changed(self, *_) -> None:
        self.prune.setEnabled(self.mode == "paper" and self.run.isEnabled())
        rec = self.model.rec
        if rec is not None and rec.mode != self.mode:
            self.reconstruct_requested.emit(rec.d, self.test.currentText(), self.theta_radians, self.prune.isChecked())

    @property
    def theta_radians(self) -> float:
        return float(np.radians(self.theta.value() / 2.0))

    def _theta_moved(self, v: int) -> None:
        self._show_theta(v / 2)
        self.model.set_candidate_display(theta=self.theta_radians)
        self.update_stale()

    def _test_changed(self, test: str) -> None:
        self.model.set_candidate_display(test=test)
        self.update_stale()

    @property
    def normals_method(self) -> str:
        """The chosen normal planes, ``"paper"`` (Algorithm 1) or ``"smoothed"``."""
        return str(self.normals.currentData() or "paper")

    def update_stale(self) -> None:
        """Say so when the candidates layer no longer matches M_S and the steps."""
        rec = self.model.rec
        if rec is not None and getattr(rec, "normals_method", "paper") != self.normals_method:
            self.stale.setText(
                f"Normals: <b>{self.normals.currentText()}</b> is chosen; this result was made with "
                f"<b>{NORMAL_WORDS.get(rec.normals_method, rec.normals_method)}</b>. "
                "Press Reconstruct to run it again with the chosen planes."
            )
            self.stale.setVisible(True)
            self.run.setText("Reconstruct")
            self.run.setStyleSheet("QPushButton { font-weight: bold; }")
            return
        # the slider has half-degree steps: a result at 22.3° (API, CLI) shows as 22.5° and is current
        stale = rec is not None and (
            self.test.currentText() != rec.test or self.theta.value() != int(round(np.degrees(rec.theta) * 2))
        )
        if stale:
            self.stale.setText(
                f"The candidates layer shows <b>{self.test.currentText()}</b>, "
                f"θ = {np.degrees(self.theta_radians):.1f}°; "
                f"M_S, the steps and the report are still from <b>{rec.test}</b>, θ = {np.degrees(rec.theta):.1f}°. "
                "Press <b>Re-extract</b> (Algorithm 3 only) to bring them in line."
            )
        self.stale.setVisible(stale)
        same_d = rec is not None and self.d.value() == rec.d
        self.run.setText("Re-extract" if stale and same_d else "Reconstruct")
        self.run.setStyleSheet("QPushButton { font-weight: bold; }" if stale else "")

    def _request(self) -> None:
        self.reconstruct_requested.emit(
            self.d.value(), self.test.currentText(), self.theta_radians, self.prune.isChecked()
        )

    def _prune_toggled(self, on: bool) -> None:
        rec = self.model.rec
        if rec is not None and rec.prune_boundary != bool(on):
            self.reconstruct_requested.emit(rec.d, self.test.currentText(), self.theta_radians, bool(on))

    def _show_theta(self, degrees: float) -> None:
        """The θ box shows ``degrees`` without echoing back to the slider."""
        self.theta_box.blockSignals(True)
        self.theta_box.setValue(float(degrees))
        self.theta_box.blockSignals(False)

    def sync(self) -> None:
        """Show the parameters of the model's reconstruction."""
        rec = self.model.rec
        if rec is None:
            return
        widgets = (self.d, self.test, self.theta, self.prune, self.extraction, self.normals)
        for w in widgets:
            w.blockSignals(True)
        self.normals.setCurrentIndex(max(0, self.normals.findData(getattr(rec, "normals_method", "paper"))))
        self.extraction.setCurrentIndex(max(0, self.extraction.findData(rec.mode)))
        self.prune.setEnabled(rec.mode == "paper" and self.run.isEnabled())
        self.d.setRange(1, max(1, rec.k - 1))
        self.d.setValue(rec.d)
        self.test.setCurrentText(rec.test)
        self.theta.setValue(int(round(np.degrees(rec.theta) * 2)))
        self._show_theta(np.degrees(rec.theta))
        self.prune.setChecked(bool(rec.prune_boundary))
        for w in widgets:
            w.blockSignals(False)
        self.update_stale()

    def sync_prune(self) -> None:
        """Show the prune setting of the current result (after a failed or cancelled run)."""
        rec = self.model.rec
        if rec is not None:
            for w in (self.prune, self.extraction):
                w.blockSignals(True)
            self.prune.setChecked(bool(rec.prune_boundary))
            self.extraction.setCurrentIndex(max(0, self.extraction.findData(rec.mode)))
            for w in (self.prune, self.extraction):
                w.blockSignals(False)

    def set_busy(self, busy: bool, label: str = "") -> None:
        self.busy = busy
        self.cancelling = False
        self._drop_pending()
        self.run.setEnabled(not busy)
        self.prune.setEnabled(not busy and self.mode == "paper")
        self.extraction.setEnabled(not busy)
        # the run's own parameters are shown when it ends: a change made meanwhile was lost without a word
        # (a new user's θ, test and normals snapped back), so they are locked while it runs
        for w in (self.d, self.test, self.theta, self.theta_box, self.normals):
            w.setEnabled(not busy)
        self.cancel.setEnabled(busy)
        if busy:
            self.progress.setStyleSheet("")
            self.progress.setValue(0)
            self.progress.setFormat(label or "starting…")
            self.full_text.setText("")  # the last run's verdict, not this one's
            self.full_text.setVisible(False)
            self._stage = (label or "starting", time.monotonic(), time.monotonic())
            self.stall_timer.start()
        else:
            self.stall_timer.stop()
            self.progress.setRange(0, 1000)
        self.progress_shown.emit()

    def _cancelling(self) -> None:
        """Cancel pressed: say so at once, and take no second press; the job stops at its next check."""
        if not self.busy:
            return
        self.cancelling = True
        self._drop_pending()
        self.cancel.setEnabled(False)
        self.progress.setRange(0, 0)  # busy until the job has stopped
        self.progress.setFormat("cancelling…")
        self.progress_shown.emit()

    def show_progress(self, stage: str, fraction: float) -> None:
        """Draw a job's report now, or keep it for the bar's next frame (:data:`PROGRESS_FRAME_SECONDS`).

        Drawn at once when its stage is new, when it is the last (fraction 1) or when the bar was drawn a
        frame ago or more; otherwise the latest report kept is drawn when the frame is up.
        """
        if self.cancelling:  # the reports still arriving are the stopping job's
            return
        now = time.monotonic()
        words = STAGES.get(stage, stage)
        new = self._stage is None or self._stage[0] != words
        started = now if new else self._stage[1]
        self._stage = (words, started, now)
        self._pending = (words, fraction)
        wait = PROGRESS_FRAME_SECONDS - (now - self._drawn_at)
        if new or fraction >= 1.0 or wait <= 0:
            self._draw_progress()
        elif not self.frame_timer.isActive():
            self.frame_timer.start(max(1, math.ceil(1000 * wait)))

    def _draw_progress(self) -> None:
        self.frame_timer.stop()
        if self._pending is None or self.cancelling:
            return
        words, fraction = self._pending
        self._pending = None
        self._drawn_at = time.monotonic()
        self.progress.setRange(0, 1000)
        self.progress.setValue(int(1000 * max(0.0, min(1.0, fraction))))
        self.progress.setFormat(f"{words} %p%")
        self.progress_shown.emit()

    def _drop_pending(self) -> None:
        """A report not drawn yet is not drawn (the job ended, or its Cancel was pressed)."""
        self.frame_timer.stop()
        self._pending = None

    def _stalled(self) -> None:
        """A stage that reports nothing for a second still moves: a busy bar and its seconds so far."""
        if self._stage is None or self.cancelling:
            return
        words, started, last = self._stage
        now = time.monotonic()
        if now - last < STALL_SECONDS:
            return
        self.progress.setRange(0, 0)  # Qt's busy indicator
        self.progress.setFormat(f"{words}: {now - started:.0f} s")
        self.progress_shown.emit()

    def _fit_text(self) -> None:
        """Show the bar's idle text below it, wrapped, when the bar cannot show all of it."""
        text = self.full_text.text()
        room = self.progress.contentsRect().width() - 12
        self.full_text.setVisible(bool(text) and self.progress.fontMetrics().horizontalAdvance(text) > room)

    def resizeEvent(self, event) -> None:  # noqa: ANN001, D102 - Qt override
        super().resizeEvent(event)
        self._fit_text()

    def show_idle(self, text: str, ok: bool | str | None = None) -> None:
        """Idle text; ``ok=False`` turns the bar red (failed or wrong result), True green, "warn" amber.

        Amber: a closed result with features the sample does not support.
        """
        self.stall_timer.stop()
        self._drop_pending()
        self._stage = None
        self.progress.setRange(0, 1000)
        self.progress.setFormat(text)
        self.progress.setToolTip(text)
        self.full_text.setText(text)
        self._fit_text()
        colour = {True: "#3a8f3a", False: "#c0392b", "warn": "#e0a020"}.get(ok)
        self.progress.setStyleSheet(f"QProgressBar::chunk {{ background: {colour}; }}" if colour else "")
        if ok is not None:
            self.progress.setValue(1000)
        self.progress_shown.emit()
