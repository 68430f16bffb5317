"""Layer panel: visibility, colour, opacity, size and counts of every layer."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QCheckBox,
    QColorDialog,
    QComboBox,
    QDoubleSpinBox,
    QGridLayout,
    QLabel,
    QScrollArea,
    QSlider,
    QToolButton,
    QWidget,
)

from ..scene.layers import POLE_MODES, Layer

#: Order of the rows in the panel.
ORDER = (
    "points",
    "manifold",
    "slice",
    "step",
    "removed",
    "holes",
    "cascade",
    "uncertain",
    "orientation",
    "candidates",
    "normals",
    "poles",
    "voronoi",
    "selection",
    "compare",
    "truth",
)


#: The count column's tooltip, and where a layer's count is not of its drawn elements.
COUNT_TIP = "Number of elements in the layer at the current step"
COUNT_TIPS = {"holes": "Number of holes of T_S (each drawn as its rim of faces on one simplex only)"}
#: Widths (px) of the opacity slider, the size box and an option menu in a narrow dock.
COMPACT_SLIDER, COMPACT_SIZE, COMPACT_OPTION = 36, 46, 78


def _swatch(button: QToolButton, color: str) -> None:
    button.setStyleSheet(f"QToolButton {{ background: {color}; border: 1px solid #555; border-radius: 3px; }}")


class LayerRow:
    """The widgets of one layer, bound both ways to the :class:`Layer`."""

    def __init__(self, layer: Layer, grid: QGridLayout, row: int, parent: QWidget) -> None:
        self.layer = layer
        self.visible = QCheckBox(layer.title, parent)
        self.visible.setChecked(layer.visible)
        self.visible.setToolTip(layer.tooltip)
        self.visible.toggled.connect(lambda v: setattr(layer, "visible", bool(v)))
        self.count = QLabel(parent)
        self.count.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
        self.count.setToolTip(COUNT_TIP)
        self.color = QToolButton(parent)
        self.color.setFixedSize(22, 18)
        self.color.setToolTip("Colour (used when no scalar colouring is active)")
        self.color.clicked.connect(self._pick_color)
        self.opacity = QSlider(Qt.Orientation.Horizontal, parent)
        self.opacity.setRange(0, 100)
        self.opacity.setFixedWidth(48)
        self.opacity.setToolTip("Opacity")
        self.opacity.valueChanged.connect(lambda v: setattr(layer, "opacity", v / 100.0))
        self.size = QDoubleSpinBox(parent)
        self.size.setRange(0.0, 40.0)
        self.size.setSingleStep(0.5)
        self.size.setDecimals(1)
        self.size.setFixedWidth(52)
        self.size.setToolTip("Point size / line width in pixels (normal planes: glyph scale)")
        self.size.valueChanged.connect(lambda v: setattr(layer, "size", float(v)))
        for col, w in enumerate((self.visible, self.count, self.color, self.opacity, self.size)):
            grid.addWidget(w, row, col)
        self.extra: QWidget | None = None
        #: Narrow widgets for the tabbed column (:meth:`compact`).
        self.compacted = False
        if layer.colorings:
            combo = QComboBox(parent)
            combo.addItems(list(layer.colorings))
            combo.setToolTip("Scalar colouring of the layer (a legend bar appears in the view)")
            combo.currentTextChanged.connect(lambda t: setattr(layer, "colorby", t))
            combo.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToContents)
            combo.setFixedWidth(max(92, combo.sizeHint().width()))  # "normal error" fits
            combo.view().setMinimumWidth(combo.view().sizeHintForColumn(0) + 12)
            self.extra = combo
        elif layer.name == "poles":
            combo = QComboBox(parent)
            combo.addItems(list(POLE_MODES))
            combo.setToolTip("Poles of the selected sample only, or of every sample")
            combo.currentTextChanged.connect(lambda t: setattr(layer, "mode", t))
            combo.setFixedWidth(92)
            self.extra = combo
        elif layer.name in ("manifold", "removed"):
            spin = QDoubleSpinBox(parent)
            spin.setRange(0.3, 1.0)
            spin.setSingleStep(0.05)
            spin.setFixedWidth(56)
            spin.setToolTip("Shrink simplices towards their centroids (separates overlapping d-simplices, d >= 3)")
            spin.valueChanged.connect(lambda v: setattr(layer, "shrink", float(v)))
            self.extra = spin
        if self.extra is not None:
            grid.addWidget(self.extra, row, 5)
        if isinstance(self.extra, QComboBox):
            self.extra.currentTextChanged.connect(self._tip)
            self._tip(self.extra.currentText())
        layer.events.connect(self.sync)
        self.sync()

    def offer(self, items: tuple[str, ...]) -> None:
        """Rebuild the colouring menu with ``items`` (those that apply to the shown data)."""
        combo = self.extra
        if not isinstance(combo, QComboBox) or not self.layer.colorings:
            return
        if tuple(combo.itemText(i) for i in range(combo.count())) == tuple(items):
            return
        combo.blockSignals(True)
        combo.clear()
        combo.addItems(list(items))
        combo.blockSignals(False)
        self.sync()

    def _tip(self, text: str) -> None:
        """The option's whole value in its tooltip (a narrow panel elides it)."""
        what = "Scalar colouring of the layer (a legend bar appears in the view)"
        if self.layer.name == "poles":
            what = "Poles of the selected sample only, or of every sample"
        self.extra.setToolTip(f"<b>{text}</b><br>{what}")

    def compact(self) -> None:
        """Narrow widgets for a narrow dock: options elided (whole in their tooltips), a shorter slider."""
        self.compacted = True
        self.opacity.setFixedWidth(COMPACT_SLIDER)
        self.size.setFixedWidth(COMPACT_SIZE)
        if isinstance(self.extra, QComboBox):
            self.extra.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
            self.extra.setMinimumContentsLength(4)
            self.extra.setFixedWidth(COMPACT_OPTION)

    def _pick_color(self) -> None:
        c = QColorDialog.getColor(QColor(self.layer.color), self.color, f"Colour of {self.layer.title}")
        if c.isValid():
            self.layer.color = c.name()

    def sync(self, *_) -> None:
        """Model -> widgets (without echoing back)."""
        layer = self.layer
        widgets = [self.visible, self.opacity, self.size] + ([self.extra] if self.extra else [])
        for w in widgets:
            w.blockSignals(True)
        try:
            self.visible.setChecked(layer.visible)
            self.opacity.setValue(round(layer.opacity * 100))
            self.size.setValue(layer.size)
            _swatch(self.color, layer.color)
            thinned = layer.total > layer.count
            if layer.stale:  # hidden since an earlier step: its count would be of that step
                self.count.setText("–")
                self.count.setToolTip("Hidden: counted again when shown")
            else:
                # in a narrow dock, drawn of total on two lines: the column stays as narrow as a count
                sep = "\n" if self.compacted else " "
                self.count.setText(f"{layer.count:,}{sep}of {layer.total:,}" if thinned else f"{layer.count:,}")
                self.count.setToolTip(layer.note if thinned else COUNT_TIPS.get(layer.name, COUNT_TIP))
            if isinstance(self.extra, QComboBox):
                value = layer.colorby if layer.colorings else layer.mode
                i = self.extra.findText(value)
                if i >= 0:
                    self.extra.setCurrentIndex(i)
                self._tip(self.extra.currentText())
            elif isinstance(self.extra, QDoubleSpinBox):
                self.extra.setValue(layer.shrink)
        finally:
            for w in widgets:
                w.blockSignals(False)


