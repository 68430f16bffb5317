"""Information panel: topology vs expectation, timings, selection, open faces."""

from __future__ import annotations

from html import escape

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtWidgets import (
    QFrame,
    QGroupBox,
    QHeaderView,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QPushButton,
    QScrollArea,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from ..scene.describe import fmt_tuple, interpretation_rows, topology_rows, verdict
from ..scene.inspector_text import face_text, sample_text, simplex_text
from ..scene.model import SceneModel
from .compare_panel import ComparePanel
from .diagnosis import DiagnosisPanel
from .features_panel import FeaturesPanel
from .normal_angles_panel import NormalAnglesPanel
from .steady import SteadyText
from .theorems_panel import TheoremPanel

#: At most this many open faces are listed.
MAX_FACES = 300
#: Height of the selection text in lines (longer text scrolls).
SELECTION_LINES = 9

#: Style of the verdict banner by level.
BANNER_STYLE = {
    "ok": "QLabel { background: #eaf6ea; border: 1px solid #5aa55a; color: #1d4d1d; padding: 5px; }",
    "warn": "QLabel { background: #fff4dc; border: 1px solid #e0a020; color: #5a3d00; padding: 5px; }",
    "bad": "QLabel { background: #fdecea; border: 1px solid #d62728; color: #7a1010; padding: 5px; }",
}


def fit_table_height(table: QTableWidget) -> None:
    """Make a small table exactly as tall as its rows (no inner scroll bar)."""
    h = table.horizontalHeader().height() if table.horizontalHeader().isVisible() else 0
    h += sum(table.rowHeight(r) for r in range(table.rowCount())) + 2 * table.frameWidth() + 2
    table.setFixedHeight(h)


class InfoPanel(QWidget):
    """Verdict banner, topology report, timings, interpretation, selection, open (d-1)-faces.

    Emits :attr:`face_clicked` with a face tuple (the window frames it).
    """

    face_clicked = Signal(object)
    #: A prune cascade was clicked (the window frames its origin).
    cascade_clicked = Signal(object)
    #: The user asked to look at the paper's run.
    paper_requested = Signal()
    #: An uncertain feature was clicked (the window frames it).
    feature_clicked = Signal(object)
    #: Something was selected by typing its index: the sample indices to frame.
    indexed = Signal(object)

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        lay = QVBoxLayout(self)
        lay.setContentsMargins(6, 4, 6, 4)
        self.banner = QLabel(self)
        self.banner.setWordWrap(True)
        self.banner.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.banner.setToolTip("The core's verdict on M_S and its report messages")
        self.banner.setVisible(False)
        lay.addWidget(self.banner)
        self.features = FeaturesPanel(model, self)
        self.features.feature_clicked.connect(self.feature_clicked)
        lay.addWidget(self.features)
        box = QGroupBox("Topology of the final M_S (after the last step)", self)
        bl = QVBoxLayout(box)
        self.topology = QTableWidget(0, 3, box)
        self.topology.setHorizontalHeaderLabels(["", "found", "expected"])
        self.topology.verticalHeader().setVisible(False)
        self.topology.verticalHeader().setDefaultSectionSize(19)
        header = self.topology.horizontalHeader()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(2, QHeaderView.ResizeMode.Stretch)
        self.topology.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.topology.setVerticalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.topology.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.topology.setToolTip("The core's topology report; 'expected' is the true topology of a built-in sample")
        bl.addWidget(self.topology)
        self.messages = QLabel(box)
        self.messages.setWordWrap(True)
        bl.addWidget(self.messages)
        self.timings = QLabel(box)
        self.timings.setWordWrap(True)
        self.timings.setToolTip("Seconds per stage of the reconstruction")
        bl.addWidget(self.timings)
        lay.addWidget(box)
        gt = self.truth_box = QGroupBox("Ground truth: the mesh's faces", self)
        gl = QVBoxLayout(gt)
        self.truth_text = QLabel(gt)
        self.truth_text.setWordWrap(True)
        self.truth_text.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        gt.setToolTip(
            "M_S against the faces of the opened mesh: a face is recovered when M_S has a "
            "simplex on exactly its samples. The Hausdorff distance is sampled on both "
            "complexes (± the sampling's error bound)."
        )
        gl.addWidget(self.truth_text)
        gt.setVisible(False)
        lay.addWidget(gt)
        self.diagnosis = DiagnosisPanel(model, self)
        self.diagnosis.cascade_clicked.connect(self.cascade_clicked)
        self.diagnosis.paper_requested.connect(self.paper_requested)
        lay.addWidget(self.diagnosis)
        self.normal_angles = NormalAnglesPanel(model, self)  # only shown when the file had normals
        lay.addWidget(self.normal_angles)
        self.theorems = TheoremPanel(model, self)
        lay.addWidget(self.theorems)
        self.compare = ComparePanel(model, self)
        lay.addWidget(self.compare)
        interp = self.interpretation_box = QGroupBox("Interpretation", self)
        il = QVBoxLayout(interp)
        self.interpretation = QLabel(interp)
        self.interpretation.setWordWrap(True)
        self.interpretation.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        il.addWidget(self.interpretation)
        interp.setToolTip("How the core read the paper for this result (docs/algorithm.md)")
        lay.addWidget(interp)
        sel = QGroupBox("Selection", self)
        sl = QVBoxLayout(sel)
        self.selection = QLabel("Click a sample or a simplex in the view.", sel)
        self.selection.setWordWrap(True)
        self.selection.setAlignment(Qt.AlignmentFlag.AlignTop | Qt.AlignmentFlag.AlignLeft)
        self.selection.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        # a fixed height, scrolled when longer: what is selected never moves the boxes below
        # (the open faces list would slide away from under the mouse)
        area = QScrollArea(sel)
        area.setWidget(self.selection)
        area.setWidgetResizable(True)
        area.setFrameShape(QFrame.Shape.NoFrame)
        area.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        area.setFixedHeight(SELECTION_LINES * self.fontMetrics().lineSpacing() + 8)
        sl.addWidget(area)
        self.lookup = QLineEdit(sel)
        self.lookup.setPlaceholderText("select by index: 12, r 7, s 40, or 12 40 41 — Enter")
        self.lookup.setToolTip(
            "A sample number; 'r N' for the sample of the file's row N (from 0; samples are numbered in "
            "spatial order); 's N' for T_S simplex N (the number the steps use); d + 1 sample numbers for "
            "a simplex, d for a face. Enter selects it and frames it in the view."
        )
        self.lookup.returnPressed.connect(self._lookup)
        sl.addWidget(self.lookup)
        self.jump = QPushButton("Jump to removing step", sel)
        self.jump.setToolTip("Go to the step of Algorithm 3 that removed the selected simplex")
        self.jump.setEnabled(False)
        self.jump.clicked.connect(self._jump)
        sl.addWidget(self.jump)
        lay.addWidget(sel)
        faces = QGroupBox("Open (d-1)-faces at this step", self)
        fl = QVBoxLayout(faces)
        self.faces_label = SteadyText(faces)  # a new count never re-lays out the dock (nor moves the list)
        fl.addWidget(self.faces_label)
        self.faces = QListWidget(faces)
        self.faces.setMinimumHeight(90)
        self.faces.setToolTip("Faces in one simplex (boundary) or more than two (non-manifold); click to frame one")
        # only a click or Enter selects: the list taking keyboard focus (e.g. after
        # Esc) must not select its first face and move the camera
        self.faces.itemClicked.connect(self._face_item)
        self.faces.itemActivated.connect(self._face_item)
        fl.addWidget(self.faces)
        lay.addWidget(faces, 1)
        self._jump_to: int | None = None
        self.refresh_timer = QTimer(self)
        self.refresh_timer.setSingleShot(True)
        self.refresh_timer.setInterval(120)
        self.refresh_timer.timeout.connect(self.refresh_faces)
        model.reconstruction_changed.connect(self.refresh_report)
        model.player.step_changed.connect(lambda *_: (self.refresh_timer.start(), self.refresh_selection()))
        model.selection.changed.connect(self.refresh_selection)
        model.candidates_changed.connect(self.refresh_selection)

    # -- report --------------------------------------------------------------
    def refresh_report(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        truth = self.model.truth
        expected = getattr(truth, "manifold", None)
        mesh_cmp = getattr(truth, "comparison", None)
        rows = topology_rows(rec, expected, mesh_cmp.mesh_topology if mesh_cmp is not None else None)
        self.topology.setRowCount(len(rows))
        for r, (name, found, exp) in enumerate(rows):
            for c, text in enumerate((name, found, exp)):
                item = QTableWidgetItem(text)
                if text:  # the whole value, also when a narrow column elides it
                    item.setToolTip(text if c == 0 else f"{name}: {text}" + (" (expected)" if c == 2 else ""))
                if c == 1 and exp and found != exp:
                    item.setForeground(Qt.GlobalColor.red)
                self.topology.setItem(r, c, item)
        fit_table_height(self.topology)
        title = f"{self.model.source}: d = {rec.d} in R^{rec.k}, n = {rec.n}"
        if expected is not None:
            title += f" — expected: {expected.name}"
        self.messages.setText("<b>" + escape(title) + "</b>")
        level, words = verdict(rec, truth)
        msgs = rec.topology.messages
        self.banner.setStyleSheet(BANNER_STYLE[level])
        which = "robust extraction" if rec.mode == "robust" else "the paper's Algorithm 3"
        self.banner.setText(
            f"<b>{escape(words)}</b> — {escape(which, quote=False)}" + "".join(f"<br>• {escape(m)}" for m in msgs)
        )
        self.banner.setVisible(True)
        self.refresh_truth()
        rows = interpretation_rows(rec)
        self.interpretation.setText(
            "<table cellspacing='0' cellpadding='1'>"
            + "".join(f"<tr><td><b>{escape(a)}</b>&nbsp;&nbsp;</td><td>{escape(b)}</td></tr>" for a, b, _ in rows)
            + "</table>"
        )
        self.interpretation.setToolTip("<br>".join(f"<b>{escape(a)}</b>: {escape(c)}" for a, _, c in rows))
        total = sum(rec.timings.values())
        parts = ", ".join(f"{k} {v:.2f}" for k, v in rec.timings.items())
        backend = f"; Delaunay by {escape(rec.delaunay_backend)}" if rec.delaunay_backend else ""
        self.timings.setText(f"<small>timings (s): {parts}; total {total:.2f}{backend}</small>")
        self.refresh_faces()
        self.refresh_selection()

    def refresh_truth(self) -> None:
        """The comparison with a mesh's faces, when the input was a mesh."""
        from ..scene.truth import comparison_rows

        cmp = getattr(self.model.truth, "comparison", None)
        self.truth_box.setVisible(cmp is not None)
        if cmp is None:
            self.truth_text.setText("")
            return
        cells = "".join(
            f"<tr><td><b>{escape(a)}</b>&nbsp;&nbsp;</td><td>{escape(b)}</td><td>&nbsp;&nbsp;{escape(c)}</td></tr>"
            for a, b, c in comparison_rows(cmp)
        )
        self.truth_text.setText(
            f"<small>{escape(self.model.truth.name)}</small>"
            "<table cellspacing='0' cellpadding='1'><tr><td></td><td><i>M_S</i></td>"
            f"<td>&nbsp;&nbsp;<i>mesh</i></td></tr>{cells}</table>"
        )

    # -- selection -------------------------------------------------------------
    def refresh_selection(self, *_) -> None:
        sel = self.model.selection
        if self.model.rec is None:
            return
        parts = []
        self._jump_to = None
        if sel.sample is not None:
            parts.append(sample_text(self.model, sel.sample))
        if sel.simplex is not None:
            text, step = simplex_text(self.model, sel.simplex)
            parts.append(text)
            self._jump_to = step
        if sel.face is not None:
            parts.append(face_text(self.model, sel.face))
        if sel.feature is not None:  # clicked in the list of uncertain features: what it is, where, how big
            from ..scene.features import epsilon_words, feature_words

            f = sel.feature
            where = ", ".join(f"{x:.4g}" for x in f.location)
            eps = epsilon_words(self.model.known_quality(), f)  # as the list says it: never computed on a click
            parts.append(
                f"<b>{escape(f.kind)}</b>, {f.size_spacings:.3g} spacings, at ({where}), "
                f"{len(f.vertices)} samples{', ' + eps if eps else ''}<br>{escape(feature_words(f))}"
            )
        self.selection.setText("<br><br>".join(parts) if parts else "Click a sample or a simplex in the view.")
        self.jump.setEnabled(self._jump_to is not None)
        self.jump.setText(
            f"Jump to removing step ({self._jump_to})" if self._jump_to is not None else "Jump to removing step"
        )

    def _lookup(self) -> None:
        from ..scene.lookup import select_by_text

        got = select_by_text(self.model, self.lookup.text())
        if isinstance(got, str):
            self.lookup.setToolTip(got)
            self.lookup.setStyleSheet("QLineEdit { background: #fdecea; }")
            window = self.window()
            if hasattr(window, "statusBar"):
                window.statusBar().showMessage(f"Select by index: {got}.", 8000)
            return
        self.lookup.setStyleSheet("")
        self.indexed.emit(got[1])

    def _jump(self) -> None:
        if self._jump_to is not None:
            self.model.player.set_step(self._jump_to)

    # -- open faces -------------------------------------------------------------
    def refresh_faces(self) -> None:
        if self.model.rec is None:
            return
        if self.visibleRegion().isEmpty():
            # hidden, or a tabbed-away dock: changing it would still cost a frame of the whole
            # window; :meth:`catch_up` refreshes it when it is seen again
            self._faces_stale = True
            return
        self._faces_stale = False
        faces, counts = self.model.open_faces()
        self.faces.blockSignals(True)
        self.faces.clear()
        nonman = int((counts > 2).sum())
        self.faces_label.setText(
            f"{len(faces)} open faces: {nonman} non-manifold, {len(faces) - nonman} boundary"
            + (f" (first {MAX_FACES} listed)" if len(faces) > MAX_FACES else "")
        )
        for f, c in zip(faces[:MAX_FACES], counts[:MAX_FACES]):
            kind = "non-manifold" if c > 2 else "boundary"
            item = QListWidgetItem(f"{fmt_tuple(f)}  — {c} simplices ({kind})")
            item.setData(Qt.ItemDataRole.UserRole, tuple(int(v) for v in f))
            self.faces.addItem(item)
        self.faces.doItemsLayout()  # now, not on the view's own timer: one repaint of the window, not two
        self.faces.blockSignals(False)

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().showEvent(event)
        self.catch_up()

    def catch_up(self, *_) -> None:
        """Refresh what changed while the panel was not seen (its dock shown or its tab chosen)."""
        if getattr(self, "_faces_stale", False):
            QTimer.singleShot(0, self.refresh_faces)  # once the dock's tab is laid out and visible

    def _face_item(self, item) -> None:
        if item is None:
            return
        face = item.data(Qt.ItemDataRole.UserRole)
        self.model.selection.select_face(face)
        self.face_clicked.emit(face)
