"""The main window: 3-D view in the centre, docks around it."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QEvent, QObject, QSettings, Qt, QTimer
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import (
    QAbstractButton,
    QAbstractSlider,
    QAbstractSpinBox,
    QApplication,
    QComboBox,
    QDialog,
    QDockWidget,
    QLineEdit,
    QMainWindow,
    QMessageBox,
    QScrollArea,
    QWidget,
)
from pyvistaqt import QtInteractor

from ..render import SceneView
from ..scene.model import SceneModel
from .export import ExportActions
from .files import FileActions
from .info_dock import InfoPanel
from .layers_dock import LayersPanel
from .layout import DockLayout
from .lod import StepDetail
from .projection_dock import ProjectionPanel
from .run_dock import RunPanel
from .running import RunActions
from .sessions import SessionActions
from .status_progress import StatusProgress
from .statusbar import ElidingStatusBar
from .steady import SteadyLabel
from .steps_dock import StepsPanel
from .worker import Runner


def _scrolled(widget: QWidget) -> QScrollArea:
    area = QScrollArea()
    area.setWidget(widget)
    area.setWidgetResizable(True)
    area.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
    return area


class MainWindow(DockLayout, SessionActions, ExportActions, FileActions, RunActions, QMainWindow):
    """crustview's main window.

    Parameters
    ----------
    settings : QSettings, optional
        Where recent files are kept (tests pass a temporary one).
    """

    def __init__(self, settings: QSettings | None = None, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.settings = settings if settings is not None else QSettings("crustview", "crustview")
        self.model = SceneModel()
        self.setWindowTitle("crustview")
        self.plotter = QtInteractor(self, auto_update=False, multi_samples=0)
        self.setCentralWidget(self.plotter)
        for key in ("q", "e", "v"):  # VTK/pyvista would quit or change style on these keys
            self.plotter.clear_events_for_key(key)
        self.view = SceneView(self.model, self.plotter)
        # the widget's paint renders the scene: a render asked for is a paint asked for (render.frames); many
        # changes before the next paint (steps while playing) cost one frame
        self.view.frames.paint = lambda: QWidget.update(self.plotter)
        self.step_detail = StepDetail(self.view, self.model.player, self)  # thinned frames while stepping
        self.points: np.ndarray | None = None
        #: Where the shown data came from: a FileSource, a BuiltinSource or None (arrays).
        self.origin = None
        self.last_error: str | None = None
        self.error_box: QMessageBox | None = None
        self._pending: dict = {}
        #: Whether the docks share one tabbed column (see :meth:`keep_view_share`).
        self.compact = False

        self.run_panel = RunPanel(self.model)
        self.layers_panel = LayersPanel(self.model.layers)
        self.projection_panel = ProjectionPanel(self.model)
        self.steps_panel = StepsPanel(self.model)
        self.info_panel = InfoPanel(self.model)
        left, right = Qt.DockWidgetArea.LeftDockWidgetArea, Qt.DockWidgetArea.RightDockWidgetArea
        self.docks = {
            "run": self._dock("Run", _scrolled(self.run_panel), left),
            "layers": self._dock("Layers", self.layers_panel, left),
            "projection": self._dock("Projection", _scrolled(self.projection_panel), left),
            "steps": self._dock("Steps of Algorithm 3", self.steps_panel, right),
            "info": self._dock("Information", _scrolled(self.info_panel), right),
        }
        self.resizeDocks(
            [self.docks["run"], self.docks["layers"], self.docks["projection"]],
            [150, 330, 260],
            Qt.Orientation.Vertical,
        )
        self.resizeDocks([self.docks["steps"], self.docks["info"]], [380, 620], Qt.Orientation.Vertical)
        self.resizeDocks([self.docks["run"], self.docks["steps"]], [400, 400], Qt.Orientation.Horizontal)

        self.runner = Runner(self)
        self.runner.started.connect(lambda label: self.run_panel.set_busy(True, label))
        self.runner.progress.connect(self.run_panel.show_progress)
        self.runner.done.connect(self._job_done)
        self.runner.failed.connect(self._job_failed)
        self.runner.cancelled.connect(self._job_cancelled)
        self.runner.finished.connect(lambda: self.run_panel.set_busy(False))
        self.run_panel.reconstruct_requested.connect(self._reconstruct_requested)
        self.run_panel.cancel_requested.connect(self.runner.cancel)
        self.docks["info"].visibilityChanged.connect(self.info_panel.catch_up)  # its tab chosen
        self.info_panel.face_clicked.connect(self.view.frame_face)
        self.info_panel.cascade_clicked.connect(self.view.frame_cascade)
        self.info_panel.feature_clicked.connect(self.view.frame_feature)
        self.info_panel.indexed.connect(self._frame_indexed)
        self.info_panel.compare.simplex_clicked.connect(self.frame_compared)
        self.info_panel.paper_requested.connect(lambda: self.run_panel.set_mode("paper"))
        self.model.player.step_changed.connect(lambda *_: self._update_status())
        self.model.player.step_changed.connect(self._follow_step)
        self.steps_panel.follow.toggled.connect(self._follow_toggled)
        self.model.reconstruction_changed.connect(self._update_status)
        self.model.reconstruction_changed.connect(lambda: self.layers_panel.offer(self.model))
        self.model.candidates_changed.connect(lambda *_: self._update_status())

        self._build_menus()
        self.setStatusBar(ElidingStatusBar(self))
        self.status_counts = SteadyLabel(self)  # a new count per step must not re-lay out the window
        self.status_progress = StatusProgress(self.run_panel, self)  # in sight whatever tab is in front
        self.statusBar().addPermanentWidget(self.status_progress)
        self.statusBar().addPermanentWidget(self.status_counts)
        # a message longer than the room left of the counts ends in "…" there: the whole of it on hover
        self.statusBar().showMessage("Open a point file (File ▸ Open, or drop it here) or a built-in sample.")
        self.setAcceptDrops(True)
        self._press: tuple[int, int] | None = None
        self.plotter.iren.add_observer("LeftButtonPressEvent", self._on_press)
        self.plotter.iren.add_observer("LeftButtonReleaseEvent", self._on_release)
        self._step_keys = {
            Qt.Key.Key_Left: self.model.player.prev,
            Qt.Key.Key_Right: self.model.player.next,
            Qt.Key.Key_Space: self.model.player.toggle,
            Qt.Key.Key_Home: self.model.player.first,
            Qt.Key.Key_End: self.model.player.last,
        }
        QApplication.instance().installEventFilter(self)

    def _owns(self, obj: QWidget) -> bool:
        """A widget of this window, floating docks included, dialogs excluded."""
        if isinstance(obj.window(), QDialog):
            return False
        w = obj
        while w is not None:
            if w is self:
                return True
            w = w.parentWidget()
        return False

    def _keeps_key(self, obj: QObject, key: int) -> bool:
        """Whether the focused widget needs this stepping key for itself."""
        if isinstance(obj, (QLineEdit, QAbstractSpinBox, QComboBox, QAbstractSlider)):
            return True  # text, numbers, choices and sliders (θ, opacity) use ← → Home End
        return key == Qt.Key.Key_Space and isinstance(obj, QAbstractButton)  # Space presses a button

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt API
        """Stepping keys reach the player, except where the focused widget needs them.

        The menu actions carry the same shortcuts.  A widget that uses the key
        (a slider, a spin box, a text field, Space on a button) claims it
        through ``ShortcutOverride``, so the shortcut does not fire; key
        presses that reach no shortcut (window not active) are handled here.
        """
        kind = event.type()
        if (
            kind in (QEvent.Type.KeyPress, QEvent.Type.ShortcutOverride)
            and isinstance(obj, QWidget)
            and self._owns(obj)
        ):
            if self._focus_key(obj, event):
                return kind == QEvent.Type.KeyPress
            fn = self._step_keys.get(event.key())
            if fn is None or event.modifiers() != Qt.KeyboardModifier.NoModifier:
                return False
            if self._keeps_key(obj, event.key()):
                if kind == QEvent.Type.ShortcutOverride:
                    event.accept()  # the widget gets the key, not the menu shortcut
                return False
            if kind == QEvent.Type.KeyPress:
                fn()
                return True
        return False

    def _focus_key(self, obj: QWidget, event) -> bool:
        """Esc, and Enter after typing in a field, give the keyboard back to the 3-D view.

        Then the step keys and the view's letter keys (R) work again, without a
        click on the view that would select what is under the mouse.  Esc on the
        view itself clears the selection (View ▸ Clear selection).  Returns True
        when the key was used here.
        """
        key = event.key()
        if obj is self.plotter or self.plotter.isAncestorOf(obj):
            if key == Qt.Key.Key_Escape and event.type() == QEvent.Type.KeyPress:
                self.model.selection.clear()  # as the menu's shortcut, which the view's key handling can miss
                return True
            return False
        if key == Qt.Key.Key_Escape:
            if event.type() == QEvent.Type.ShortcutOverride:
                event.accept()  # not the Clear selection shortcut: only the focus moves
            else:
                self.plotter.setFocus(Qt.FocusReason.ShortcutFocusReason)
            return True
        typed = isinstance(obj, (QLineEdit, QAbstractSpinBox)) or (isinstance(obj, QComboBox) and obj.isEditable())
        if typed and key in (Qt.Key.Key_Return, Qt.Key.Key_Enter) and event.type() == QEvent.Type.KeyPress:
            # the field takes the value first (its editingFinished), then the view the focus
            QTimer.singleShot(0, lambda: self.plotter.setFocus(Qt.FocusReason.OtherFocusReason))
        return False

    # -- construction helpers ---------------------------------------------------
    def _dock(self, title: str, widget: QWidget, area) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(title)
        dock.setWidget(widget)
        dock.setFeatures(
            QDockWidget.DockWidgetFeature.DockWidgetMovable
            | QDockWidget.DockWidgetFeature.DockWidgetFloatable
            | QDockWidget.DockWidgetFeature.DockWidgetClosable
        )
        self.addDockWidget(area, dock)
        return dock

    def _action(self, menu, text: str, slot, shortcut=None, tip: str = "") -> QAction:
        act = QAction(text, self)
        if shortcut is not None:
            act.setShortcut(QKeySequence(shortcut))
            act.setShortcutContext(Qt.ShortcutContext.WindowShortcut)
        act.setToolTip(tip or text)
        act.setStatusTip(tip or text)
        act.triggered.connect(slot)
        menu.addAction(act)
        self.addAction(act)
        return act

    def _build_menus(self) -> None:
        bar = self.menuBar()
        f = bar.addMenu("&File")
        self._action(f, "&Open…", self.open_dialog, QKeySequence.StandardKey.Open, "Open a point file")
        self._action(
            f,
            "Open &built-in sample…",
            self.open_builtin_dialog,
            "Ctrl+B",
            "Sample a built-in manifold of known topology",
        )
        self.recent_menu = f.addMenu("Open &recent")
        self._fill_recent()
        f.addSeparator()
        self._action(
            f,
            "&Save result…",
            self.save_result_dialog,
            QKeySequence.StandardKey.Save,
            "Write M_S and the recorded steps (npz) or the mesh (ply, obj, off, vtk, stl)",
        )
        self._action(f, "Save s&creenshot…", self.save_screenshot_dialog, "Ctrl+P", "Save the 3-D view as PNG")
        f.addSeparator()
        self.add_session_actions(f)
        self.add_tool_actions(f)
        f.addSeparator()
        self._action(f, "&Quit", self.close, QKeySequence.StandardKey.Quit)
        s = bar.addMenu("&Steps")
        p = self.model.player
        self._action(s, "Previous step", p.prev, Qt.Key.Key_Left)
        self._action(s, "Next step", p.next, Qt.Key.Key_Right)
        self._action(s, "Play / pause", p.toggle, Qt.Key.Key_Space)
        self._action(s, "First (T_S)", p.first, Qt.Key.Key_Home)
        self._action(s, "Last (M_S)", p.last, Qt.Key.Key_End)
        v = bar.addMenu("&View")
        self._action(v, "Reset camera", lambda: (self.view.reset_camera(), self.view.render()), "R")
        self.y_up = self._action(
            v, "Y axis up", self._set_y_up, "Y", "View with the Y axis up (scans such as the bunny are stored Y-up)"
        )
        self.y_up.setCheckable(True)  # for this session only: the demo and R^4 data read Z-up
        self._action(v, "Clear selection", self.model.selection.clear, Qt.Key.Key_Escape)
        v.addSeparator()
        for dock in self.docks.values():
            v.addAction(dock.toggleViewAction())

    def show_error(self, message: str) -> None:
        """A clear, non-blocking message; the current result stays visible."""
        self.last_error = message
        self.statusBar().showMessage(message, 20000)
        if self.error_box is not None:
            self.error_box.close()
        box = QMessageBox(QMessageBox.Icon.Warning, "crustview", message, QMessageBox.StandardButton.Ok, self)
        box.setWindowModality(Qt.WindowModality.WindowModal)
        box.open()
        self.error_box = box

    def _update_status(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        alive = int(np.count_nonzero(rec.extraction.alive(self.model.player.position)))
        shown = int(np.count_nonzero(self.model.candidate_mask()))  # the candidates layer's count
        pending = (self.model.test, self.model.theta) != (rec.test, float(rec.theta))
        self.status_counts.setText(
            f"n = {rec.n} · candidates {shown:,}"
            + (" (pending change)" if pending else "")
            + f" · M_S now {alive:,} · step {self.model.player.position}/{rec.extraction.n_steps}"
        )

    def _set_y_up(self, *_) -> None:
        self.view.y_up = self.y_up.isChecked()
        self.view.reset_camera()
        self.view.render()

    def _follow_toggled(self, on: bool) -> None:
        if on:
            self._follow_step()
        else:  # back to the whole of the data, uncut (the framed step's zoom went with it)
            self.view.reset_camera()
            self.view.render()

    def _follow_step(self, *_) -> None:
        """With "Frame each step" on, look at the step just applied from its open side."""
        step = self.model.player.shown_step
        if not self.steps_panel.follow.isChecked() or step is None or self.model.rec is None:
            return
        self.view.frame_step(step)

    def _frame_indexed(self, samples) -> None:
        """Frame what was selected by its index (a sample with its neighbours in view)."""
        if len(samples) == 1:
            i = int(samples[0])
            near = np.argsort(np.linalg.norm(self.model.rec.points - self.model.rec.points[i], axis=1))[:12]
            self.view.clear_clip()
            self.view.frame_points(near)
        else:
            self.view.frame_simplex(samples)

    # -- picking ---------------------------------------------------------------------
    def _on_press(self, *_) -> None:
        self._press = tuple(self.plotter.iren.interactor.GetEventPosition())

    def _on_release(self, *_) -> None:
        pos = tuple(self.plotter.iren.interactor.GetEventPosition())
        if self._press is None or abs(pos[0] - self._press[0]) + abs(pos[1] - self._press[1]) > 4:
            return
        self.pick_at(*pos)

    def pick_at(self, x: int, y: int):
        """Select what is under VTK display position ``(x, y)``; returns it."""
        got = self.view.pick(x, y)
        sel = self.model.selection
        if got is None:
            sel.clear()
        elif got[0] == "sample":
            sel.select_sample(got[1])
        elif got[0] == "face":
            sel.select_face(got[1])
        else:
            sel.select_simplex(got[1])
        return got

    # -- closing ----------------------------------------------------------------------
    def closeEvent(self, event) -> None:  # noqa: N802 - Qt API
        app = QApplication.instance()
        if app is not None:
            app.removeEventFilter(self)
        self.model.player.pause()
        self.model.tour.pause()
        self.runner.shutdown()
        self.shutdown_tasks()
        self.plotter.close()
        super().closeEvent(event)
