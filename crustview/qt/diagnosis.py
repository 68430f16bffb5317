"""Information-panel widgets that say why an extraction failed: epsilon histogram, cascades."""

from __future__ import annotations

from html import escape

import numpy as np
from PySide6.QtCore import QRectF, Qt, Signal
from PySide6.QtGui import QColor, QPainter, QPen
from PySide6.QtWidgets import (
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QListWidget,
    QListWidgetItem,
    QPushButton,
    QVBoxLayout,
    QWidget,
)

from ..core.analysis.quality import SamplingQuality
from ..scene.describe import fmt_tuple
from ..scene.model import SceneModel

#: At most this many cascades are listed.
MAX_CASCADES = 500
#: Bars of the histogram over [0, 4 x the largest bound], plus one for everything beyond.
N_BINS = 32


def bar_color(x: float, lo: float, hi: float) -> QColor:
    """The colour the samples' epsilon colouring gives to ``x`` (same breaks)."""
    if x <= lo:
        return QColor("#2a8f6a")
    if x <= hi:
        return QColor("#eecc1a")
    return QColor("#c0301a")


class EpsilonHistogram(QWidget):
    """Bars of the estimated epsilon with the paper's bounds as dashed lines.

    Attributes
    ----------
    edges : ndarray of shape (N_BINS + 1,)
    counts : ndarray of shape (N_BINS + 1,)
        Samples per bar; the last bar holds everything beyond ``edges[-1]``.
    bounds : dict of str to float
    """

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setMinimumHeight(120)
        self.edges = np.zeros(0)
        self.counts = np.zeros(0, dtype=np.int64)
        self.bounds: dict[str, float] = {}
        self.setToolTip(
            "Estimated ε of the samples (cell radius in the tangent plane / distance to the "
            "nearest pole). Dashed: the paper's bounds; bars beyond them are undersampled."
        )

    def set_quality(self, q: SamplingQuality | None) -> None:
        if q is None:
            self.edges, self.counts, self.bounds = np.zeros(0), np.zeros(0, dtype=np.int64), {}
        else:
            self.bounds = dict(q.thresholds)
            hi = 4.0 * max(self.bounds.values())
            self.edges = np.linspace(0.0, hi, N_BINS + 1)
            eps = q.epsilon[np.isfinite(q.epsilon)]
            inside = np.histogram(np.minimum(eps, hi), bins=self.edges)[0]
            inside[-1] -= int((eps >= hi).sum())
            self.counts = np.r_[inside, int((eps >= hi).sum())]
        self.update()

    def bar_rects(self) -> list[QRectF]:
        """Rectangles of the bars in widget coordinates (tests and painting)."""
        if len(self.counts) == 0:
            return []
        w, h = self.width(), self.height()
        left, right, top, bottom = 8.0, 8.0, 18.0, 16.0
        nb = len(self.counts)
        bw = (w - left - right) / (nb + 0.5)  # the overflow bar stands a little apart
        top_count = max(int(self.counts.max()), 1)
        out = []
        for i, c in enumerate(self.counts):
            x = left + bw * (i + (0.5 if i == nb - 1 else 0.0))
            bh = (h - top - bottom) * c / top_count
            out.append(QRectF(x + 0.5, h - bottom - bh, bw - 1.0, bh))
        return out

    def x_of(self, value: float) -> float:
        """Horizontal position of an epsilon value."""
        w = self.width()
        left, right = 8.0, 8.0
        bw = (w - left - right) / (len(self.counts) + 0.5)
        return left + bw * (value / (self.edges[1] - self.edges[0]))

    def paintEvent(self, _event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        p.fillRect(self.rect(), QColor("#fbfbf8"))
        if len(self.counts) == 0:
            p.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, "no reconstruction")
            return
        lo, hi = min(self.bounds.values()), max(self.bounds.values())
        centres = np.r_[(self.edges[:-1] + self.edges[1:]) / 2, np.inf]
        for r, c in zip(self.bar_rects(), centres):
            p.fillRect(r, bar_color(c, lo, hi))
        h = self.height()
        p.setPen(QColor("#333333"))
        p.drawLine(8, h - 16, self.width() - 8, h - 16)
        p.drawText(QRectF(8, h - 15, 60, 14), Qt.AlignmentFlag.AlignLeft, "0")
        p.drawText(QRectF(self.width() - 80, h - 15, 72, 14), Qt.AlignmentFlag.AlignRight, f"≥ {self.edges[-1]:.2g}")
        pen = QPen(QColor("#111111"))
        pen.setStyle(Qt.PenStyle.DashLine)
        p.setPen(pen)
        seen: dict[float, list[str]] = {}
        for name, b in self.bounds.items():
            seen.setdefault(round(b, 6), []).append(name.replace("theorems", "Thm").replace("theorem", "Thm"))
        for j, (b, names) in enumerate(sorted(seen.items())):
            x = self.x_of(b)
            p.drawLine(int(x), 14, int(x), h - 16)
            p.drawText(
                QRectF(x + 3, 1 + 12 * j, 220, 13), Qt.AlignmentFlag.AlignLeft, f"ε = {b:.3g} ({'; '.join(names)})"
            )
        p.end()


