"""Controls of the slicing hyperplane: show the slice, move it, cut M_S to one side."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QCheckBox, QGridLayout, QGroupBox, QLabel, QSlider, QWidget

from ..scene.model import SceneModel

#: Slider steps across the data's extent along the slice normal.
STEPS = 200


class SlicePanel(QGroupBox):
    """The hyperplane orthogonal to the hidden direction, moved through the data by a slider."""

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__("Slice (hyperplane ⟂ the hidden direction)", parent)
        self.model = model
        grid = QGridLayout(self)
        grid.setContentsMargins(6, 4, 6, 4)
        self.show_slice = QCheckBox("Show the cross-section of M_S", self)
        self.show_slice.setToolTip(model.layers["slice"].tooltip)
        self.cut = QCheckBox("Cut M_S: keep the side below", self)
        self.cut.setToolTip("Draw only the simplices of M_S that lie wholly below the hyperplane (a half-space cut)")
        self.offset = QSlider(Qt.Orientation.Horizontal, self)
        self.offset.setRange(-STEPS // 2, STEPS // 2)
        self.offset.setToolTip("Move the hyperplane through the data")
        self.readout = QLabel("0", self)
        self.readout.setMinimumWidth(self.readout.fontMetrics().horizontalAdvance("-0.000") + 4)
        grid.addWidget(self.show_slice, 0, 0, 1, 2)
        grid.addWidget(self.cut, 1, 0, 1, 2)
        grid.addWidget(self.offset, 2, 0)
        grid.addWidget(self.readout, 2, 1)
        self.show_slice.toggled.connect(lambda on: setattr(model.layers["slice"], "visible", on))
        model.layers["slice"].events.visible.connect(self._sync)
        self.cut.toggled.connect(lambda on: model.set_slice(cut=on))
        self.offset.valueChanged.connect(self._moved)
        model.reconstruction_changed.connect(self._sync)
        self._sync()

    def extent(self) -> float:
        """Half the data's extent along the slice normal."""
        rec = self.model.rec
        if rec is None:
            return 1.0
        v = (rec.points - self.model.projection.origin) @ self.model.slice_normal()
        return float(max(np.abs(v).max(), 1e-12))

    def set_offset(self, offset: float) -> None:
        """Move the slider (and the hyperplane) to ``offset`` in data units."""
        self.offset.setValue(int(round(offset / self.extent() * (STEPS // 2))))

    def _moved(self, v: int) -> None:
        off = v / (STEPS // 2) * self.extent()
        self.readout.setText(f"{off:.3f}")
        self.model.set_slice(offset=off)

    def _sync(self, *_) -> None:
        """Widgets from the model: a new file's slice starts at 0, uncut (its label too)."""
        m = self.model
        for w in (self.show_slice, self.cut, self.offset):
            w.blockSignals(True)
        try:
            self.show_slice.setChecked(m.layers["slice"].visible)
            self.cut.setChecked(m.slice_cut)
            self.offset.setValue(int(round(m.slice_offset / self.extent() * (STEPS // 2))))
        finally:
            for w in (self.show_slice, self.cut, self.offset):
                w.blockSignals(False)
        self.readout.setText(f"{m.slice_offset:.3f}")
        self.cut.setEnabled(self.model.layers["slice"].visible)
        self.offset.setEnabled(self.model.rec is not None)
