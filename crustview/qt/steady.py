"""Widgets whose size never follows their text, so updating them never re-lays out the window."""

from __future__ import annotations

import re

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLabel, QLineEdit, QWidget

_DIGIT = re.compile(r"\d")


class SteadyLabel(QLabel):
    """A one-line label of fixed size that only ever grows, to fit its widest text so far.

    A plain QLabel asks its parent's layout to be redone on every new text
    (``updateGeometry``); in a dock that reaches the main window, whose
    re-layout repaints and re-composites the whole window: a second, third
    and fourth frame after every step of the replay.  A widget of fixed
    size does not ask.  Digits are measured as the widest digit, so counts
    that change from step to step keep the size they have.
    """

    def setText(self, text: str) -> None:  # noqa: N802 - Qt API
        if text == self.text():
            return
        fm = self.fontMetrics()
        margins = self.contentsMargins()
        width = fm.horizontalAdvance(_DIGIT.sub("8", text)) + margins.left() + margins.right() + 2 * self.margin() + 6
        height = max(fm.height() + margins.top() + margins.bottom() + 2 * self.margin(), self.minimumHeight())
        if width > self.width() or height != self.height() or self.minimumWidth() != self.maximumWidth():
            self.setFixedSize(max(width, self.width() if self.minimumWidth() == self.maximumWidth() else 0), height)
        super().setText(text)


class SteadyText(QLineEdit):
    """Read-only text that looks like a label and never re-lays out its parent.

    A QLineEdit's size does not depend on its text, so setting a new one
    repaints this widget only.  Text wider than the widget scrolls (the
    whole of it is in the tooltip).
    """

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setReadOnly(True)
        self.setFrame(False)
        self.setFocusPolicy(Qt.FocusPolicy.NoFocus)
        self.setStyleSheet("QLineEdit { background: transparent; }")

    def setText(self, text: str) -> None:  # noqa: N802 - Qt API
        if text != self.text():
            super().setText(text)
            self.setCursorPosition(0)
            self.setToolTip(text)
