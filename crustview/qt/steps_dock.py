"""Steps panel: replay Algorithm 3 step by step, with a synchronised event log."""

from __future__ import annotations

from PySide6.QtCore import QAbstractTableModel, QElapsedTimer, QModelIndex, Qt, QTimer
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QPlainTextEdit,
    QPushButton,
    QSizePolicy,
    QSlider,
    QSpinBox,
    QStyle,
    QTableView,
    QToolButton,
    QToolTip,
    QVBoxLayout,
    QWidget,
)

from ..core.steps import PLACELESS_RULES, RULES
from ..scene.describe import deg, fmt_tuple, step_words, tau_text
from ..scene.layers import STEP_COLORS
from ..scene.model import SceneModel
from .steady import SteadyLabel
from .timeline import TimelineView

COLUMNS = ("#", "rule", "τ", "kept", "removed", "added", "angle")
#: Header labels of a narrow table (the tabbed column of a small window); tooltips say them whole.
SHORT_COLUMNS = ("#", "rule", "τ", "kept", "rem.", "add.", "angle")
#: What each column holds (header tooltips).
COLUMN_TIPS = (
    "step number",
    "the rule that made the step",
    "tau: the face the step looked at",
    "kept: the pair of simplices the step kept (paper's resolve)",
    "removed: the simplices the step removed",
    "added: the simplices the step added (robust extension)",
    "angle: the angle of the kept pair at tau (resolve steps)",
)

#: Playback draws at most this many frames per second; the steps in between are applied undrawn.
FRAME_RATE = 30
#: Fastest playback offered (steps per second).
MAX_SPEED = 20_000

#: Short rule names in the step table.
RULE_SHORT = {
    "prune-sharp": "prune",
    "resolve-nonmanifold": "resolve",
    "seed-core": "core",
    "grow-relaxed": "relax",
    "fill-hole": "fill",
    "insert-sample": "insert",
    "drop-stray": "stray",
}


def _ids(t) -> str:
    return "" if not t else (fmt_tuple(t) if len(t) <= 4 else f"{len(t)} simplices")


def _tau_cell(step, d: int) -> str:
    """The τ column's text: :func:`tau_text` up to d vertices (a (d-1)-face), "N samples" past that.

    The robust rules' faces, loops and rims (cut-handle's, tens of samples) listed in full made the column
    657 px wide at 1024 x 700 (a 17-sample loop), and triangles and 5-sample loops 124-200 px, leaving the
    removed and added simplices "(…" (Qt sizes the column to its widest text among 1,000 rows); the
    tooltip gives every vertex.
    """
    text = tau_text(step)  # "—" for a rule that acts everywhere at once
    return text if text == "—" or len(step.tau) <= d else f"{len(step.tau)} samples"