class LayersPanel(QScrollArea):
    """All layers of a model, one row each."""

    def __init__(self, layers: dict[str, Layer], parent: QWidget | None = None) -> None:
        super().__init__(parent)
        body = QWidget(self)
        grid = QGridLayout(body)
        grid.setContentsMargins(6, 4, 6, 4)
        grid.setHorizontalSpacing(4)
        grid.setVerticalSpacing(2)
        for col, text in enumerate(("layer", "count", "", "opacity", "size", "option")):
            lab = QLabel(f"<small><i>{text}</i></small>", body)
            if text == "option":
                lab.setToolTip("Scalar colouring (samples, candidates), which poles, or the shrink factor")
            grid.addWidget(lab, 0, col)
        names = [n for n in ORDER if n in layers] + [n for n in layers if n not in ORDER]
        self.rows = {n: LayerRow(layers[n], grid, r + 1, body) for r, n in enumerate(names)}
        grid.setRowStretch(len(names) + 1, 1)
        self.setWidget(body)
        self.setWidgetResizable(True)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setMinimumWidth(body.sizeHint().width() + self.verticalScrollBar().sizeHint().width() + 4)

    def compact(self) -> None:
        """Fit a narrow dock (the tabbed column of a small window) without scrolling sideways."""
        for row in self.rows.values():
            row.compact()
            row.sync()
        grid = self.widget().layout()
        grid.setContentsMargins(3, 4, 3, 4)
        grid.setHorizontalSpacing(3)
        self.setMinimumWidth(0)
        # a width it still cannot fit (a window narrower than 1024 px) scrolls rather than clips
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAsNeeded)

    def offer(self, model) -> None:
        """Menus that fit the shown data: each row's colourings from :meth:`SceneModel.colorings`."""
        for name, row in self.rows.items():
            row.offer(model.colorings(name))