def quality_text(q: SamplingQuality) -> str:
    """One paragraph: median, bounds and the samples beyond each."""
    eps = q.epsilon[np.isfinite(q.epsilon)]
    n = len(q.epsilon)
    if len(eps) == 0:
        return "No sample has a finite pole: ε cannot be estimated."
    parts = [f"estimated ε: median {np.median(eps):.3g}, 90% {np.percentile(eps, 90):.3g}, max {eps.max():.3g}"]
    seen: dict[float, list[str]] = {}
    for name, b in q.thresholds.items():
        seen.setdefault(round(b, 6), []).append(name)
    for b, names in sorted(seen.items()):
        c = int(q.beyond(b).sum())
        parts.append(f"beyond {b:.3g} ({', '.join(names)}): <b>{c:,}</b> of {n:,} samples ({100 * c / n:.0f}%)")
    if len(eps) < n:
        parts.append(f"{n - len(eps)} without a finite pole (not estimated)")
    return "<br>".join(parts)


def cascade_words(c) -> str:
    """List entry of a cascade, e.g. "hole at (2, 1903): 14,332 simplices"."""
    kind = "hole" if c.hole else ("resolve" if c.rule == "resolve-nonmanifold" else "sharp face")
    return f"{kind} at {fmt_tuple(c.tau)}: {c.removed:,} simplices ({len(c.steps):,} steps from step {c.origin + 1})"


class DiagnosisPanel(QWidget):
    """Sampling-quality histogram and the list of prune cascades.

    Emits :attr:`cascade_clicked` with the chosen cascade (the window frames
    it) and :attr:`paper_requested` when the user asks for the paper's run.
    """

    cascade_clicked = Signal(object)
    paper_requested = Signal()

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        lay = QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        box = QGroupBox("Sampling quality (estimated ε per sample)", self)
        bl = QVBoxLayout(box)
        self.histogram = EpsilonHistogram(box)
        bl.addWidget(self.histogram)
        self.quality_label = QLabel(box)
        self.quality_label.setWordWrap(True)
        self.quality_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        bl.addWidget(self.quality_label)
        lay.addWidget(box)
        box = QGroupBox("Prune cascades (Algorithm 3), largest first", self)
        bl = QVBoxLayout(box)
        self.cascade_label = QLabel(box)
        self.cascade_label.setWordWrap(True)
        bl.addWidget(self.cascade_label)
        self.to_paper = QPushButton("Look at the paper's run (re-extract with Algorithm 3)", box)
        self.to_paper.setToolTip(
            "Switch the Run panel's extraction to the paper's Algorithm 3; only Algorithm 3 runs again"
        )
        self.to_paper.clicked.connect(self.paper_requested)
        bl.addWidget(self.to_paper)
        self.cascades = QListWidget(box)
        self.cascades.setMinimumHeight(110)
        self.cascades.setToolTip(
            "Click a cascade: the view frames its origin face and highlights every simplex its steps removed"
        )
        self.cascades.itemClicked.connect(self._clicked)
        self.cascades.itemActivated.connect(self._clicked)
        bl.addWidget(self.cascades)
        row = QHBoxLayout()
        self.to_first = QPushButton("Go to its first step", box)
        self.to_first.setToolTip("Jump to just after the step that started the chosen cascade (its origin)")
        self.to_first.clicked.connect(self._to_first)
        self.play_alone = QPushButton("Play it alone", box)
        self.play_alone.setToolTip(
            "Replay only the chosen cascade's steps, from its origin on, at the Steps panel's speed"
        )
        self.play_alone.clicked.connect(self._play_alone)
        for b in (self.to_first, self.play_alone):
            b.setEnabled(False)
            row.addWidget(b)
        bl.addLayout(row)
        lay.addWidget(box)
        self._list: list = []
        model.reconstruction_changed.connect(self.refresh)

    def refresh(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        q = self.model.quality
        self.histogram.set_quality(q)
        self.quality_label.setText(quality_text(q))
        self._list = self.model.cascades()
        self.cascades.clear()
        for b in (self.to_first, self.play_alone):
            b.setEnabled(False)  # until a cascade of this result is chosen
        ext = rec.extraction
        # a robust run whose paper loop succeeded is the paper's own log (no added_at):
        # its cascades, if any, are listed like a paper run's
        grown = rec.mode == "robust" and ext.added_at is not None
        if grown and not self._list:
            self.cascade_label.setText(
                "This robust run's log has no prune cascades: the paper's loop was abandoned "
                "(see the notes above) and the robust extension built M_S instead (labelled or grown). "
                "The paper's run shows where its "
                "pruning cascaded."
            )
            self.to_paper.setVisible(True)
        else:
            total = sum(c.removed for c in self.list)
            holes = sum(c.hole for c in self.list)
            self.cascade_label.setText(
                f"{len(self.list):,} cascades ({holes:,} from holes of T_S) removed {total:,} of "
                f"{len(ext.simplices):,} simplices"
                + (f"; the first {MAX_CASCADES} listed" if len(self.list) > MAX_CASCADES else "")
                + ". Click one to frame and highlight it."
                if self.list
                else "No prune cascades: Algorithm 3 removed nothing that exposed other faces."
            )
            self.to_paper.setVisible(False)
        for c in self.list[:MAX_CASCADES]:
            item = QListWidgetItem(cascade_words(c))
            item.setToolTip(escape(cascade_words(c)))
            self.cascades.addItem(item)

    @property
    def list(self) -> list:
        """The cascades listed, in list order."""
        return self._list

    def _clicked(self, item) -> None:
        row = self.cascades.row(item)
        if 0 <= row < len(self._list):
            c = self._list[row]
            self.model.set_cascade(c)
            self.cascade_clicked.emit(c)
            for b in (self.to_first, self.play_alone):
                b.setEnabled(True)

    def _to_first(self) -> None:
        c = self.model.cascade
        if c is not None:
            self.model.player.set_step(int(c.origin) + 1)

    def _play_alone(self) -> None:
        c = self.model.cascade
        if c is not None:
            self.model.player.play_only(np.asarray(c.steps))
