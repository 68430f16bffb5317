"""The main window: 3-D view in the centre, docks around it."""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QEvent, QObject, QSettings, Qt
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

from ..core import cost_warning, reconstruct, reextract
from ..render import SceneView
from ..scene.model import SceneModel
from ..scene.shapes import name_of
from ..session import BuiltinSource
from .export import ExportActions
from .files import FileActions
from .info_dock import InfoPanel
from .layers_dock import LayersPanel
from .layout import DockLayout
from .lod import StepDetail
from .projection_dock import ProjectionPanel
from .run_dock import RunPanel
from .sessions import SessionActions
from .steady import SteadyLabel
from .steps_dock import StepsPanel
from .worker import Runner

DEMO = "torus"


#: How the window names each extraction mode.
MODE_WORDS = {"robust": "robust extraction", "paper": "the paper's Algorithm 3"}


def _scrolled(widget: QWidget) -> QScrollArea:
    area = QScrollArea()
    area.setWidget(widget)
    area.setWidgetResizable(True)
    area.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
    return area


def _quality(rec, progress, cancel=None):
    """The samples' estimated epsilon, computed in the worker with the reconstruction (with progress; cancellable)."""
    from ..core.analysis.quality import sampling_quality

    return sampling_quality(rec, progress=lambda f: progress("quality", f), cancel=cancel)


def _same_simplices(rec, saved: np.ndarray) -> bool:
    """Whether ``rec``'s M_S, in input rows, is the saved simplex list."""
    mine = np.asarray(rec.point_input)[np.asarray(rec.manifold, dtype=np.intp)].reshape(-1, rec.d + 1)
    a = np.unique(np.sort(mine, axis=1), axis=0)
    b = np.unique(np.sort(np.asarray(saved).reshape(-1, rec.d + 1), axis=1), axis=0)
    return a.shape == b.shape and bool((a == b).all())


def _comparing(job, truth, points):
    """``job`` followed, in the worker, by the comparison with a mesh truth (if any)."""
    if truth is None or not hasattr(truth, "compared"):
        return job

    def run(progress, cancel):
        out = job(progress, cancel)  # a Reconstruction, or a dict holding one under "rec"
        progress("compare", 0.0)
        if isinstance(out, dict):
            return {**out, "truth": truth.compared(out["rec"])}
        return {"rec": out, "truth": truth.compared(out), "points": points}

    return run


