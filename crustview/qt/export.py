"""File ▸ Export animation…: a replay or a grand tour of the window's scene to GIF, MP4 or PNGs.

The frames are drawn by :class:`crustview.animation.OffscreenScene` (the
code ``crustview render`` uses) from a clone of the window's model
(:func:`~crustview.animation.clone_scene`: result, layers, colours,
projection, slice, comparison and step) with the window's camera.  The
window's own view is not touched.  Frames are rendered one per event-loop
turn on the GUI thread (VTK's OpenGL contexts belong to it), so the
window stays responsive; a progress dialog's Cancel stops between two
frames and drops the temporary file.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PySide6.QtCore import QObject, Qt, QTimer, Signal
from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMenu,
    QProgressDialog,
    QPushButton,
    QSpinBox,
    QWidget,
)

from ..animation import DEFAULT_BUDGET, FrameWriter, OffscreenScene, clone_scene, even_size, plan_replay
from ..render.camera import camera_state, set_camera_state

#: Formats offered, with the ending they give the path (a folder has none).
FORMATS = {"GIF": ".gif", "MP4 (H.264)": ".mp4", "PNG folder": ""}


@dataclass
class ExportOptions:
    """What to export.

    Attributes
    ----------
    path : str
        ``.gif``, ``.mp4`` or a folder.
    kind : str
        ``"replay"`` or ``"tour"``.
    first, last : int
        Replay: the step range (both included).
    frames : int
        Replay: the frame budget (longer ranges are subsampled); tour: its length.
    size : (int, int)
    fps : float
    """

    path: str
    kind: str = "replay"
    first: int = 0
    last: int = 0
    frames: int = DEFAULT_BUDGET
    size: tuple[int, int] = (640, 480)
    fps: float = 12.0


class ExportDialog(QDialog):
    """The options of an export, with the window's step range and view size as defaults."""

    def __init__(self, parent: QWidget, n_steps: int, step: int, suggested: str) -> None:
        super().__init__(parent)
        self.setWindowTitle("Export animation")
        form = QFormLayout(self)
        self.kind = QComboBox(self)
        self.kind.addItem("replay of Algorithm 3's steps", "replay")
        self.kind.addItem("grand tour of R^k (M_S at this step)", "tour")
        form.addRow("animation", self.kind)
        self.first, self.last = QSpinBox(self), QSpinBox(self)
        for w, v in ((self.first, 0), (self.last, n_steps)):
            w.setRange(0, n_steps)
            w.setValue(v)
        steps = QHBoxLayout()
        steps.addWidget(self.first)
        steps.addWidget(QLabel("to", self))
        steps.addWidget(self.last)
        form.addRow("steps", steps)
        self.frames = QSpinBox(self)
        self.frames.setRange(2, 5000)
        self.frames.setValue(DEFAULT_BUDGET)
        self.frames.setToolTip(
            "Replay: at most this many frames (a longer range is subsampled evenly; the "
            "caption says which steps); tour: its number of frames"
        )
        form.addRow("frames (budget)", self.frames)
        self.format = QComboBox(self)
        self.format.addItems(list(FORMATS))
        form.addRow("format", self.format)
        self.path = QLineEdit(suggested, self)
        browse = QPushButton("Browse…", self)
        browse.clicked.connect(self._browse)
        row = QHBoxLayout()
        row.addWidget(self.path, 1)
        row.addWidget(browse)
        form.addRow("file", row)
        self.width_, self.height_ = QSpinBox(self), QSpinBox(self)
        for w, v in ((self.width_, 640), (self.height_, 480)):
            w.setRange(16, 4096)
            w.setValue(v)
        size = QHBoxLayout()
        size.addWidget(self.width_)
        size.addWidget(QLabel("×", self))
        size.addWidget(self.height_)
        form.addRow("size (pixels)", size)
        self.fps = QDoubleSpinBox(self)
        self.fps.setRange(0.5, 60.0)
        self.fps.setValue(12.0)
        form.addRow("frames per second", self.fps)
        self.note = QLabel(self)
        self.note.setWordWrap(True)
        form.addRow(self.note)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel, self)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.n_steps, self.step = n_steps, step
        for sig in (
            self.kind.currentIndexChanged,
            self.first.valueChanged,
            self.last.valueChanged,
            self.frames.valueChanged,
            self.format.currentIndexChanged,
        ):
            sig.connect(self._changed)
        self._changed()

    def _changed(self, *_) -> None:
        replay = self.kind.currentData() == "replay"
        self.first.setEnabled(replay)
        self.last.setEnabled(replay)
        ending = FORMATS[self.format.currentText()]
        p = Path(self.path.text().strip() or "animation")
        stem = p.name[: -len(p.suffix)] if p.suffix.lower() in (".gif", ".mp4") else p.name
        self.path.setText(str(p.with_name(stem + ending)))
        if replay:
            lo, hi = sorted((self.first.value(), self.last.value()))
            plan = plan_replay(self.n_steps, (lo, hi), self.frames.value())
            self.note.setText(f"{plan.note()}." if plan.subsampled else f"{len(plan.positions)} frames: {plan.note()}.")
        else:
            self.note.setText(
                f"{self.frames.value()} frames of the grand tour around M_S at step {self.step}, "
                f"{self.frames.value() / self.fps.value():.1f} s."
            )

    def _browse(self) -> None:
        ending = FORMATS[self.format.currentText()]
        if not ending:
            path = QFileDialog.getExistingDirectory(self, "Folder for the PNG frames", self.path.text())
        else:
            path, _ = QFileDialog.getSaveFileName(self, "Export animation", self.path.text(), f"*{ending}")
        if path:
            self.path.setText(path)
            self._changed()

    def options(self) -> ExportOptions:
        lo, hi = sorted((self.first.value(), self.last.value()))
        return ExportOptions(
            self.path.text().strip(),
            self.kind.currentData(),
            lo,
            hi,
            self.frames.value(),
            (self.width_.value(), self.height_.value()),
            self.fps.value(),
        )


