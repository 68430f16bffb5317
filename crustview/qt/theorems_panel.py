"""Information-panel box: the paper's Theorems 2 and 10 measured on a built-in.

A scatter of each sample's true epsilon against its normal error, with
Theorem 2's bound ``asin(2 eps sqrt(k - d))`` as a curve and its precondition
``eps <= 0.25 / (k - d)`` as a dashed line, and a paragraph of counts.  The
check runs on request (5-60 s) in a worker thread of its own, with progress and Cancel.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QGroupBox, QHBoxLayout, QLabel, QProgressBar, QPushButton, QVBoxLayout, QWidget

from ..core.analysis.theorems import TheoremChecks, theorem2_bound
from ..scene.model import SceneModel
from .worker import Runner

_MARGIN = (34.0, 8.0, 8.0, 20.0)  # left, right, top, bottom


class TheoremScatter(QWidget):
    """Normal error (degrees) against true epsilon, one dot per sample.

    Attributes
    ----------
    checks : TheoremChecks or None
    x_max, y_max : float
        Axis ranges.
    """

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setMinimumHeight(150)
        self.checks: TheoremChecks | None = None
        self.x_max, self.y_max = 1.0, 1.0
        self.setToolTip(
            "Each dot is a sample: x its true ε (largest |p - s| / LFS(p) over the points p of M "
            "nearest to it), y the angle between AN_s and the true normal plane. Curve: Theorem 2's "
            "bound asin(2ε√(k-d)); dashed: its precondition ε = 0.25/(k-d). Red dots break the bound."
        )

    def set_checks(self, checks: TheoremChecks | None) -> None:
        self.checks = checks
        if checks is not None:
            eps = checks.epsilon[np.isfinite(checks.epsilon)]
            self.x_max = max(float(eps.max()) if len(eps) else 0.0, 0.25 / checks.codim) * 1.1
            err = np.degrees(checks.normal_error)
            self.y_max = max(float(np.nanmax(err)), float(np.degrees(theorem2_bound(self.x_max, checks.codim))))
            self.y_max = min(self.y_max * 1.1, 90.0)
        self.update()

    def to_widget(self, eps: np.ndarray, deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Widget coordinates of (epsilon, degrees) pairs."""
        left, right, top, bottom = _MARGIN
        w, h = self.width() - left - right, self.height() - top - bottom
        return left + w * np.asarray(eps) / self.x_max, top + h * (1 - np.asarray(deg) / self.y_max)

    def paintEvent(self, _event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        p.fillRect(self.rect(), QColor("#fbfbf8"))
        c = self.checks
        if c is None:
            p.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, "not checked")
            p.end()
            return
        p.setRenderHint(QPainter.RenderHint.Antialiasing)
        left, right, top, bottom = _MARGIN
        h = self.height()
        p.setPen(QColor("#333333"))
        p.drawLine(int(left), int(h - bottom), int(self.width() - right), int(h - bottom))
        p.drawLine(int(left), int(top), int(left), int(h - bottom))
        p.drawText(QRectF(0, top - 4, left - 3, 14), Qt.AlignmentFlag.AlignRight, f"{self.y_max:.0f}°")
        p.drawText(QRectF(left, h - bottom + 2, 120, 14), Qt.AlignmentFlag.AlignLeft, "ε = 0")
        p.drawText(
            QRectF(self.width() - 130, h - bottom + 2, 122, 14), Qt.AlignmentFlag.AlignRight, f"{self.x_max:.3g}"
        )
        xs = np.linspace(0, self.x_max, 120)
        bx, by = self.to_widget(xs, np.degrees(theorem2_bound(xs, c.codim)))
        p.setPen(QPen(QColor("#1f5fd6"), 1.5))
        p.drawPolyline(QPolygonF([QPointF(float(a), float(b)) for a, b in zip(bx, by)]))
        lim_x, _ = self.to_widget(0.25 / c.codim, 0.0)
        pen = QPen(QColor("#111111"))
        pen.setStyle(Qt.PenStyle.DashLine)
        p.setPen(pen)
        p.drawLine(int(lim_x), int(top), int(lim_x), int(h - bottom))
        p.drawText(QRectF(lim_x + 3, top, 200, 13), Qt.AlignmentFlag.AlignLeft, f"0.25/(k-d) = {0.25 / c.codim:.3g}")
        ok = np.isfinite(c.epsilon)
        x, y = self.to_widget(c.epsilon[ok], np.degrees(c.normal_error[ok]))
        bad = (c.normal_error > c.bound)[ok]
        p.setPen(Qt.PenStyle.NoPen)
        for mask, colour in ((~bad, "#2a8f6a"), (bad, "#d62728")):
            p.setBrush(QColor(colour))
            for a, b in zip(x[mask], y[mask]):
                p.drawEllipse(QPointF(float(a), float(b)), 1.6, 1.6)
        p.end()


