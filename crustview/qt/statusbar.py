"""A status bar whose message ends in an ellipsis where the permanent widgets begin."""

from __future__ import annotations

import time

from PySide6.QtCore import QEvent, QObject, Qt, QTimer
from PySide6.QtWidgets import QStatusBar, QWidget

#: Pixels kept between an elided message and the first permanent widget.
GAP = 12


class ElidingStatusBar(QStatusBar):
    """A QStatusBar that elides its message to the room left of its permanent widgets.

    QStatusBar draws a message across its whole width and the permanent widgets
    over it, so a long one ran into them (a new user read "…; 80 stn = 20494 ·
    candidates" at 1024 pixels).  Here the message ends in "…" before the first
    of them, is elided again at every resize, and its whole text is the
    tooltip and what :meth:`currentMessage` returns.
    """

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._full = ""
        self._shown = ""  # the elided text handed to Qt (a status tip bypasses showMessage: not ours then)
        self._until: float | None = None  # when a timed message goes (time.monotonic)
        self.messageChanged.connect(lambda _text: self.setToolTip(self.currentMessage()))

    def showMessage(self, text: str, timeout: int = 0) -> None:  # noqa: N802 - Qt API
        self._full = str(text)
        self._until = time.monotonic() + timeout / 1000.0 if timeout > 0 else None
        self._shown = self._elided(self._full)
        super().showMessage(self._shown, timeout)
        self.setToolTip(self._full)

    def currentMessage(self) -> str:  # noqa: N802 - Qt API
        """The whole of the shown message ("" when none is; a menu's status tip as Qt shows it)."""
        shown = super().currentMessage()
        return self._full if shown and shown == self._shown else shown

    def addPermanentWidget(self, widget: QWidget, stretch: int = 0) -> None:  # noqa: N802 - Qt API
        """Add ``widget``; the message is elided again whenever it shows, hides or changes size."""
        super().addPermanentWidget(widget, stretch)
        widget.installEventFilter(self)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt API
        if event.type() in (QEvent.Type.Show, QEvent.Type.Hide, QEvent.Type.Resize):
            QTimer.singleShot(0, self._reelide)  # once the layout has placed it
        return False

    def resizeEvent(self, event) -> None:  # noqa: N802, ANN001 - Qt API
        super().resizeEvent(event)
        self._reelide()

    def _reelide(self) -> None:
        """The shown message elided again to the room there is now (a status tip of Qt's is left alone)."""
        if not super().currentMessage() or super().currentMessage() != self._shown:
            return
        left = 0 if self._until is None else max(1, int(1000 * (self._until - time.monotonic())))
        self._shown = self._elided(self._full)
        super().showMessage(self._shown, left)

    def room(self) -> int:
        """Pixels left of the first shown permanent widget (the whole width when none is)."""
        lefts = [
            w.geometry().left()
            for w in self.findChildren(QWidget, options=Qt.FindChildOption.FindDirectChildrenOnly)
            if w.isVisible() and w.geometry().left() > 0
        ]
        return (min(lefts) if lefts else self.width()) - GAP

    def _elided(self, text: str) -> str:
        return self.fontMetrics().elidedText(text, Qt.TextElideMode.ElideRight, max(self.room(), 40))