class AnimationExport(QObject):
    """One export in progress: a frame per event-loop turn, a progress dialog, Cancel.

    Emits :attr:`finished` once with ``(ok, message)``; after a cancel or an
    error no output file is left (its temporary file is dropped).
    """

    finished = Signal(bool, str)

    def __init__(self, window, options: ExportOptions) -> None:
        super().__init__(window)
        self.options = options
        model = clone_scene(window.model)
        size = even_size(options.size) if options.path.lower().endswith(".mp4") else options.size
        self.writer = FrameWriter(options.path, options.fps, 1)  # checks the ending first
        self.scene = OffscreenScene(model, size)
        set_camera_state(self.scene.plotter, camera_state(window.plotter))
        if options.kind == "replay":
            plan = plan_replay(model.rec.extraction.n_steps, (options.first, options.last), options.frames)
            self.total = len(plan.positions)
            self.frames = self.scene.replay(plan)
            self.what = plan.note()
        else:
            self.total = options.frames
            self.frames = self.scene.tour(options.frames, options.fps)
            self.what = f"{options.frames} frames of the grand tour"
        self.writer.total = self.total
        self.cancelled = False
        self.done = False
        self.dialog = QProgressDialog(f"Rendering {self.what}…", "Cancel", 0, self.total, window)
        self.dialog.setWindowTitle("Export animation")
        self.dialog.setWindowModality(Qt.WindowModality.WindowModal)
        self.dialog.setMinimumDuration(0)
        self.dialog.setAutoClose(False)
        self.dialog.setAutoReset(False)
        self.dialog.canceled.connect(self.cancel)
        self.dialog.setValue(0)
        self.timer = QTimer(self)
        self.timer.setInterval(0)
        self.timer.timeout.connect(self._tick)
        self.timer.start()

    def cancel(self) -> None:
        """Stop before the next frame and remove what was written."""
        if not self.done:
            self.cancelled = True
            self._end(False, "Export cancelled; no file was left.")

    def _tick(self) -> None:
        if self.done:
            return
        try:
            img = next(self.frames, None)
            if img is None:
                path = self.writer.finish()
                self._end(True, f"Exported {self.writer.count} frames to {path} ({self.what}).", abort=False)
                return
            self.writer.append(img)
        except Exception as err:  # noqa: BLE001 - an encoder or disk error: one sentence, no file left
            self._end(False, f"The export failed ({type(err).__name__}: {err}); no file was left.")
            return
        self.dialog.setValue(self.writer.count)
        self.dialog.setLabelText(f"Rendering {self.what}: frame {self.writer.count} of {self.total}")

    def _end(self, ok: bool, message: str, abort: bool = True) -> None:
        self.done = True
        self.timer.stop()
        if abort:
            self.writer.abort()
        self.scene.close()
        self.dialog.blockSignals(True)
        self.dialog.close()
        self.finished.emit(ok, message)


