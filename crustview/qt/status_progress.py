"""A copy of the Run panel's progress bar in the status bar, with Cancel, while a job runs.

In a window whose docks share one tabbed column the Run panel is usually a
tab behind Steps or Information, so its bar is not in sight when a file is
opened; this one is, whatever tab is in front.
"""

from __future__ import annotations

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QHBoxLayout, QProgressBar, QToolButton, QWidget

from .run_dock import RunPanel

#: Width (px) of the status bar's progress bar.
BAR_WIDTH = 300


class StatusProgress(QWidget):
    """Follows ``panel.progress`` (range, value, text); shown only while ``panel`` is busy."""

    def __init__(self, panel: RunPanel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.panel = panel
        lay = QHBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        lay.setSpacing(4)
        self.bar = QProgressBar(self)
        self.bar.setFixedWidth(BAR_WIDTH)
        self.bar.setTextVisible(True)
        lay.addWidget(self.bar)
        self.cancel = QToolButton(self)
        self.cancel.setText("Cancel")
        self.cancel.setToolTip("Stop the running reconstruction; the previous result stays")
        self.cancel.clicked.connect(panel.cancel_requested)
        lay.addWidget(self.cancel)
        panel.progress_shown.connect(self.follow)
        self.setVisible(False)

    def follow(self) -> None:
        """Copy the panel's bar; visible while a job runs (its Cancel pressed or not)."""
        src = self.panel.progress
        self.bar.setRange(src.minimum(), src.maximum())
        self.bar.setValue(src.value())
        self.bar.setFormat(src.format())
        self.bar.setToolTip(src.format())
        self.cancel.setEnabled(not self.panel.cancelling)
        if self.panel.busy != self.isVisible():
            # at the next turn of the event loop: showing it lays the window out again, which must
            # not happen inside the call that starts the job (nor once per progress report)
            QTimer.singleShot(0, self._show_if_busy)

    def _show_if_busy(self) -> None:
        self.setVisible(self.panel.busy)
