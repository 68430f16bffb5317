"""Information-panel box listing the features of M_S the sample does not support; a click frames one."""

from __future__ import annotations

from html import escape

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QGroupBox, QLabel, QListWidget, QListWidgetItem, QVBoxLayout, QWidget

from ..scene.features import feature_words, uncertain_features, uncertain_summary
from ..scene.model import SceneModel


class FeaturesPanel(QGroupBox):
    """The "Uncertain features" box: how many of each kind, and one clickable line per feature.

    Hidden when the sample supports every feature.  Emits
    :attr:`feature_clicked` with the chosen ``Feature`` (the window frames it).
    """

    feature_clicked = Signal(object)

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__("Uncertain features (not supported by the sample)", parent)
        self.model = model
        self.setStyleSheet("QGroupBox { color: #7a4b00; font-weight: bold; }")
        lay = QVBoxLayout(self)
        self.summary = QLabel(self)
        self.summary.setWordWrap(True)
        self.summary.setStyleSheet("QLabel { font-weight: normal; color: #5a3d00; }")
        lay.addWidget(self.summary)
        self.list = QListWidget(self)
        self.list.setMinimumHeight(70)
        self.list.setStyleSheet("QListWidget { font-weight: normal; }")
        self.list.setWordWrap(True)  # a reason is a sentence: wrapped, never cut at the dock's edge
        self.list.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.list.setToolTip("Click a feature: the view frames it (the Uncertain features layer draws them all)")
        # a click or Enter only: the list taking focus must not move the camera
        self.list.itemClicked.connect(self._clicked)
        self.list.itemActivated.connect(self._clicked)
        lay.addWidget(self.list)
        self.features: list = []
        self.setVisible(False)
        model.reconstruction_changed.connect(self.refresh)

    def refresh(self) -> None:
        self.features = uncertain_features(self.model.rec)
        self.list.clear()
        self.setVisible(bool(self.features))
        if not self.features:
            self.summary.setText("")
            return
        handles = ""
        if any(f.kind == "handle" for f in self.features):
            handles = (
                " A handle is counted by its loops: one handle of a surface has two (b1 = 2 g)."
                if self.model.rec.d == 2
                else " A handle here is one unit of b1, an independent loop of M_S (disputed: a difference in b1)."
            )
        self.summary.setText(
            escape(uncertain_summary(self.features))
            + ": each is below what the sample can resolve, so M_S may be wrong there (a false bridge, "
            "a missing piece, a gap taken for a hole). Click one to frame it." + handles
        )
        quality = self.model.known_quality()  # the estimated epsilon where each is, when already computed
        for i, f in enumerate(self.features):
            words = feature_words(f, i, quality)
            item = QListWidgetItem(words)
            item.setToolTip(escape(words))
            self.list.addItem(item)

    def _clicked(self, item) -> None:
        row = self.list.row(item)
        if 0 <= row < len(self.features):
            self.feature_clicked.emit(self.features[row])