class StepText(QPlainTextEdit):
    """The words about the current step: read-only, wrapped, a fixed size whatever the text."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setReadOnly(True)
        self.setLineWrapMode(QPlainTextEdit.LineWrapMode.WidgetWidth)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setStyleSheet("QPlainTextEdit { background: #f7f7f2; border: 1px solid #ccc; }")
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)

    def text(self) -> str:
        return self.toPlainText()

    def setText(self, text: str) -> None:  # noqa: N802 - as QLabel
        if text != self.toPlainText():
            self.setPlainText(text)


class StepLog(QAbstractTableModel):
    """Table model over ``extraction.steps`` (row r is step r + 1)."""

    def __init__(self, model: SceneModel) -> None:
        super().__init__()
        self.model = model
        #: Display texts of the rows painted lately (the view asks for every cell and role on each paint).
        self._rows: dict[int, tuple[str, ...]] = {}
        #: Abbreviated header labels (:data:`SHORT_COLUMNS`) for a narrow table.
        self.short_headers = False

    def rowCount(self, parent=QModelIndex()) -> int:  # noqa: B008, N802 - Qt API
        return 0 if parent.isValid() else self.model.player.n_steps

    def columnCount(self, parent=QModelIndex()) -> int:  # noqa: B008, N802 - Qt API
        return len(COLUMNS)

    def headerData(self, section, orientation, role=Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if orientation != Qt.Orientation.Horizontal:
            return None
        if role == Qt.ItemDataRole.DisplayRole:
            return (SHORT_COLUMNS if self.short_headers else COLUMNS)[section]
        if role == Qt.ItemDataRole.ToolTipRole:
            return COLUMN_TIPS[section]
        return None

    def data(self, index, role=Qt.ItemDataRole.DisplayRole):
        if role == Qt.ItemDataRole.DisplayRole:
            ext = self.model.player.extraction
            if ext is None or not index.isValid():
                return None
            row = index.row()
            texts = self._rows.get(row)
            if texts is None:
                if len(self._rows) > 4096:  # a few screens of rows: enough to scroll without formatting again
                    self._rows.clear()
                s = ext.steps[row]
                texts = self._rows[row] = (
                    str(s.index + 1),
                    RULE_SHORT.get(s.rule, s.rule),
                    _tau_cell(s, self.model.rec.d),
                    _ids(s.kept),
                    _ids(s.removed),
                    _ids(s.added),
                    deg(s.angle),
                )
            return texts[index.column()]
        if role == Qt.ItemDataRole.ToolTipRole:
            ext = self.model.player.extraction
            if ext is None or not index.isValid():
                return None
            s = ext.steps[index.row()]
            # the whole value, which a narrow column cuts ("res…", "(2782, 2819, …"), then the reason
            full = {
                "rule": s.rule,
                "τ": tau_text(s),
                "kept": fmt_tuple(s.kept) if s.kept else "",
                "removed": fmt_tuple(s.removed) if s.removed else "",
                "added": fmt_tuple(s.added) if s.added else "",
            }.get(COLUMNS[index.column()], "")
            return f"{COLUMNS[index.column()]}: {full}\n{s.reason}" if full else s.reason
        return None

    def reset(self) -> None:
        self.beginResetModel()
        self._rows = {}
        self.endResetModel()


class StepsPanel(QWidget):
    """Controls of the :class:`~crustview.scene.StepPlayer` of a model."""

    def __init__(self, model: SceneModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.model = model
        player = model.player
        lay = QVBoxLayout(self)
        lay.setContentsMargins(6, 4, 6, 4)
        row = QHBoxLayout()

        style = self.style()
        icon = QStyle.StandardPixmap

        def button(sp, tip, slot):
            b = QToolButton(self)
            b.setIcon(style.standardIcon(sp))
            b.setToolTip(tip)
            b.clicked.connect(slot)
            row.addWidget(b)
            return b

        self.first = button(
            icon.SP_MediaSkipBackward,
            "First: step 0, T_S (or an empty M_S where the robust extension builds it) (Home)",
            player.first,
        )
        self.prev = button(icon.SP_MediaSeekBackward, "Previous step (Left)", player.prev)
        self.play = button(icon.SP_MediaPlay, "Play / pause (Space)", player.toggle)
        self.next = button(icon.SP_MediaSeekForward, "Next step (Right)", player.next)
        self.last = button(icon.SP_MediaSkipForward, "Last: the extracted M_S (End)", player.last)
        self.speed = QDoubleSpinBox(self)
        self.speed.setRange(0.5, MAX_SPEED)
        self.speed.setDecimals(1)
        self.speed.setValue(player.speed)
        self.speed.setSuffix(" steps/s")
        self.speed.setToolTip(
            f"Playback speed. The view is drawn at most {FRAME_RATE} times a second; "
            "faster playback applies the steps in between without drawing them."
        )
        row.addWidget(self.speed)
        self.counter = SteadyLabel(self)
        self.counter.setText("step 0 / 0")
        self.counter.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
        row.addWidget(self.counter)
        lay.addLayout(row)
        row3 = QHBoxLayout()
        row3.addWidget(QLabel("Go to step", self))
        self.goto = QSpinBox(self)
        self.goto.setKeyboardTracking(False)  # typing 1234 goes to 1234, not to 1, 12, 123 first
        self.goto.setToolTip("Type a step number and press Enter")
        self.goto.valueChanged.connect(player.set_step)
        row3.addWidget(self.goto)
        self.only_rule = QCheckBox("Play only the rule below", self)
        self.only_rule.setToolTip(
            "Playback visits only steps of the chosen rule; ← and → still go one step at a time "
            "(Next of rule jumps to the next step of it)"
        )
        self.only_rule.toggled.connect(self._rule_filter)
        row3.addWidget(self.only_rule, 1)
        lay.addLayout(row3)
        self.rate = QLabel("", self)
        self.rate.setStyleSheet("QLabel { color: #555; }")
        self.rate.setWordWrap(True)
        lay.addWidget(self.rate)
        self.slider = QSlider(Qt.Orientation.Horizontal, self)
        self.slider.setToolTip("Scrub through all steps of Algorithm 3")
        lay.addWidget(self.slider)
        self.timeline = TimelineView(model, self)
        lay.addWidget(self.timeline)
        row2 = QHBoxLayout()
        self.rule = QComboBox(self)
        self.rule.addItems(list(RULES))
        self.rule.currentTextChanged.connect(lambda *_: self._rule_filter(self.only_rule.isChecked()))
        self.rule.setToolTip(
            "prune-sharp: line 2 of Algorithm 3; resolve-nonmanifold: lines 3-5; seed, grow, "
            "grow-relaxed, fill-hole, drop-stray, insert-sample: the robust extension, which "
            "mostly adds simplices"
        )
        self.to_rule = QPushButton("Run to next step of rule", self)
        self.to_rule.setToolTip("Jump to just after the next step that applied the chosen rule")
        self.to_rule.clicked.connect(self._run_to_rule)
        row2.addWidget(self.to_rule)
        row2.addWidget(self.rule, 1)
        lay.addLayout(row2)
        self.follow = QCheckBox("Frame each step (zoom onto τ and its simplices; R resets the view)", self)
        self.follow.setToolTip("Move the camera to every step as it is applied, keeping the view direction")
        lay.addWidget(self.follow)
        # a read-only text box of fixed height (scrolled when a step's text is longer): its
        # size never depends on the text, so stepping never re-lays out the dock and the window,
        # which would cost a full repaint and composition of the window after every step
        self.words = StepText(self)
        self.words.setFixedHeight(4 * self.fontMetrics().lineSpacing() + 14)
        lay.addWidget(self.words)
        legend = QLabel(
            f"<span style='color:{STEP_COLORS['tau']}'>■</span> τ &nbsp; "
            f"<span style='color:{STEP_COLORS['kept']}'>■</span> kept pair &nbsp; "
            f"<span style='color:{STEP_COLORS['removed']}'>■</span> removed by this step &nbsp; "
            f"<span style='color:{STEP_COLORS['added']}'>■</span> added by this step (robust)",
            self,
        )
        legend.setWordWrap(True)  # narrow docks: wrap rather than widen the dock
        lay.addWidget(legend)
        self._syncing = False
        self.log = StepLog(model)
        self.table = QTableView(self)
        self.table.setModel(self.log)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(20)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        # the simplex lists share what is left, so the angle column is never cut off
        header.setSectionResizeMode(3, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(4, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(5, QHeaderView.ResizeMode.Stretch)
        header.setStretchLastSection(False)
        header.setMinimumSectionSize(24)
        self.table.setToolTip("Event log: every recorded step; selecting a row jumps there")
        lay.addWidget(self.table, 1)
        self.timer = QTimer(self)
        self.timer.setTimerType(Qt.TimerType.PreciseTimer)
        self.timer.timeout.connect(self._tick)
        self.clock = QElapsedTimer()
        self.play_clock = QElapsedTimer()
        self.slider.valueChanged.connect(player.set_step)
        self.table.selectionModel().currentRowChanged.connect(self._row_selected)
        self.table.clicked.connect(self._cell_clicked)
        self.speed.valueChanged.connect(self._speed)
        player.step_changed.connect(self.sync)
        player.extraction_changed.connect(self._extraction)
        player.playing_changed.connect(self._playing)
        self._extraction(player.n_steps)

    def compact(self) -> None:
        """Narrower controls for small screens."""
        self.log.short_headers = True  # "removed" was cut to "emove" at 1024 px
        self.log.headerDataChanged.emit(Qt.Orientation.Horizontal, 0, len(COLUMNS) - 1)
        self.speed.setSuffix("/s")
        self.follow.setText("Frame each step")
        self.to_rule.setText("Next of rule")

    def _extraction(self, n: int) -> None:
        self.log.reset()
        # ResizeToContents only measures the rows in view: size the step-number column for the largest
        fm = self.table.fontMetrics()
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.Fixed)
        header.resizeSection(0, fm.horizontalAdvance(str(max(n, 10))) + 14)
        # a run without kept pairs (the labelling path) leaves 'kept' and 'angle' empty: their
        # width goes to the removed and added simplices
        ext = self.model.player.extraction
        paired = ext is not None and any(len(st.kept) for st in ext.steps)
        for col in (COLUMNS.index("kept"), COLUMNS.index("angle")):
            self.table.setColumnHidden(col, not paired)
        self.slider.blockSignals(True)
        self.slider.setRange(0, n)
        self.slider.blockSignals(False)
        self.goto.blockSignals(True)
        self.goto.setRange(0, n)
        self.goto.blockSignals(False)
        self.counter.setText(f"step {n} / {n}")  # its widest text: the size it keeps while stepping
        # offer a rule this run applied: a robust run has no prune-sharp step, a paper run no grow
        ext = self.model.player.extraction
        present = {st.rule for st in ext.steps} if ext is not None else set()
        offered = [r for r in RULES if r in present]  # only rules this run applied (none: T_S was M_S)
        if [self.rule.itemText(i) for i in range(self.rule.count())] != offered:
            current = self.rule.currentText()
            self.rule.blockSignals(True)
            self.rule.clear()
            self.rule.addItems(offered)
            if offered:
                self.rule.setCurrentText(current if current in offered else offered[0])
            self.rule.blockSignals(False)
            self._rule_filter(self.only_rule.isChecked() and bool(offered))
        for w in (self.rule, self.to_rule, self.only_rule):  # a run of no steps has no rule to go to
            w.setEnabled(bool(offered))
        self.sync(self.model.player.position)

    def _row_selected(self, current, _previous) -> None:
        if current.isValid() and not self._syncing:
            self.model.player.set_step(current.row() + 1)

    def _cell_clicked(self, index) -> None:
        """A click on a τ, kept, removed or added cell selects that face or simplex.

        A cell listing several simplices selects them in turn, one per click.
        """
        ext = self.model.player.extraction
        if ext is None or not index.isValid():
            return
        s = ext.steps[index.row()]
        col = COLUMNS[index.column()]
        sel = self.model.selection
        if col == "τ":
            if s.rule not in PLACELESS_RULES:
                sel.select_face(s.tau)
            return
        ids = {"kept": s.kept, "removed": s.removed, "added": s.added}.get(col, ())
        if not ids:
            return
        rows = [self.model.candidate_row(int(e)) for e in ids]
        rows = [r for r in rows if r >= 0]
        if not rows:
            return
        turn = (rows.index(sel.simplex) + 1) % len(rows) if sel.simplex in rows else 0
        sel.select_simplex(rows[turn])

    def _run_to_rule(self) -> None:
        rule = self.rule.currentText()
        if not self.model.player.run_to_rule(rule):
            # said beside the button; the current step's description stays
            self.to_rule.setToolTip(f"No further step of rule {rule} after step {self.model.player.position}.")
            QToolTip.showText(
                self.to_rule.mapToGlobal(self.to_rule.rect().bottomLeft()), self.to_rule.toolTip(), self.to_rule
            )
            window = self.window()
            if hasattr(window, "statusBar"):
                window.statusBar().showMessage(self.to_rule.toolTip(), 8000)

    def _speed(self, v: float) -> None:
        self.model.player.speed = v
        self._playing(self.model.player.playing)

    def _rule_filter(self, on: bool) -> None:
        self.model.player.rule = self.rule.currentText() if on else None

    def _playing(self, playing: bool) -> None:
        sp = QStyle.StandardPixmap.SP_MediaPause if playing else QStyle.StandardPixmap.SP_MediaPlay
        self.play.setIcon(self.style().standardIcon(sp))
        if playing:
            sps = self.model.player.speed
            self.clock.start()
            self.play_clock.start()
            self._frames = 0
            self.timer.start(max(1000 // FRAME_RATE, int(1000 / sps)))
        else:
            self.timer.stop()
            self._show_rate(final=True)

    def _tick(self) -> None:
        """Apply the steps due since the last frame; only the last of them is drawn."""
        elapsed = self.clock.restart() / 1000.0
        self.model.player.advance(elapsed)
        self._frames += 1
        if self._frames % 10 == 0:
            self._show_rate()

    def _show_rate(self, final: bool = False) -> None:
        """Say how fast playback really goes and how many steps each frame skips."""
        player = self.model.player
        secs = self.play_clock.elapsed() / 1000.0 if self.play_clock.isValid() else 0.0
        frames = getattr(self, "_frames", 0)
        if secs <= 0 or frames == 0 or player.applied == 0:
            self.rate.setText("")
            return
        per_frame = player.applied / frames
        text = f"{player.applied / secs:,.0f} steps/s, {frames / secs:.0f} frames/s"
        if per_frame > 1.5:
            text += f": drawing 1 step in {per_frame:.0f}, the others applied undrawn"
        self.rate.setText(("last playback: " if final else "") + text)

    def sync(self, i: int) -> None:
        player = self.model.player
        n = player.n_steps
        self.slider.blockSignals(True)
        self.slider.setValue(i)
        self.slider.blockSignals(False)
        self.goto.blockSignals(True)
        self.goto.setValue(i)
        self.goto.blockSignals(False)
        self.counter.setText(f"step {i} / {n}")
        self.words.setText(
            step_words(player.current_step, i, n, player.extraction) if player.extraction else "No reconstruction yet."
        )
        # the selection model's signals stay on (the view repaints from them, so
        # exactly one row looks selected); a flag stops the echo to the player
        sm = self.table.selectionModel()
        self._syncing = True
        try:
            if i > 0:
                idx = self.log.index(i - 1, 0)
                flags = sm.SelectionFlag.ClearAndSelect | sm.SelectionFlag.Rows
                sm.setCurrentIndex(idx, flags)
                # EnsureVisible: a clicked row never moves away from under the mouse
                self.table.scrollTo(idx, QAbstractItemView.ScrollHint.EnsureVisible)
            else:
                sm.clearSelection()
                sm.setCurrentIndex(QModelIndex(), sm.SelectionFlag.Clear)
                self.table.scrollToTop()  # the first step comes next: show it, not old rows
        finally:
            self._syncing = False
