"""File menu behaviour of the main window: open, built-ins, recent, save, drop."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
from PySide6.QtCore import QSettings
from PySide6.QtGui import QAction
from PySide6.QtWidgets import QFileDialog, QMenu

from ..core.analysis.dimension import estimate_file_dimension
from ..core.errors import CrustviewError
from ..scene.truth import MeshTruth
from .dialogs import BuiltinDialog, ask_dimension, ask_overwrite_input
from .running import d_doubt

MAX_RECENT = 8


def _read_suffixes() -> tuple[str, ...]:
    from .. import io

    return tuple(io.READ_SUFFIXES)


def builtin_description(truth) -> dict | None:
    """How a built-in sample was drawn (stored in a saved result), or None for other data."""
    m = getattr(truth, "manifold", None)
    if m is None or not hasattr(truth, "seed"):
        return None
    return {
        "name": m.name,
        "n": len(truth.points),
        "seed": truth.seed,
        "noise": truth.noise,
        "density": truth.density,
        "method": truth.method,
    }


def builtin_truth(info: dict, points: np.ndarray):
    """The built-in ``Sample`` a saved result came from, for its true topology.

    The sample is drawn again as it was saved; when that gives the saved
    points (the sampler is deterministic), its true tangents come with it.
    Otherwise the saved points stand with the manifold and no tangents.
    Returns None for a name crustview does not know.
    """
    from ..core.samples.manifolds import get_manifold
    from ..core.samples.sampling import Sample

    try:
        m = get_manifold(info["name"])
    except Exception:  # noqa: BLE001 - a name from another version: no truth
        return None
    opts = {key: info[key] for key in ("noise", "density", "method") if key in info}
    if info.get("seed") is not None and info.get("n") == len(points) and m.k == points.shape[1]:
        try:
            again = m.sample(int(info["n"]), seed=int(info["seed"]), **opts)
        except Exception:  # noqa: BLE001
            again = None
        if again is not None and np.array_equal(again.points, points):
            return again
    return Sample(
        points=points,
        tangents=None,
        manifold=m,
        seed=info.get("seed"),
        noise=info.get("noise", 0.0),
        density=info.get("density", "uniform"),
        method=info.get("method", "even"),
    )


def with_filter_suffix(path: str, chosen: str) -> str:
    """``path`` with the suffix of the dialog's chosen filter ("NPZ (*.npz)") when it has none of its own.

    A name typed without a suffix under the selected NPZ filter was refused ("unsupported file type (no
    suffix)"), where the screenshot dialog adds its ".png"; a suffix the user typed is kept as typed.
    """
    import re

    if Path(path).suffix:
        return path
    found = re.search(r"\*(\.[A-Za-z0-9]+)", chosen or "")
    return path + found.group(1) if found else path


def _result_suffixes() -> tuple[str, ...]:
    from .. import io

    return tuple(io.RESULT_SUFFIXES)


#: Most faces of a mesh file drawn as its ground truth when it opens (a denser one starts hidden).
TRUTH_SHOWN_FACES = 30_000


class FileActions:
    """Mixin of :class:`~crustview.qt.window.MainWindow`: opening files and built-ins.

    Needs ``settings``, ``model``, ``show_error``, ``start_job`` and ``statusBar``.
    """

    settings: QSettings
    recent_menu: QMenu

    # -- opening -----------------------------------------------------------------
    def open_dialog(self) -> None:
        pattern = " ".join(f"*{s}" for s in _read_suffixes())
        path, _ = QFileDialog.getOpenFileName(
            self, "Open point file", self._last_dir(), f"Point files ({pattern});;All files (*)"
        )
        if path:
            self.open_file(path)

    def open_file(
        self, path: str | os.PathLike, d: int | None = None, mode: str | None = None, run: dict | None = None
    ) -> bool:
        """Read a point file and start its reconstruction.

        When ``d`` is None the user is asked, with a local-PCA suggestion.
        ``mode`` ("robust" or "paper") overrides the Run panel's extraction
        mode and the one saved in a result ``.npz``.
        ``run`` (``test``, ``theta``, ``prune_boundary``) overrides the saved
        or shown run parameters (a session).  A ``*.crustview.json`` path
        opens that session.
        Returns False when the file could not be used (the error is shown and
        the current result stays).
        """
        from .. import io
        from ..session import file_source, is_session_path

        path = str(path)
        if is_session_path(path):
            return self.open_session(path)
        if self.runner.busy:
            self.show_error("A reconstruction is already running; cancel it first.")
            return False
        if Path(path).parent.is_dir():  # the next dialog starts here, even when this file is refused
            self.settings.setValue("last_dir", str(Path(path).parent))
        try:
            read_notes: list[str] = []  # e.g. a text file's header line of column names, a flat mesh's z dropped
            mesh = io.read_mesh(path, read_notes)  # a mesh with faces: vertices are the sample, faces the truth
            points = mesh.points if mesh is not None else io.read_points(path, read_notes)
            attributes = io.read_attributes(path)  # colours, intensity, normals (PLY and scanner formats)
            saved = io.read_run_parameters(path)
            origin = file_source(path)  # size and SHA-1 as read, for a session
        except CrustviewError as err:
            self.show_error(str(err))
            return False
        except Exception as err:  # noqa: BLE001 - reader bug: still one sentence
            self.show_error(f"Cannot read '{path}' ({type(err).__name__}: {err}).")
            return False
        points = np.asarray(points, dtype=float)
        k = points.shape[1]
        if k < 2:
            self.show_error(f"'{path}' holds points with {k} coordinate; at least 2 are needed.")
            return False
        self._add_recent(path)
        name = Path(path).name
        if self.model.rec is None:  # nothing shown yet: the raw points, while d is asked and the run goes
            self.view.show_preview(points)
        params: dict = {}
        note = ""
        if saved is not None:
            # a saved result: redo its run (deterministic), no question; a d given
            # on top changes only d
            params = {"test": saved["test"], "theta": saved["theta"], "prune_boundary": saved["prune_boundary"]}
            params["normals"] = saved.get("normals", "paper")  # its own planes, whatever the Run panel has
            if not saved.get("labelling", True):  # grown on request (the API's labelling=False): grown again
                params["labelling"] = False
            if saved.get("mode") is not None:  # "paper" for files saved before the robust extraction
                params["mode"] = str(saved["mode"])
            if d is None:
                d = saved["d"]
            elif d != saved["d"]:
                note = (
                    f"{name} was saved with d = {saved['d']}; reconstructing with d = {d}, "
                    f"keeping its test ({saved['test']}) and θ = {np.degrees(saved['theta']):.1f}°."
                )
        if run:
            params.update(run)
        if mode is not None:
            if saved is not None and saved.get("mode") not in (None, mode) and not note:
                note = f"{name} was saved in {saved['mode']} mode; reconstructing in {mode} mode as asked."
            params["mode"] = mode
        asked = False  # d asked here, with the estimate shown; otherwise a d given is checked against it
        if d is not None and not 1 <= d < k:
            self.statusBar().showMessage(f"d = {d} is not possible for points in R^{k}; choose 1 … {k - 1}.", 10000)
            d = None
        if d is None:
            try:
                estimate = estimate_file_dimension(points, mesh)  # local PCA (a mesh's faces overrule it)
            except CrustviewError as err:  # e.g. too few distinct points to tell: one line, nothing changed
                self.show_error(str(err))
                return False
            d = ask_dimension(self, k, estimate.d, name, estimate.sentence())
            asked = True
            if d is None:
                self.statusBar().showMessage("Opening cancelled: no dimension given.", 5000)
                return False
        truth = None
        if saved is not None and saved.get("builtin"):
            truth = builtin_truth(saved["builtin"], points)  # the expected topology comes back
        stored = None if saved is None else saved.get("mesh")  # a mesh's faces written with the result
        if mesh is None and stored is not None and stored[1].shape[1] == int(d) + 1:
            truth = MeshTruth(points, stored[1], stored[0])
        if mesh is not None:
            try:
                truth = MeshTruth(points, mesh.simplices(int(d)), name)
            except CrustviewError as err:  # with what was read: a flat mesh's points are in R^2
                self.show_error(" ".join([str(err), *read_notes]))
                return False
        self.model.file_attributes = attributes
        self.input_path = path  # saving over it asks first
        if attributes.get("colors") is not None:
            self.model.layers["points"].colorby = "file colours"
        elif attributes.get("normals") is not None:
            self.model.layers["points"].colorby = "file normal angle"
        doubt = None if asked else d_doubt(points, int(d), mesh)
        if doubt:
            read_notes.append(doubt)  # said with the result
        if self.model.rec is not None and not self.runner.busy:
            self._shelve_shown(points, name)  # the last file's result aside while this one runs
        if not self.start_reconstruction(points, int(d), truth=truth, source=name, origin=origin, **params):
            return self._put_back_shelved() or False
        if mesh is not None:  # the mesh's faces shown with its result, not over the last file's while it runs
            faces = len(truth.faces)
            # a dense wireframe on top would grey the whole result out (the armadillo's 86,482 faces)
            self._pending["show_truth"] = faces <= TRUTH_SHOWN_FACES
            if faces > TRUTH_SHOWN_FACES:
                self._pending["truth_note"] = (
                    f"The mesh's {faces:,} faces are not drawn (Layers ▸ Ground truth shows them)."
                )
        if note:
            self.statusBar().showMessage(note, 20000)
        elif saved is not None:
            self._pending["saved"] = (saved["simplices"], name)
        if read_notes:  # said with the result, in the status bar
            self._pending["notes"] = read_notes
        return True

    def open_builtin_dialog(self) -> None:
        dlg = BuiltinDialog(
            self, current=getattr(self.model.truth, "manifold", None) and self.model.truth.manifold.name or "torus"
        )
        if dlg.exec():
            name, n, seed = dlg.values()
            self.model.file_attributes, self.input_path = {}, None
            self.load_builtin(name, n, seed)

    # -- recent files -----------------------------------------------------------------
    def recent_files(self) -> list[str]:
        value = self.settings.value("recent", [])
        if isinstance(value, str):
            value = [value]
        return [str(v) for v in (value or [])]

    def _shelve_shown(self, points: np.ndarray, name: str) -> None:
        """Set the shown result aside (render/shelf.py) and preview ``points``.

        It comes back if the run fails or is cancelled (``_put_back_shelved``); its result replaces it.
        """
        from ..render.camera import camera_state
        from ..render.shelf import shelve

        if getattr(self.view, "shelved", None) is not None:
            return
        points_layer = self.model.layers["points"]
        self._shelved_state = {
            "title": self.windowTitle(),
            "banner": not self.info_panel.banner.isHidden(),
            "camera": camera_state(self.plotter),
            "points": (points_layer.count, points_layer.total, points_layer.note),
            "counts": self.status_counts.text(),
        }
        shelve(self.view)
        self.status_counts.setText(f"n = {len(points)} · reconstructing…")  # not the last file's counts
        self.setWindowTitle(f"crustview — {name}: reconstructing…")
        for panel in (self.info_panel, self.steps_panel, self.layers_panel):  # what they show is set aside
            panel.setEnabled(False)
        self.info_panel.banner.setVisible(False)  # its own colours: the last file's verdict would stay red
        self.view.show_preview(points)

    def _add_recent(self, path: str) -> None:
        path = str(Path(path).resolve())
        items = [p for p in self.recent_files() if p != path]
        self.settings.setValue("recent", [path] + items[: MAX_RECENT - 1])
        self._fill_recent()

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        files = self.recent_files()
        for p in files:
            act = QAction(Path(p).name, self.recent_menu)
            act.setToolTip(p)
            act.setStatusTip(p)
            act.triggered.connect(lambda _=False, p=p: self.open_file(p))
            self.recent_menu.addAction(act)
        self.recent_menu.setEnabled(bool(files))

    def _last_dir(self) -> str:
        return str(self.settings.value("last_dir", str(Path.home())))

    def suggested_path(self, ending: str) -> str:
        """A file name for saving, in the last folder used: the data's name plus ``ending``."""
        stem = re.sub(r"\s*\(.*\)$", "", self.model.source or "crustview")  # "torus (n = 1500)" -> "torus"
        stem = Path(stem).stem or "crustview"
        stem = re.sub(r"[^\w.-]+", "-", stem).strip("-") or "crustview"
        return str(Path(self._last_dir()) / f"{stem}{ending}")

    def pending_change(self) -> str:
        """What the run panel would change on Re-extract, in words ('' when nothing)."""
        rec = self.model.rec
        if rec is None or (self.model.test, self.model.theta) == (rec.test, float(rec.theta)):
            return ""
        return (
            f"the shown test {self.model.test}, θ = {np.degrees(self.model.theta):.1f}° is not extracted yet; "
            f"the saved result is {rec.test}, θ = {np.degrees(rec.theta):.1f}° (press Re-extract to save the other)"
        )

    # -- saving ---------------------------------------------------------------------
    def save_result_dialog(self) -> None:
        if self.model.rec is None:
            self.show_error("There is no result to save yet.")
            return
        filters = ";;".join(f"{s[1:].upper()} (*{s})" for s in _result_suffixes())
        path, chosen = QFileDialog.getSaveFileName(self, "Save result", self.suggested_path("-crust.npz"), filters)
        if path:
            self.save_result(with_filter_suffix(path, chosen))

    def save_result(self, path: str, ask: bool = True) -> bool:
        from .. import io

        source = getattr(self, "input_path", None)
        if ask and source and Path(source).exists() and Path(path).exists() and os.path.samefile(source, path):
            if not ask_overwrite_input(self, path):
                self.statusBar().showMessage(f"Not saved: {path} is the input file.", 10000)
                return False
        try:
            truth = self.model.truth
            mesh = (truth.name, truth.faces) if isinstance(truth, MeshTruth) else None
            io.write_result(path, self.model.rec, builtin=builtin_description(truth), mesh=mesh)
        except CrustviewError as err:
            self.show_error(str(err))
            return False
        except OSError as err:
            self.show_error(f"Cannot write '{path}': {err.strerror or err}.")
            return False
        self.settings.setValue("last_dir", str(Path(path).parent))
        pending = self.pending_change()
        if pending:
            self.statusBar().showMessage(f"Saved {path}, but {pending}.", 30000)
        else:
            self.statusBar().showMessage(f"Saved {path}", 5000)
        return True

    def save_screenshot_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(
            self, "Save screenshot", self.suggested_path(f"-step{self.model.player.position}.png"), "PNG image (*.png)"
        )
        if path:
            self.save_screenshot(path)

    def save_screenshot(self, path: str) -> bool:
        if not path.lower().endswith(".png"):
            path += ".png"
        try:
            import imageio.v3 as iio

            from ..atomic import atomic_path

            img = self.plotter.screenshot(None, return_img=True)
            with atomic_path(path) as tmp:  # a failed write leaves an earlier screenshot as it was
                iio.imwrite(tmp, img, extension=".png")
        except Exception as err:  # noqa: BLE001 - e.g. no OpenGL context
            from ..io import _reason

            self.show_error(f"Cannot save the screenshot '{path}': {_reason(err)}.")
            return False
        self.settings.setValue("last_dir", str(Path(path).parent))
        self.statusBar().showMessage(f"Saved {path}", 5000)
        return True

    # -- drag and drop -----------------------------------------------------------------
    def dragEnterEvent(self, event) -> None:  # noqa: N802 - Qt API
        if event.mimeData().hasUrls() and any(u.isLocalFile() for u in event.mimeData().urls()):
            event.acceptProposedAction()

    def dropEvent(self, event) -> None:  # noqa: N802
        files = [u.toLocalFile() for u in event.mimeData().urls() if u.isLocalFile()]
        if files:
            event.acceptProposedAction()
            self.open_file(files[0])