class MainWindow(DockLayout, SessionActions, ExportActions, FileActions, QMainWindow):
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
        self.view.schedule_render = lambda: QWidget.update(self.plotter)
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
        self.info_panel.compare.simplex_clicked.connect(self.frame_compared)
        self.info_panel.paper_requested.connect(lambda: self.run_panel.set_mode("paper"))
        self.model.player.step_changed.connect(lambda *_: self._update_status())
        self.model.player.step_changed.connect(self._follow_step)
        self.steps_panel.follow.toggled.connect(self._follow_toggled)
        self.model.reconstruction_changed.connect(self._update_status)
        self.model.candidates_changed.connect(lambda *_: self._update_status())

        self._build_menus()
        self.status_counts = SteadyLabel(self)  # a new count per step must not re-lay out the window
        self.statusBar().addPermanentWidget(self.status_counts)
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

    # -- running ----------------------------------------------------------------
    def start_job(self, fn, label: str, **pending) -> bool:
        """Run ``fn(progress, cancel)`` in the worker; ``pending`` is used when it ends."""
        if self.runner.busy:
            self.show_error("A reconstruction is already running; cancel it first.")
            return False
        self._pending = pending
        self.statusBar().showMessage(label)
        return self.runner.start(fn, label)

    def start_reconstruction(
        self,
        points: np.ndarray,
        d: int,
        truth=None,
        source: str = "",
        test: str | None = None,
        theta: float | None = None,
        prune_boundary: bool | None = None,
        mode: str | None = None,
        origin=None,
    ) -> bool:
        """Reconstruct ``points`` in the worker; ``origin`` is where they came from (for sessions)."""
        test = test or self.run_panel.test.currentText()
        theta = self.run_panel.theta_radians if theta is None else theta
        if prune_boundary is None:
            self._default_prune()
        prune = self.run_panel.prune.isChecked() if prune_boundary is None else bool(prune_boundary)
        mode = mode or self.run_panel.mode

        def job(progress, cancel):
            rec = reconstruct(
                points, d, test=test, theta=theta, prune_boundary=prune, mode=mode, progress=progress, cancel=cancel
            )
            return {"rec": rec, "truth": truth, "points": points, "quality": _quality(rec, progress, cancel)}

        job = _comparing(job, truth, points)

        note = cost_warning(points.shape[1], d)
        if note:
            self.show_error(note + " Cancel stops it at any time.")

        return self.start_job(
            job,
            f"Reconstructing {source} (d = {d})…",
            points=points,
            truth=truth,
            source=source,
            keep_view=False,
            origin=origin,
        )

    def load_builtin(
        self,
        name: str,
        n: int | None = None,
        seed: int = 0,
        test: str | None = None,
        theta: float | None = None,
        prune_boundary: bool | None = None,
        mode: str | None = None,
    ) -> bool:
        """Sample a built-in manifold and reconstruct it (in the worker).

        The run's parameters default to the Run panel's (pruning: on).
        """
        from ..core.samples.manifolds import get_manifold

        try:
            m = get_manifold(name)
        except Exception as err:  # noqa: BLE001
            self.show_error(str(err))
            return False
        n = n or m.default_n
        self._default_prune()
        test = test or self.run_panel.test.currentText()
        theta = self.run_panel.theta_radians if theta is None else float(theta)
        prune = self.run_panel.prune.isChecked() if prune_boundary is None else bool(prune_boundary)
        mode = mode or self.run_panel.mode

        # with nothing on screen yet, sample here (< 0.2 s up to 3000 points) and show the
        # raw points while the reconstruction runs; otherwise all of it runs in the worker
        early = m.sample(n, seed=seed) if self.model.rec is None and n <= 3000 and not self.runner.busy else None
        if early is not None:
            self.view.show_preview(early.points)

        def job(progress, cancel):
            progress("prepare", 0.0)
            sample = early if early is not None else m.sample(n, seed=seed)
            rec = reconstruct(
                sample.points,
                m.d,
                test=test,
                theta=theta,
                prune_boundary=prune,
                mode=mode,
                progress=progress,
                cancel=cancel,
            )
            return {"rec": rec, "truth": sample, "points": sample.points, "quality": _quality(rec, progress, cancel)}

        return self.start_job(
            job,
            f"Sampling and reconstructing {name} (n = {n})…",
            source=f"{name} (n = {n})",
            keep_view=False,
            origin=BuiltinSource(name, int(n), int(seed)),
        )

    def _default_prune(self) -> None:
        """New data starts with the paper's boundary pruning on again, and says so if it was off."""
        box = self.run_panel.prune
        if box.isChecked():
            return
        box.blockSignals(True)
        box.setChecked(True)
        box.blockSignals(False)
        self.prune_note = "Prune boundary faces is on again for the new data (it was off for the last one)."

    def load_demo(self) -> bool:
        return self.load_builtin(DEMO)

    def _reconstruct_requested(self, d: int, test: str, theta: float, prune: bool = True) -> None:
        rec = self.model.rec
        if self.points is None:
            self.show_error("Open a point file or a built-in sample first.")
            self.run_panel.sync_prune()
            return
        mode = self.run_panel.mode
        if rec is not None and rec.d == d:  # same points and d: only Algorithm 3 again

            def job(progress, cancel):
                return reextract(rec, test, theta, prune_boundary=prune, mode=mode, progress=progress, cancel=cancel)

            job = _comparing(job, self.model.truth, self.points)

            label = f"Re-extracting ({MODE_WORDS[mode]}) with {test}, θ = {np.degrees(theta):.1f}°" + (
                f", boundary faces {'pruned' if prune else 'kept'}…" if mode == "paper" else "…"
            )
            if not self.start_job(
                job, label, points=self.points, truth=self.model.truth, source=self.model.source, keep_view=True
            ):
                self.run_panel.sync_prune()
        else:
            self.start_reconstruction(
                self.points,
                d,
                truth=self.model.truth,
                source=self.model.source,
                test=test,
                theta=theta,
                prune_boundary=prune,
                origin=self.origin,
            )

    def _job_done(self, result) -> None:
        pending = self._pending
        if isinstance(result, dict):
            rec, truth, points = result["rec"], result["truth"], result["points"]
        else:
            rec, truth, points = result, pending.get("truth"), pending.get("points")
        self.points = points
        if "origin" in pending:  # new data (a re-extraction keeps the origin)
            self.origin = pending["origin"]
        self.model.set_reconstruction(
            rec,
            truth=truth,
            source=pending.get("source", ""),
            keep_view=bool(pending.get("keep_view")),
            quality=result.get("quality") if isinstance(result, dict) else None,
        )
        t = rec.topology
        verdict = "closed manifold" if t.closed_manifold else f"NOT a closed manifold ({rec.extraction.stopped})"
        expected = truth.manifold if truth is not None else None
        problems = []
        if expected is not None and t.closed_manifold and tuple(t.betti) != tuple(expected.betti):
            problems.append(f"Betti {tuple(t.betti)} ≠ true {tuple(expected.betti)}")
        mesh_cmp = getattr(truth, "comparison", None)
        if mesh_cmp is not None and t.closed_manifold and tuple(t.betti) != tuple(mesh_cmp.mesh_topology.betti):
            problems.append(f"Betti {tuple(t.betti)} ≠ mesh {tuple(mesh_cmp.mesh_topology.betti)}")
        if t.closed_manifold and t.unused_samples:
            problems.append(f"{t.unused_samples} unused")
        if problems:
            verdict = "WRONG: " + ", ".join(problems)
        ok = t.closed_manifold and not problems
        self.run_panel.show_idle(f"{rec.mode}: done in {sum(rec.timings.values()):.2f} s — {verdict}", ok=ok)
        message = (
            f"{self.model.source}: {verdict}; Betti {t.betti}; {rec.extraction.n_steps} steps of "
            f"{MODE_WORDS.get(rec.mode, rec.mode)}."
        )
        saved = pending.get("saved")
        if saved is not None:
            same = _same_simplices(rec, saved[0])
            message += (
                f" Same M_S as saved in {saved[1]}."
                if same
                else f" M_S DIFFERS from the one saved in {saved[1]} (other crustview version?)."
            )
        for extra in pending.get("notes", ()):
            message += " " + extra
        if getattr(self, "prune_note", None):
            message += " " + self.prune_note
            self.prune_note = None
        self.statusBar().showMessage(message, 20000)
        self.setWindowTitle(f"crustview — {self.model.source}: {name_of(t, rec.d)} (d = {rec.d} in R^{rec.k})")
        if pending.get("session") is not None:
            self.restore_view(*pending["session"])

    def _job_failed(self, message: str) -> None:
        self.run_panel.sync_prune()
        self.run_panel.show_idle("failed — previous result kept" if self.model.rec is not None else "failed", ok=False)
        self.show_error(message)

    def _job_cancelled(self) -> None:
        self.run_panel.sync_prune()
        self.run_panel.show_idle("cancelled — previous result kept" if self.model.rec is not None else "cancelled")
        self.statusBar().showMessage("Cancelled; the previous result is still shown.", 10000)

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
        else:
            self.view.clear_clip()
            self.view.render()

    def _follow_step(self, *_) -> None:
        """With "Frame each step" on, look at the step just applied from its open side."""
        step = self.model.player.current_step
        if not self.steps_panel.follow.isChecked() or step is None or self.model.rec is None:
            return
        self.view.frame_step(step)

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
