"""Compare the shown M_S with a saved result, a mesh's faces or another run: dialog and Information box.

The work (reading B, re-running Algorithm 3, the simplex-by-simplex diff)
runs in a worker thread of the box's own (:class:`~crustview.qt.worker.Runner`);
the result goes to :meth:`SceneModel.set_comparison`, which the comparison
layer draws.
"""

from __future__ import annotations

import math
from html import escape

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QButtonGroup,
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QProgressBar,
    QPushButton,
    QRadioButton,
    QScrollArea,
    QVBoxLayout,
    QWidget,
)

from ..core.result import CANDIDATE_TESTS
from ..scene.comparison import comparison_job
from ..scene.describe import fmt_tuple
from ..scene.model import SceneModel
from .worker import Runner

#: At most this many differing simplices are listed.
MAX_LISTED = 500

_WHAT = {
    "result": "a saved result (.npz): its M_S",
    "mesh": "a mesh file: its faces",
    "run": "M_S under another test, θ or extraction",
}


class CompareDialog(QDialog):
    """Choose B: a saved result, a mesh file or another run of Algorithm 3."""

    def __init__(
        self,
        parent: QWidget | None = None,
        test: str = "cocone",
        theta: float = math.pi / 8,
        mode: str = "robust",
        folder: str = "",
    ) -> None:
        super().__init__(parent)
        self.setWindowTitle("Compare M_S with…")
        self.folder = folder
        form = QFormLayout(self)
        self.kinds = QButtonGroup(self)
        self.radio: dict[str, QRadioButton] = {}
        for key, text in _WHAT.items():
            b = QRadioButton(text, self)
            self.radio[key] = b
            self.kinds.addButton(b)
            form.addRow(b)
        self.path = QLineEdit(self)
        self.path.setPlaceholderText("file to compare with")
        browse = QPushButton("Browse…", self)
        browse.clicked.connect(self._browse)
        row = QHBoxLayout()
        row.addWidget(self.path, 1)
        row.addWidget(browse)
        form.addRow("file", row)
        self.test = QComboBox(self)
        self.test.addItems(list(CANDIDATE_TESTS))
        self.test.setCurrentText(test)
        form.addRow("test", self.test)
        self.theta = QDoubleSpinBox(self)
        self.theta.setRange(0.5, 89.5)
        self.theta.setSingleStep(0.5)
        self.theta.setDecimals(1)
        self.theta.setSuffix("°")
        self.theta.setValue(math.degrees(theta))
        form.addRow("θ", self.theta)
        self.mode = QComboBox(self)
        self.mode.addItem("robust", "robust")
        self.mode.addItem("the paper's Algorithm 3", "paper")
        self.mode.setCurrentIndex(max(0, self.mode.findData(mode)))
        form.addRow("extraction", self.mode)
        self.buttons = QDialogButtonBox(
            QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel, self
        )
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        #: Says why OK waits: B would be the shown run itself.
        self.same = QLabel("B is the shown run: change the test, θ or extraction.", self)
        self.same.setStyleSheet("color: #9a5800;")
        form.addRow(self.same)
        form.addRow(self.buttons)
        self._shown = (test, round(math.degrees(theta), 1), mode)
        for b in self.radio.values():
            b.toggled.connect(self._changed)
        self.path.textChanged.connect(self._changed)
        self.test.currentTextChanged.connect(self._changed)
        self.theta.valueChanged.connect(self._changed)
        self.mode.currentIndexChanged.connect(self._changed)
        self.radio["run"].setChecked(True)

    @property
    def kind(self) -> str:
        return next(k for k, b in self.radio.items() if b.isChecked())

    def _changed(self, *_) -> None:
        run = self.kind == "run"
        self.path.setEnabled(not run)
        for w in (self.test, self.theta, self.mode):
            w.setEnabled(run)
        ok = self.buttons.button(QDialogButtonBox.StandardButton.Ok)
        # comparing the shown run with itself finds nothing: OK waits for a change
        same = run and (self.test.currentText(), round(self.theta.value(), 1), self.mode.currentData()) == self._shown
        self.same.setVisible(same)
        ok.setEnabled((run and not same) or (not run and bool(self.path.text().strip())))

    def _browse(self) -> None:
        pattern = (
            "Saved results (*.npz)"
            if self.kind == "result"
            else "Meshes (*.off *.noff *.ply *.obj *.vtk *.stl);;All files (*)"
        )
        path, _ = QFileDialog.getOpenFileName(self, "Compare with", self.folder, pattern)
        if path:
            self.path.setText(path)

    def spec(self) -> dict:
        """What :func:`~crustview.scene.comparison.comparison_job` takes."""
        if self.kind == "run":
            return {
                "kind": "run",
                "test": self.test.currentText(),
                "theta": math.radians(self.theta.value()),
                "mode": self.mode.currentData(),
            }
        return {"kind": self.kind, "path": self.path.text().strip()}


