"""Information-panel box: the file's own normals held against AN_s (a histogram of the angles per sample)."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QRectF, Qt, Signal
from PySide6.QtGui import QColor, QPainter
from PySide6.QtWidgets import QGroupBox, QLabel, QPushButton, QVBoxLayout, QWidget

from ..scene.fileattrs import angle_histogram
from ..scene.model import SceneModel


class AngleHistogram(QWidget):
    """Bars of the angle between each sample's file normal and AN_s, 0 to 90 degrees in 5-degree bins."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setMinimumHeight(100)
        self.edges = np.zeros(0)
        self.counts = np.zeros(0, dtype=np.int64)
        self.setToolTip(
            "Angle between the normal stored in the file and the approximate normal plane AN_s of Algorithm 1: "
            "0° where the file's normal lies in AN_s"
        )

    def set_histogram(self, summary: dict | None) -> None:
        if not summary:
            self.edges, self.counts = np.zeros(0), np.zeros(0, dtype=np.int64)
        else:
            self.edges = np.asarray(summary["histogram"]["edges_degrees"], dtype=float)
            self.counts = np.asarray(summary["histogram"]["counts"], dtype=np.int64)
        self.update()

    def bar_rects(self) -> list[QRectF]:
        if len(self.counts) == 0:
            return []
        w, h = self.width(), self.height()
        left, right, top, bottom = 8.0, 8.0, 8.0, 16.0
        bw = (w - left - right) / len(self.counts)
        top_count = max(int(self.counts.max()), 1)
        out = []
        for i, c in enumerate(self.counts):
            bh = (h - top - bottom) * c / top_count
            out.append(QRectF(left + bw * i + 0.5, h - bottom - bh, bw - 1.0, bh))
        return out

    def paintEvent(self, _event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        p.fillRect(self.rect(), QColor("#fbfbf8"))
        if len(self.counts) == 0:
            p.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, "no file normals")
            p.end()
            return
        for r, lo in zip(self.bar_rects(), self.edges[:-1]):
            t = min(lo / 45.0, 1.0)  # green near 0, red from 45 degrees on
            p.fillRect(r, QColor.fromRgbF(0.2 + 0.7 * t, 0.65 - 0.45 * t, 0.3 - 0.1 * t))
        h, w = self.height(), self.width()
        p.setPen(QColor("#333333"))
        p.drawLine(8, h - 16, w - 8, h - 16)
        p.drawText(QRectF(8, h - 15, 40, 14), Qt.AlignmentFlag.AlignLeft, "0°")
        p.drawText(QRectF(w / 2 - 20, h - 15, 40, 14), Qt.AlignmentFlag.AlignCenter, "45°")
        p.drawText(QRectF(w - 48, h - 15, 40, 14), Qt.AlignmentFlag.AlignRight, "90°")
        p.end()


def angle_text(summary: dict) -> str:
    return (
        f"{summary['n']} samples with a normal: median {summary['median_degrees']:.1f}°, "
        f"90 % under {summary['p90_degrees']:.1f}°, {summary['over_30_degrees']} over 30°"
        + (f"; {summary['missing']} without one" if summary.get("missing") else "")
        + "."
    )


class NormalAnglesPanel(QGroupBox):
    """Shown when the opened file has normals: their angles to AN_s, and a button to colour the samples by them."""

    color_requested = Signal()

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__("File normals against AN_s (angle per sample)", parent)
        self.model = model
        lay = QVBoxLayout(self)
        self.histogram = AngleHistogram(self)
        lay.addWidget(self.histogram)
        self.label = QLabel(self)
        self.label.setWordWrap(True)
        self.label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        lay.addWidget(self.label)
        self.color_button = QPushButton("Colour the samples by this angle", self)
        self.color_button.clicked.connect(self._color)
        lay.addWidget(self.color_button)
        self.summary: dict | None = None
        self.setVisible(False)
        model.reconstruction_changed.connect(self.refresh)

    def refresh(self, *_) -> None:
        rec = self.model.rec
        self.summary = angle_histogram(rec, self.model.file_attributes) if rec is not None else None
        if self.summary is None or not self.summary.get("n"):
            self.histogram.set_histogram(None)
            self.setVisible(False)
            return
        self.histogram.set_histogram(self.summary)
        self.label.setText(angle_text(self.summary))
        self.setVisible(True)

    def _color(self) -> None:
        layer = self.model.layers["points"]
        layer.visible = True
        layer.colorby = "file normal angle"
        self.color_requested.emit()
