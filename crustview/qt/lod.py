"""Stepping through Algorithm 3 on big samples: thinned frames while stepping, whole ones after."""

from __future__ import annotations

from PySide6.QtCore import QObject, QTimer

from ..render.view import SceneView
from ..scene.player import StepPlayer


class StepDetail(QObject):
    """Thins the big layers while the user steps or plays, and draws them whole once stepping pauses.

    A whole frame of a million-sample M_S takes over a second in software
    OpenGL; a thinned one (:mod:`crustview.render.lod`) a tenth of that.
    Each step restarts a :data:`IDLE_MS` timer; when it runs out, the view
    is drawn whole once.
    """

    #: Pause after the last step before the whole scene is drawn.
    IDLE_MS = 400

    def __init__(self, view: SceneView, player: StepPlayer, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.view = view
        self.timer = QTimer(self)
        self.timer.setSingleShot(True)
        self.timer.setInterval(self.IDLE_MS)
        self.timer.timeout.connect(view.end_lod)
        player.step_changed.connect(self._stepped)

    def _stepped(self, *_) -> None:
        if self.view.begin_lod():
            self.timer.start()
