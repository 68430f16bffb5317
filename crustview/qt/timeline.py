"""A timeline of the replay: |M_S|, boundary and non-manifold faces per step; a click jumps there."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRect, QSize, Qt
from PySide6.QtGui import QColor, QPainter, QPen, QPixmap, QPolygonF
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
        self.setToolTip(
            "|M_S| (amber), boundary faces (blue) and non-manifold faces (red) at every step, "
            "each scaled to its own maximum. Click or drag to go to a step."
        )
        self.setMouseTracking(False)
        #: The curves drawn once (for a size and a reconstruction); each step paints only the cursor.
        self._picture: QPixmap | None = None
        self._picture_key: tuple | None = None
        self._cursor_x: float | None = None
        model.player.step_changed.connect(self._moved)
        model.reconstruction_changed.connect(self._invalidate)

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

    def _invalidate(self, *_) -> None:
        self._picture = None
        self.update()

    def _moved(self, *_) -> None:
        """Repaint the strips under the old and the new cursor only."""
        new = self.x_of(self.model.player.position)
        old, self._cursor_x = self._cursor_x, new
        if old is None or self._picture is None:
            self.update()
            return
        top, height = self._plot_rect().top(), self._plot_rect().height() + 1
        for x in {int(old), int(new)}:
            self.update(QRect(x - 2, top, 5, height))

    def paintEvent(self, _event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        rec = self.model.rec
        key = (id(rec), self.model.player.n_steps, self.width(), self.height(), self.devicePixelRatioF())
        if self._picture is None or self._picture_key != key:
            ratio = self.devicePixelRatioF()
            self._picture = QPixmap(int(self.width() * ratio), int(self.height() * ratio))
            self._picture.setDevicePixelRatio(ratio)
            self._picture_key = key
            painter = QPainter(self._picture)
            self._paint_curves(painter)
            painter.end()
        p.drawPixmap(0, 0, self._picture)
        if rec is None or self.model.player.n_steps == 0:
            return
        r = self._plot_rect()
        cx = self.x_of(self.model.player.position)
        self._cursor_x = cx
        p.setPen(QPen(QColor("#222222"), 1.0, Qt.PenStyle.DashLine))
        p.drawLine(QPointF(cx, r.top()), QPointF(cx, r.bottom()))

    def _paint_curves(self, p: QPainter) -> None:
        """Background, frame, the three curves and their legend (everything but the cursor)."""
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
        for (field, _label, colour), text in zip(SERIES, self.legend_texts(), strict=True):
            y = column_max(np.asarray(getattr(tl, field)), len(x))
            top = max(float(y.max()), 1.0)
            ys = r.bottom() - (r.height() - 1) * y / top
            p.setPen(QPen(QColor(colour), 1.4))
            p.drawPolyline(QPolygonF([QPointF(a, b) for a, b in zip(x[: len(ys)], ys)]))
            p.drawText(legend_x, 11, text)
            legend_x += p.fontMetrics().horizontalAdvance(text) + 12

    def legend_texts(self) -> list[str]:
        """Each curve's legend: its name and its own largest value.

        A curve that stays at 0 says 0, though it is drawn on a scale of 1 ("≤ 1" was shown for none).
        """
        if self.model.rec is None or self.model.player.n_steps == 0:
            return []
        tl = self.model.timeline()
        return [f"{label} ≤ {int(np.max(getattr(tl, field))):,}" for field, label, _ in SERIES]
