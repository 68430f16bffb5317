"""File ▸ Save session… / Open session…: the window's state to a ``*.crustview.json`` file and back.

The file format and its checks are in :mod:`crustview.session` (no Qt);
this mixin only gathers the window's state and restores it.
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from PySide6.QtWidgets import QFileDialog, QMenu

from ..render.camera import camera_state, set_camera_state
from ..session import (
    LAYER_FIELDS,
    SUFFIX,
    BuiltinSource,
    FileSource,
    Session,
    SessionError,
    read_session,
    resolve_input,
    session_path,
    write_session,
)


class SessionActions:
    """Mixin of :class:`~crustview.qt.window.MainWindow`: saving and opening sessions.

    Needs ``model``, ``plotter``, ``view``, ``origin``, ``runner``,
    ``show_error``, ``open_file``, ``load_builtin``, ``settings``,
    ``suggested_path``, ``statusBar`` and ``_action``.
    """

    def add_session_actions(self, menu: QMenu) -> None:
        """The two session entries of the File menu."""
        self._action(
            menu,
            "Save sess&ion…",
            self.save_session_dialog,
            "Ctrl+Shift+S",
            f"Save the input, the run's parameters, camera, projection, layers and step to a {SUFFIX} file",
        )
        self._action(
            menu,
            "Open sessio&n…",
            self.open_session_dialog,
            "Ctrl+Shift+O",
            f"Reopen a {SUFFIX} file: reconstruct its input again and restore its view",
        )

    # -- saving ---------------------------------------------------------------------
    def current_session(self, path: str | os.PathLike | None = None) -> Session:
        """The window's state as a :class:`Session` (``path``: where it will be written).

        Raises
        ------
        SessionError
            When there is nothing to save, or the data came from neither a file
            nor a built-in (arrays given to the API), so a session could not reopen it.
        """
        rec = self.model.rec
        if rec is None:
            raise SessionError("there is no result to save in a session yet")
        origin = self.origin
        if origin is None:
            raise SessionError(
                "this data was read from neither a file nor a built-in sample, so a session "
                "could not reopen it; save the points to a file first"
            )
        if isinstance(origin, FileSource) and path is not None:
            try:
                rel = os.path.relpath(origin.path, Path(path).resolve().parent)
            except ValueError:  # another drive (Windows)
                rel = ""
            origin = dataclasses.replace(origin, relative=rel)
        m = self.model
        layers = {name: {f: getattr(layer, f) for f in LAYER_FIELDS} for name, layer in m.layers.items()}
        return Session(
            origin,
            rec.d,
            rec.test,
            float(rec.theta),
            bool(rec.prune_boundary),
            rec.mode,
            int(m.player.position),
            camera_state(self.plotter),
            m.projection.state(),
            layers,
            {"offset": float(m.slice_offset), "cut": bool(m.slice_cut)},
            float(m.player.speed),
            self._selection_state(),
            dict(m.comparison.spec) if m.comparison is not None and m.comparison.spec else None,
            getattr(rec, "normals_method", "paper"),
        )

    def _selection_state(self) -> dict | None:
        """The selection as sample indices (a simplex by its samples, the same in every run of the input)."""
        m = self.model
        sel = m.selection
        if sel.sample is None and sel.simplex is None and sel.face is None:
            return None
        simplex = None if sel.simplex is None else [int(v) for v in m.rec.candidates.faces[sel.simplex]]
        return {
            "sample": None if sel.sample is None else int(sel.sample),
            "simplex": simplex,
            "face": None if sel.face is None else [int(v) for v in sel.face],
        }

    def _restore_selection(self, state: dict | None, notes: list[str]) -> None:
        from ..scene import geometry as geo

        m = self.model
        rec = m.rec
        if not state:
            return
        bad = [v for v in (state["sample"], *(state["simplex"] or ()), *(state["face"] or ())) if v is not None]
        if any(v >= rec.n for v in bad):
            notes.append("the selection names samples this input does not have")
            return
        if state["simplex"] is not None:
            row = int(geo.find_rows(rec.candidates.faces, [state["simplex"]])[0])
            if row >= 0:
                m.selection.select_simplex(row)
            else:
                notes.append("the selected simplex is not a Delaunay face here")
        if state["face"] is not None:
            m.selection.select_face(tuple(sorted(state["face"])))
        if state["sample"] is not None:
            m.selection.select_sample(int(state["sample"]))

    def save_session_dialog(self) -> None:
        if self.model.rec is None:
            self.show_error("There is nothing to save in a session yet.")
            return
        path, _ = QFileDialog.getSaveFileName(
            self, "Save session", self.suggested_path(SUFFIX), f"crustview session (*{SUFFIX})"
        )
        if path:
            self.save_session(path)

    def save_session(self, path: str | os.PathLike) -> Path | None:
        """Write the session; returns the file written (its name ends in ``.crustview.json``), or None."""
        target = session_path(path)
        try:
            written = write_session(target, self.current_session(target))
        except SessionError as err:
            self.show_error(f"Cannot save the session: {err}.")
            return None
        except OSError as err:
            self.show_error(f"Cannot write '{target}': {err.strerror or err}.")
            return None
        self.settings.setValue("last_dir", str(written.parent))
        pending = self.pending_change()  # a θ or test shown but not extracted: the session keeps the run's
        if pending:
            self.statusBar().showMessage(f"Saved session {written}, but {pending}.", 30000)
        else:
            self.statusBar().showMessage(f"Saved session {written}", 5000)
        return written

    # -- opening --------------------------------------------------------------------
    def open_session_dialog(self) -> None:
        path, _ = QFileDialog.getOpenFileName(
            self, "Open session", self._last_dir(), f"crustview session (*{SUFFIX});;All files (*)"
        )
        if path:
            self.open_session(path)

    def open_session(self, path: str | os.PathLike) -> bool:
        """Reconstruct a session's input and, when that is done, restore its view.

        Returns False (with a one-line message) when the file is malformed, of
        another version, or its input file moved or changed; the current
        result stays.
        """
        if self.runner.busy:
            self.show_error("A reconstruction is already running; cancel it first.")
            return False
        note = ""
        try:
            s = read_session(path)
            if isinstance(s.source, FileSource):
                found, note = resolve_input(s.source, path)
        except SessionError as err:
            self.show_error(f"Cannot open the session: {err}.")
            return False
        run = {"test": s.test, "theta": s.theta, "prune_boundary": s.prune_boundary}
        box = self.run_panel.normals  # the run reads the panel's planes
        box.setCurrentIndex(max(0, box.findData(s.normals)))
        if isinstance(s.source, BuiltinSource):
            ok = self.load_builtin(s.source.name, s.source.n, s.source.seed, mode=s.mode, **run)
        else:
            ok = self.open_file(found, s.d, mode=s.mode, run=run)
        if ok:
            self._pending["session"] = (s, Path(path).name, note)
            self.settings.setValue("last_dir", str(Path(path).resolve().parent))
        return ok

    def restore_view(self, s: Session, name: str = "", note: str = "") -> list[str]:
        """Apply a session's layers, projection, slice, step and camera to the shown result.

        Returns the notes (what could not be restored); they are also shown in the status bar.
        """
        m = self.model
        notes = [note] if note else []
        for lname, style in s.layers.items():
            layer = m.layers.get(lname)
            if layer is None:
                notes.append(f"layer '{lname}' is unknown here")
                continue
            for f, v in style.items():
                if f == "colorby" and layer.colorings and v not in layer.colorings:
                    notes.append(f"colouring '{v}' of {lname} is unknown here")
                    continue
                setattr(layer, f, float(v) if f in ("opacity", "size", "shrink") else v)
        if s.projection is not None:
            try:
                m.projection.restore(s.projection)
            except ValueError as err:
                notes.append(str(err))
        if s.slice is not None:
            m.set_slice(s.slice["offset"], s.slice["cut"])
        n = m.player.n_steps
        if s.step > n:
            notes.append(f"step {s.step} is past the last step ({n}) of this run")
        m.player.set_step(min(s.step, n))
        self.steps_panel.speed.setValue(s.speed)
        self._restore_selection(s.selection, notes)
        if s.camera is not None:
            try:
                set_camera_state(self.plotter, s.camera)
            except ValueError as err:
                notes.append(str(err))
        if s.comparison is not None:  # made again in the worker, as when it was first asked for
            if not self.info_panel.compare.start(s.comparison):
                notes.append("the comparison could not be started again")
        self.view.render()
        text = f"Session {name} restored" + (f" ({'; '.join(notes)})" if notes else "") + "."
        self.statusBar().showMessage(text, 20000)
        return notes
