"""Small dialogs: built-in sample chooser, dimension question, overwriting the input."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QFontMetrics, QGuiApplication
from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QInputDialog,
    QLabel,
    QLayout,
    QMessageBox,
    QSpinBox,
    QWidget,
)


class BuiltinDialog(QDialog):
    """Choose a built-in manifold, a sample size and a seed."""

    def __init__(self, parent: QWidget | None = None, current: str = "torus") -> None:
        super().__init__(parent)
        from ..core.samples.manifolds import MANIFOLDS

        self.manifolds = MANIFOLDS
        self.setWindowTitle("Open built-in sample")
        form = QFormLayout(self)
        self.name = QComboBox(self)
        for name, m in MANIFOLDS.items():
            self.name.addItem(f"{name}  (d = {m.d} in R^{m.k})", name)
        self.name.setToolTip("Closed manifolds of known topology, with their true tangent planes")
        form.addRow("manifold", self.name)
        self.description = QLabel(self)
        self.description.setWordWrap(True)
        self.description.setMinimumWidth(360)
        form.addRow(self.description)
        self.n = QSpinBox(self)
        self.n.setRange(10, 200_000)
        self.n.setSingleStep(100)
        self.n.setToolTip("Number of sample points (the default is dense enough for a correct reconstruction)")
        form.addRow("points", self.n)
        self.seed = QSpinBox(self)
        self.seed.setRange(0, 2**31 - 1)
        self.seed.setToolTip("Random seed of the sample")
        form.addRow("seed", self.seed)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel, self)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.name.currentIndexChanged.connect(self._changed)
        i = self.name.findData(current)
        self.name.setCurrentIndex(max(i, 0))
        self._changed()

    def _changed(self, *_) -> None:
        m = self.manifolds[self.name.currentData()]
        self.n.setValue(m.default_n)
        betti = ", ".join(map(str, m.betti))
        self.description.setText(
            f"{m.description}<br><small>Betti {betti}; χ = {m.euler}; "
            f"{'orientable' if m.orientable else 'non-orientable'}</small>"
        )

    def values(self) -> tuple[str, int, int]:
        return self.name.currentData(), self.n.value(), self.seed.value()


#: Widest the dimension question gets, as a share of the screen's width (a long file name is elided).
DIALOG_SCREEN_SHARE = 0.6


def dimension_dialog(parent: QWidget | None, k: int, default: int, source: str, why: str = "") -> QInputDialog:
    """The question for d, sized to its text: every line whole, inside the screen.

    A file name wider than the dialog may get is elided in the middle (whole in
    the tooltip); the suggestion's reasons wrap to the width of the other lines.
    """
    dlg = _FittedInputDialog(parent)
    dlg.setWindowTitle("Intrinsic dimension")
    dlg.setInputMode(QInputDialog.InputMode.IntInput)
    dlg.setIntRange(1, max(1, k - 1))
    dlg.setIntValue(default)
    fm = QFontMetrics(dlg.font())
    screen = (parent.screen() if parent is not None else None) or QGuiApplication.primaryScreen()
    widest = int(screen.availableGeometry().width() * DIALOG_SCREEN_SHARE) if screen is not None else 900
    head = [
        source,
        f"holds points in R^{k}. Dimension d of the manifold they sample",
        f"(1 = curve, 2 = surface …; suggested: {default}):",
    ]
    width = max(fm.horizontalAdvance(t) for t in head[1:])
    name = fm.elidedText(source, Qt.TextElideMode.ElideMiddle, min(widest, max(600, 2 * width)))
    head[0] = name
    lines = list(head)
    if why:  # wrapped to the width of the lines above, in pixels (not characters)
        line = ""
        for word in f"Suggested {why}".split():
            wider = f"{line} {word}".strip()
            if line and fm.horizontalAdvance(wider) > width:
                lines.append(line)
                line = word
            else:
                line = wider
        lines.append(line)
    dlg.setLabelText("\n".join(lines))
    dlg.setToolTip(source if name != source else "")
    label = dlg.findChild(QLabel)
    if label is not None:
        label.setWordWrap(False)
        label.setMinimumWidth(max(fm.horizontalAdvance(t) for t in lines) + 8)
    return dlg


class _FittedInputDialog(QInputDialog):
    """A QInputDialog exactly as big as its contents (its layout exists only once it is shown)."""

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        if self.layout() is not None:
            self.layout().setSizeConstraint(QLayout.SizeConstraint.SetFixedSize)
        super().showEvent(event)


def ask_dimension(parent: QWidget, k: int, default: int, source: str, why: str = "") -> int | None:
    """Ask for d (1 <= d < k), suggesting ``default`` (and saying ``why``); returns None when cancelled."""
    dlg = dimension_dialog(parent, k, default, source, why)
    ok = dlg.exec() == QDialog.DialogCode.Accepted
    d = dlg.intValue()
    dlg.deleteLater()
    return d if ok else None


def ask_overwrite_input(parent: QWidget, path: str) -> bool:
    """Ask before writing over the file the shown points were read from; True to go ahead."""
    answer = QMessageBox.question(
        parent,
        "Overwrite the input file?",
        f"{path}\nis the file these points were read from. Writing the result over it replaces the input.\n\n"
        "Overwrite it?",
        QMessageBox.StandardButton.Yes | QMessageBox.StandardButton.No,
        QMessageBox.StandardButton.No,
    )
    return answer == QMessageBox.StandardButton.Yes