def theorem_text(c: TheoremChecks) -> str:
    """The panel's paragraph (HTML): f, epsilon, Theorem 2 and Theorem 10 counts."""
    s = c.summary()
    t2, t10 = s["theorem2"], s["theorem10"]
    n = len(c.epsilon)
    holds = "holds" if t2["precondition_holds"] else "<b>fails</b>"
    lines = [
        f"LFS: {s['lfs']}.",
        f"true ε: max {c.epsilon_global:.3g}, median {s['epsilon_median']:.3g} "
        f"({s['dense_points']:,} points of M; covering radius {c.covering:.2g}).",
        f"<b>Theorem 2</b> (ε ≤ {t2['epsilon_limit']:.3g}: {holds}; {t2['samples_beyond_limit']:,} of {n:,} samples "
        f"beyond it): normal error max {t2['max_error_deg']:.2f}°, median {t2['median_error_deg']:.2f}°; "
        f"bound with the global ε {t2['global_bound_deg']:.2f}°: <b>{t2['beyond_global_bound']}</b> beyond; "
        f"with each sample's own ε: <b>{t2['beyond_local_bound']}</b> beyond.",
    ]
    if t10["max_distance"] is not None:
        pre = "holds" if t10["precondition_holds"] else "<b>fails</b>"
        lines.append(
            f"<b>Theorem 10</b> (ε &lt; {t10['epsilon_limit']:.3g}: {pre}): M_S is at most {t10['max_distance']:.3g} "
            f"from M, {t10['max_ratio']:.3g}·ε·LFS (bound 2.65·ε·LFS); {t10['simplices_beyond']} simplices beyond."
        )
    lines += [f"Note: {x}." for x in s["notes"]]
    lines.append(
        f"{s['seconds']:.1f} s. Colour the samples by 'Thm 2 error / bound' or 'true epsilon', "
        "and M_S by 'distance to M', in the Layers panel."
    )
    return "<br>".join(lines)


class TheoremPanel(QGroupBox):
    """The box in the Information panel; its button runs the check in :attr:`runner` (off the GUI thread)."""

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        # a short title: the group box is as wide as its title, and the tabbed column of a
        # 1024-px window is not wide enough for a longer one
        super().__init__("Theorems 2 and 10 (true ε, LFS)", parent)
        self.setToolTip("The paper's Theorems 2 and 10 on this built-in: true ε, local feature size and normals")
        self.model = model
        lay = QVBoxLayout(self)
        self.button = QPushButton("Check Theorems 2 and 10", self)
        self.button.setToolTip(
            "Sample M densely, compute every sample's true ε and normal error, and the "
            "distance of M_S to M (a few seconds)"
        )
        self.button.clicked.connect(self.run)
        row = QHBoxLayout()
        row.addWidget(self.button, 1)
        self.progress = QProgressBar(self)
        self.progress.setRange(0, 100)
        self.progress.setVisible(False)
        row.addWidget(self.progress, 1)
        self.cancel = QPushButton("Cancel", self)
        self.cancel.setToolTip("Stop the check (the result shown stays as it is)")
        self.cancel.setVisible(False)
        row.addWidget(self.cancel)
        lay.addLayout(row)
        self.runner = Runner(self)
        self.runner.progress.connect(self._progress)
        self.runner.done.connect(self._done)
        self.runner.failed.connect(lambda msg: self._ended(f"The check failed: {msg}"))
        self.runner.cancelled.connect(lambda: self._ended("Cancelled; press the button to check again."))
        self.cancel.clicked.connect(self.runner.cancel)
        self._job = None
        self.scatter = TheoremScatter(self)
        lay.addWidget(self.scatter)
        self.label = QLabel(self)
        self.label.setWordWrap(True)
        self.label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        lay.addWidget(self.label)
        model.reconstruction_changed.connect(self.refresh)
        model.theorems_changed.connect(self.refresh)
        self.refresh()

    def run(self) -> bool:
        """Start the check in the worker; False when it cannot run (busy, or not a built-in)."""
        if self.runner.busy or self.model.builtin is None or self.model.rec is None:
            return False
        self._job = self.model.theorem_job()
        self.runner.start(self._job, "Checking Theorems 2 and 10…")
        self.button.setEnabled(False)
        self.progress.setValue(0)
        self.progress.setFormat("starting…")
        self.progress.setVisible(True)
        self.cancel.setVisible(True)
        self.label.setText("Checking (a few seconds; Cancel stops it)…")
        return True

    def _progress(self, stage: str, fraction: float) -> None:
        self.progress.setValue(int(round(100 * fraction)))
        self.progress.setFormat(f"{stage} %p%")

    def _done(self, checks) -> None:
        job, self._job = self._job, None
        self._idle()
        if job is None or not self.model.set_theorems(job.rec, checks):
            self.refresh()
            self.label.setText("The result changed while checking; press the button to check this one.")

    def _ended(self, text: str) -> None:
        self._job = None
        self._idle()
        self.refresh()
        self.label.setText(text)

    def _idle(self) -> None:
        self.progress.setVisible(False)
        self.cancel.setVisible(False)

    def refresh(self) -> None:
        builtin = self.model.builtin is not None and self.model.rec is not None
        self.setVisible(builtin)
        c = self.model.theorems
        self.scatter.set_checks(c)
        self.scatter.setVisible(c is not None)
        self.button.setEnabled(builtin and c is None and not self.runner.busy)
        if self.runner.busy:
            return
        if c is None:
            self.label.setText(
                "Only for noise-free samples of a built-in manifold, where M is known."
                if not builtin
                else "Not checked yet (a few seconds)."
            )
        else:
            self.label.setText(theorem_text(c))