class ComparePanel(QGroupBox):
    """The Information box: a button, progress with Cancel, the counts and the differing simplices.

    Emits :attr:`simplex_clicked` with the vertices of a listed simplex (the window frames it).
    """

    simplex_clicked = Signal(object)

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__("Compare M_S (A) with another complex (B)", parent)
        self.model = model
        lay = QVBoxLayout(self)
        row = QHBoxLayout()
        self.button = QPushButton("Compare with…", self)
        self.button.setToolTip("A saved result, a mesh file's faces, or M_S under another test, θ or extraction")
        self.button.clicked.connect(self.ask)
        row.addWidget(self.button)
        self.progress = QProgressBar(self)
        self.progress.setRange(0, 100)
        self.progress.setVisible(False)
        row.addWidget(self.progress, 1)
        self.cancel = QPushButton("Cancel", self)
        self.cancel.setVisible(False)
        row.addWidget(self.cancel)
        self.clear = QPushButton("Clear", self)
        self.clear.setToolTip("Drop the comparison layer")
        self.clear.clicked.connect(lambda: self.model.set_comparison(None))
        row.addWidget(self.clear)
        lay.addLayout(row)
        self.label = QLabel("No comparison yet.", self)
        self.label.setWordWrap(True)
        self.label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        lay.addWidget(self.label)
        self.list = QListWidget(self)
        self.list.setMinimumHeight(80)
        self.list.setToolTip("Simplices in only one of A and B; click one to frame it")
        self.list.itemClicked.connect(self._item)
        self.list.itemActivated.connect(self._item)
        lay.addWidget(self.list)
        self.runner = Runner(self)
        self.runner.progress.connect(
            lambda stage, f: (self.progress.setValue(int(100 * f)), self.progress.setFormat(f"{stage} %p%"))
        )
        self.runner.done.connect(self._done)
        self.runner.failed.connect(lambda msg: self._ended(f"The comparison failed: {escape(msg)}"))
        self.runner.cancelled.connect(lambda: self._ended("Comparison cancelled."))
        self.cancel.clicked.connect(self.runner.cancel)
        model.comparison_changed.connect(self.refresh)
        model.reconstruction_changed.connect(self.refresh)
        self.refresh()

    def ask(self) -> None:
        """Open the dialog; on OK, start the comparison."""
        rec = self.model.rec
        if rec is None:
            return
        dlg = CompareDialog(self, rec.test, float(rec.theta), rec.mode)
        if dlg.exec():
            self.start(dlg.spec())

    def start(self, spec: dict) -> bool:
        """Compare the shown M_S with ``spec`` (see :func:`comparison_job`) in the worker."""
        if self.runner.busy or self.model.rec is None:
            return False
        self.runner.start(comparison_job(self.model.rec, spec), "Comparing…")
        self.button.setEnabled(False)
        self.progress.setValue(0)
        for w in (self.progress, self.cancel):
            w.setVisible(True)
        self.label.setText("Comparing…")
        return True

    def _done(self, comparison) -> None:
        self._idle()
        if not self.model.set_comparison(comparison):
            self.refresh()
            self.label.setText("The result changed while comparing; compare again.")
            return
        self.bring_into_view()

    def bring_into_view(self) -> None:
        """Scroll the Information panel to this box (a comparison just made is read here)."""
        area = self.parentWidget()
        while area is not None and not isinstance(area, QScrollArea):
            area = area.parentWidget()
        if area is not None:
            area.ensureWidgetVisible(self, 0, 0)

    def _ended(self, text: str) -> None:
        self._idle()
        self.refresh()
        self.label.setText(text)

    def _idle(self) -> None:
        for w in (self.progress, self.cancel):
            w.setVisible(False)
        self.button.setEnabled(self.model.rec is not None)

    def refresh(self, *_) -> None:
        c = self.model.comparison
        self.button.setEnabled(self.model.rec is not None and not self.runner.busy)
        self.clear.setEnabled(c is not None)
        self.list.clear()
        if c is None:
            self.label.setText("No comparison yet." if self.model.rec is not None else "")
            return
        d = c.diff
        ta, tb = d.topology_a, d.topology_b
        self.label.setText(
            f"<b>A</b> = {escape(c.label_a)}: {ta.n_simplices:,} simplices, Betti {fmt_tuple(ta.betti)}<br>"
            f"<b>B</b> = {escape(c.label_b)}: {tb.n_simplices:,} simplices, Betti {fmt_tuple(tb.betti)}<br>"
            + escape(c.summary())
        )
        rows = c.differing()
        half = MAX_LISTED // 2  # both sides get listed
        shown = [x for x in rows if x[0] == "A"][:half] + [x for x in rows if x[0] == "B"][:half]
        for side, r in shown:
            item = QListWidgetItem(f"only in {side}: {fmt_tuple(r)}")
            item.setData(Qt.ItemDataRole.UserRole, tuple(int(v) for v in r))
            item.setForeground(Qt.GlobalColor.darkRed if side == "A" else Qt.GlobalColor.darkBlue)
            self.list.addItem(item)
        if len(rows) > len(shown):
            self.list.addItem(f"… and {len(rows) - len(shown):,} more (the first {half} of each side are listed)")

    def _item(self, item) -> None:
        v = item.data(Qt.ItemDataRole.UserRole) if item is not None else None
        if v is not None:
            self.simplex_clicked.emit(np.asarray(v, dtype=np.int64))