class ExportActions:
    """Mixin of :class:`~crustview.qt.window.MainWindow`: the export and compare menu entries.

    It also stops the background tasks when the window closes.
    """

    export: AnimationExport | None = None

    def add_tool_actions(self, menu: QMenu) -> None:
        self._action(
            menu,
            "E&xport animation…",
            self.export_dialog,
            "Ctrl+Shift+E",
            "A replay of the steps or a grand tour to GIF, MP4 or PNGs, as the view shows it",
        )
        self._action(
            menu,
            "Co&mpare with…",
            self.compare_dialog,
            "Ctrl+Shift+C",
            "Compare M_S with a saved result, a mesh file's faces or another run",
        )

    def compare_dialog(self) -> None:
        if self.model.rec is None:
            self.show_error("There is no result to compare yet.")
            return
        self.docks["info"].show()
        self.docks["info"].raise_()
        self.info_panel.compare.ask()

    def frame_compared(self, vertices) -> None:
        """Frame a simplex listed by the comparison, and select it when it is a candidate of T_S."""
        from ..scene.geometry import find_rows

        rec = self.model.rec
        if rec is None:
            return
        row = int(find_rows(rec.candidates.faces, np.sort(np.asarray(vertices))[None])[0])
        if row >= 0:
            self.model.selection.select_simplex(row)
        self.view.frame_simplex(vertices)

    def export_dialog(self) -> None:
        if self.model.rec is None:
            self.show_error("There is no result to export yet.")
            return
        p = self.model.player
        dlg = ExportDialog(self, p.n_steps, p.position, self.suggested_path("-replay.gif"))
        if dlg.exec():
            self.export_animation(dlg.options())

    def export_animation(self, options: ExportOptions) -> AnimationExport | None:
        """Start exporting (see :class:`AnimationExport`); None (with a message) when it cannot start."""
        if self.export is not None and not self.export.done:
            self.show_error("An export is already running.")
            return None
        try:
            job = AnimationExport(self, options)
        except (ValueError, OSError) as err:
            self.show_error(f"Cannot export: {err}.")
            return None
        job.finished.connect(self._export_finished)
        self.export = job
        return job

    def _export_finished(self, ok: bool, message: str) -> None:
        if not ok and "failed" in message:
            self.show_error(message)
        else:  # done, or cancelled by the user: no dialog needed
            self.statusBar().showMessage(message, 20000 if ok else 10000)

    def shutdown_tasks(self) -> None:
        """Cancel an export, a theorem check and a comparison (the window is closing)."""
        if self.export is not None and not self.export.done:
            self.export.cancel()
        self.info_panel.theorems.runner.shutdown()
        self.info_panel.compare.runner.shutdown()
