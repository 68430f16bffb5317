"""Small dialogs: built-in sample chooser, dimension question, overwriting the input."""

from __future__ import annotations

import textwrap

from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QInputDialog,
    QLabel,
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


def ask_dimension(parent: QWidget, k: int, default: int, source: str, why: str = "") -> int | None:
    """Ask for d (1 <= d < k), suggesting ``default`` (and saying ``why``); returns None when cancelled."""
    reason = "\n".join(textwrap.wrap(f"Suggested {why}", 70)) + "\n" if why else ""
    d, ok = QInputDialog.getInt(
        parent,
        "Intrinsic dimension",
        f"{source}\nholds points in R^{k}. Dimension d of the manifold they sample\n"
        f"(1 = curve, 2 = surface …; suggested from local PCA: {default}):\n{reason}",
        default,
        1,
        max(1, k - 1),
    )
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
