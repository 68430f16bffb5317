"""A timeline of the replay: |M_S|, boundary and non-manifold faces per step; a click jumps there."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QSize, Qt
from PySide6.QtGui import QColor, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QSizePolicy, QWidget

from ..scene.model import SceneModel

#: (Timeline field, label, colour) of each curve.
SERIES = (
    ("size", "|M_S|", "#b7791f"),
    ("boundary", "boundary faces", "#1f5fd6"),
    ("nonmanifold", "non-manifold faces", "#c0392b"),
)


def column_max(values: np.ndarray, columns: int) -> np.ndarray:
    """The largest value in each of ``columns`` consecutive bins of ``values``."""
    n = len(values)
    if n <= columns:
        return values.astype(float)
    edges = np.linspace(0, n, columns + 1).astype(np.int64)[:-1]
    return np.maximum.reduceat(values, edges).astype(float)


class TimelineView(QWidget):
    """Three curves over the step positions 0..n; each scaled to its own maximum (named in the legend).

    A click or drag sets the player's position; a vertical line marks the current one.
    """

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        self.setMinimumHeight(64)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.setToolTip("|M_S| (amber), boundary faces (blue) and non-manifold faces (red) at every step, "
                        "each scaled to its own maximum. Click or drag to go to a step.")
        self.setMouseTracking(False)
        model.player.step_changed.connect(lambda *_: self.update())
        model.reconstruction_changed.connect(lambda *_: self.update())

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt API
        return QSize(300, 72)

    # -- geometry ---------------------------------------------------------------
    def _plot_rect(self):
        return self.rect().adjusted(4, 14, -4, -3)

    def position_at(self, x: float) -> int:
        """Step position under widget x coordinate ``x``."""
        n = self.model.player.n_steps
        r = self._plot_rect()
        if n == 0 or r.width() <= 1:
            return 0
        return int(round(np.clip((x - r.left()) / (r.width() - 1), 0.0, 1.0) * n))

    def x_of(self, position: int) -> float:
        n = max(self.model.player.n_steps, 1)
        r = self._plot_rect()
        return r.left() + (r.width() - 1) * position / n

    # -- events -------------------------------------------------------------------
    def mousePressEvent(self, event) -> None:  # noqa: N802 - Qt API
        if event.button() == Qt.MouseButton.LeftButton:
            self.model.player.set_step(self.position_at(event.position().x()))

    def mouseMoveEvent(self, event) -> None:  # noqa: N802 - Qt API
        if event.buttons() & Qt.MouseButton.LeftButton:
            self.model.player.set_step(self.position_at(event.position().x()))

    def paintEvent(self, _event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        font = p.font()
        font.setPixelSize(10)
        p.setFont(font)
        p.fillRect(self.rect(), QColor("#fbfbf8"))
        p.setPen(QColor("#cccccc"))
        p.drawRect(self.rect().adjusted(0, 0, -1, -1))
        if self.model.rec is None or self.model.player.n_steps == 0:
            p.setPen(QColor("#777777"))
            p.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, "timeline: no steps")
            return
        tl = self.model.timeline()
        r = self._plot_rect()
        cols = max(2, r.width())
        x = np.linspace(r.left(), r.right(), min(cols, tl.n_steps + 1))
        legend_x = 6
        p.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for field, label, colour in SERIES:
            y = column_max(np.asarray(getattr(tl, field)), len(x))
            top = max(float(y.max()), 1.0)
            ys = r.bottom() - (r.height() - 1) * y / top
            p.setPen(QPen(QColor(colour), 1.4))
            p.drawPolyline(QPolygonF([QPointF(a, b) for a, b in zip(x[: len(ys)], ys)]))
            text = f"{label} ≤ {int(top):,}"
            p.drawText(legend_x, 11, text)
            legend_x += p.fontMetrics().horizontalAdvance(text) + 12
        cx = self.x_of(self.model.player.position)
        p.setPen(QPen(QColor("#222222"), 1.0, Qt.PenStyle.DashLine))
        p.drawLine(QPointF(cx, r.top()), QPointF(cx, r.bottom()))
