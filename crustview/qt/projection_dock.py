"""Projection panel: coordinates, PCA, plane rotations and the grand tour."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QGridLayout,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSlider,
    QStyle,
    QVBoxLayout,
    QWidget,
)

from ..scene.model import SceneModel
from .slice_panel import SlicePanel

#: At most this many plane sliders are shown (k <= 6 gets all of them).
MAX_PLANES = 15


class ProjectionPanel(QWidget):
    """Choose the k x 3 projection basis; shows the current basis."""

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        self.lay = QVBoxLayout(self)
        self.lay.setContentsMargins(6, 4, 6, 4)
        row = QHBoxLayout()
        self.coords = [QComboBox(self) for _ in range(3)]
        for axis, c in zip("XYZ", self.coords):
            c.setToolTip(f"Ambient coordinate shown as the view's {axis} axis")
            row.addWidget(QLabel(axis, self))
            row.addWidget(c)
        self.apply = QPushButton("Show", self)
        self.apply.setToolTip("Project onto the three chosen coordinates")
        row.addWidget(self.apply)
        self.lay.addLayout(row)
        row2 = QHBoxLayout()
        self.pca = QPushButton("PCA", self)
        self.pca.setToolTip("Project onto the three principal axes of the samples")
        self.tour = QPushButton("Grand tour", self)
        self.tour.setCheckable(True)
        self.tour.setIcon(self.style().standardIcon(QStyle.StandardPixmap.SP_MediaPlay))
        self.tour.setToolTip("Move smoothly between random projections of R^k (click again to pause)")
        self.tour_speed = QSlider(Qt.Orientation.Horizontal, self)
        self.tour_speed.setRange(1, 30)
        self.tour_speed.setValue(6)
        self.tour_speed.setToolTip("Speed of the grand tour")
        row2.addWidget(self.pca)
        row2.addWidget(self.tour)
        row2.addWidget(self.tour_speed)
        self.lay.addLayout(row2)
        self.stereo = QCheckBox("Stereographic view (k ≥ 4, data on a 3-sphere)", self)
        self.stereo.setToolTip(
            "Project the 3-sphere through the data from its point in the direction the view "
            "drops: the Clifford torus becomes a torus of revolution, S^3 fills R^3. "
            "Needs k >= 4."
        )
        self.stereo.toggled.connect(self._stereo)
        self.lay.addWidget(self.stereo)
        self.planes = QGridLayout()
        self.planes.setVerticalSpacing(0)
        self.lay.addLayout(self.planes)
        self.sliders: dict[tuple[int, int], QSlider] = {}
        self.readouts: dict[tuple[int, int], QLabel] = {}
        self.basis = QLabel(self)
        self.basis.setWordWrap(True)
        self.basis.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.basis.setToolTip("The current basis: each view axis as a combination of ambient coordinates")
        self.lay.addWidget(self.basis)
        self.slice = SlicePanel(model, self)
        self.lay.addWidget(self.slice)
        self.lay.addStretch(1)
        self.timer = QTimer(self)
        self.timer.setInterval(40)
        self.timer.timeout.connect(self._tick)
        self.apply.clicked.connect(self._coordinates)
        self.pca.clicked.connect(self._pca)
        self.tour.toggled.connect(self._toggle_tour)
        model.projection.changed.connect(self._show_basis)
        model.reconstruction_changed.connect(self.rebuild)
        model.tour.playing_changed.connect(self._tour_state)
        self._k = 0
        self.rebuild()

    def rebuild(self) -> None:
        """Re-create the controls for the current ambient dimension."""
        k = self.model.projection.k
        if k != self._k:
            self._k = k
            for j, c in enumerate(self.coords):
                c.blockSignals(True)
                c.clear()
                c.addItems([f"x{i + 1}" for i in range(k)])
                c.setCurrentIndex(min(j, k - 1))
                c.setEnabled(k >= 3)
                c.blockSignals(False)
            self.coords[2].setVisible(k >= 3)
            while self.planes.count():
                w = self.planes.takeAt(0).widget()
                if w is not None:
                    w.deleteLater()
            self.sliders = {}
            self.readouts = {}
            planes = [(i, j) for i in range(k) for j in range(i + 1, k)][:MAX_PLANES]
            if k >= 3:
                for r, (i, j) in enumerate(planes):
                    lab = QLabel(f"x{i + 1}–x{j + 1}", self)
                    s = QSlider(Qt.Orientation.Horizontal, self)
                    s.setRange(-180, 180)
                    s.setToolTip(f"Rotate the projection in the coordinate plane (x{i + 1}, x{j + 1}), degrees")
                    s.valueChanged.connect(lambda v, i=i, j=j: self.model.projection.set_angle(i, j, np.radians(v)))
                    readout = QLabel("0°", self)
                    readout.setMinimumWidth(readout.fontMetrics().horizontalAdvance("-180°") + 4)
                    readout.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                    self.planes.addWidget(lab, r, 0)
                    self.planes.addWidget(s, r, 1)
                    self.planes.addWidget(readout, r, 2)
                    self.sliders[(i, j)] = s
                    self.readouts[(i, j)] = readout
        for w in (self.apply, self.pca, self.tour, self.tour_speed):
            w.setEnabled(k >= 3)
        self.stereo.setEnabled(k >= 4)
        self.stereo.blockSignals(True)
        self.stereo.setChecked(self.model.projection.stereographic)
        self.stereo.blockSignals(False)
        self._show_basis()

    def _stereo(self, on: bool) -> None:
        rec = self.model.rec
        if rec is None or self.model.projection.k < 4:
            return
        p = self.model.projection
        r = float(np.median(np.linalg.norm(rec.points - p.origin, axis=1))) if on else 0.0
        p.set_stereographic(r)

    def _coordinates(self) -> None:
        idx = [c.currentIndex() for c in self.coords[: min(3, self._k)]]
        if len(set(idx)) != len(idx):
            self.basis.setText("<span style='color:#b00'>Choose three different coordinates.</span>")
            return
        self.model.tour.pause()
        self.model.projection.set_coordinates(*idx)

    def _pca(self) -> None:
        if self.model.rec is not None:
            self.model.tour.pause()
            self.model.projection.set_pca(self.model.rec.points)

    def _toggle_tour(self, on: bool) -> None:
        self.model.tour.play() if on else self.model.tour.pause()

    def _tour_state(self, playing: bool) -> None:
        self.tour.blockSignals(True)
        self.tour.setChecked(playing)
        # standard icons: the ⏸/▶ glyphs are missing from many fonts
        sp = QStyle.StandardPixmap.SP_MediaPause if playing else QStyle.StandardPixmap.SP_MediaPlay
        self.tour.setIcon(self.style().standardIcon(sp))
        self.tour.setText("Pause tour" if playing else "Grand tour")
        self.tour.blockSignals(False)
        self.timer.start() if playing else self.timer.stop()

    def _tick(self) -> None:
        self.model.tour.speed = self.tour_speed.value() / 15.0
        self.model.tour.advance(self.timer.interval() / 1000.0)

    def _show_basis(self) -> None:
        p = self.model.projection
        angles = p.angles
        for key, s in self.sliders.items():
            deg = float(np.degrees(angles.get(key, 0.0)))
            deg = (deg + 180.0) % 360.0 - 180.0
            s.blockSignals(True)
            s.setValue(int(round(deg)))
            s.blockSignals(False)
            self.readouts[key].setText(f"{deg:.0f}°")
        if p.flat:
            self.basis.setText("2-D data: shown flat in the plane z = 0.")
            return
        lab = p.axis_labels()
        hidden = ""
        if p.k >= 4:
            u = p.hidden
            terms = " + ".join(f"{c:.2f} x{i + 1}" for i, c in enumerate(u) if abs(c) > 0.005).replace("+ -", "- ")
            hidden = f"<br>hidden: {terms}" + (" (stereographic pole)" if p.stereographic else "")
        self.basis.setText(f"<b>basis</b> ({p.description})<br>X = {lab[0]}<br>Y = {lab[1]}<br>Z = {lab[2]}{hidden}")
