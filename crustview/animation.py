"""Animations of a scene, rendered off-screen: a replay of Algorithm 3 or a grand tour of R^k.

No Qt: a :class:`pyvista.Plotter` with ``off_screen=True`` renders through
EGL without any display.  The scene is drawn by the viewer's own adapters
(:class:`crustview.render.SceneView`) into that plotter, so layers, colours
and projection look as they do in the window.  The window's File ▸ Export
animation clones its model (:func:`clone_scene`) and uses the same code.

Frames are written by imageio: ``.gif`` (Pillow), ``.mp4`` (the ffmpeg
binary that ships in the ``imageio-ffmpeg`` wheel) or a folder of PNGs.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import AtomicFile, atomic_path
from .scene.model import SceneModel

#: Default frame budget of a replay: longer step ranges are subsampled.
DEFAULT_BUDGET = 90
#: Output kinds by suffix (anything else with no suffix is a folder of PNGs).
KINDS = {".gif": "gif", ".mp4": "mp4"}

Progress = Callable[[int, int], bool | None]  # (done, total) -> False to cancel


@dataclass(frozen=True)
class ReplayPlan:
    """Which steps a replay shows.

    Attributes
    ----------
    positions : list of int
        Player positions, one per frame (position i shows M_S after i steps).
    first, last : int
        The step range asked for.
    total : int
        Steps in the extraction.
    """

    positions: list[int]
    first: int
    last: int
    total: int

    @property
    def subsampled(self) -> bool:
        return len(self.positions) < self.last - self.first + 1

    def note(self) -> str:
        """What the frames show, said on screen."""
        span = self.last - self.first + 1
        if not self.subsampled:
            return f"steps {self.first}-{self.last} of {self.total}, every step"
        every = span / max(len(self.positions), 1)
        return (
            f"steps {self.first}-{self.last} of {self.total}: {len(self.positions)} frames, about every {every:.3g}th"
        )


def parse_steps(text: str | None, total: int) -> tuple[int, int]:
    """``"A:B"`` (either side may be empty, negative counts from the end) to a clipped range."""
    if not text:
        return 0, total
    if ":" not in text:
        raise ValueError(f"--steps takes A:B (e.g. 0:200 or 100:), got {text!r}")
    a, b = text.split(":", 1)
    try:
        lo = int(a) if a.strip() else 0
        hi = int(b) if b.strip() else total
    except ValueError:
        raise ValueError(f"--steps takes integers A:B, got {text!r}") from None
    lo = lo + total if lo < 0 else lo
    hi = hi + total if hi < 0 else hi
    if hi < lo:
        raise ValueError(f"--steps {text}: the range is empty (the extraction has {total} steps)")
    if lo > total:  # clipped, it would be the last step alone: said, not drawn as if asked for
        raise ValueError(f"--steps {text} starts after the last step: the extraction has {total} steps")
    return max(0, min(lo, total)), max(0, min(hi, total))


def plan_replay(total: int, steps: tuple[int, int] | None = None, budget: int = DEFAULT_BUDGET) -> ReplayPlan:
    """Evenly spread at most ``budget`` positions over ``steps`` (both ends included)."""
    lo, hi = steps if steps is not None else (0, total)
    if budget < 2:
        raise ValueError("the frame budget must be at least 2")
    span = hi - lo + 1
    if span <= budget:
        pos = list(range(lo, hi + 1))
    else:
        pos = sorted({int(round(x)) for x in np.linspace(lo, hi, budget)})
    return ReplayPlan(pos, lo, hi, total)


def step_caption(model: SceneModel, position: int) -> str:
    """The caption of a replay frame: the step number, its rule and its reason."""
    ext = model.rec.extraction
    if position == 0:
        alive = int(ext.alive(0).sum())
        if alive == 0 and ext.n_steps:  # a robust run that builds M_S anew: step 0 is empty, as the window says
            return f"step 0 of {ext.n_steps}: M_S empty before the extension's first step (T_S: its own layer)"
        return f"step 0 of {ext.n_steps}: T_S before Algorithm 3 ({alive:,} candidate simplices)"
    s = ext.steps[position - 1]
    reason = s.reason if len(s.reason) <= 90 else s.reason[:87] + "..."
    return f"step {position} of {ext.n_steps}: {s.rule} - {reason}"


def clone_scene(model: SceneModel) -> SceneModel:
    """A new model showing the same result, layers, projection and step (not connected to ``model``)."""
    out = SceneModel()
    rec = model.rec
    assert rec is not None
    out.set_reconstruction(rec, truth=model.truth, source=model.source)
    out.theorems = model.theorems
    out.comparison = model.comparison
    for name, layer in model.layers.items():
        dst = out.layers[name]
        for f in ("visible", "color", "opacity", "size", "colorby", "mode", "shrink"):
            setattr(dst, f, getattr(layer, f))
    out.set_candidate_display(model.test, model.theta)
    out.projection.restore(model.projection.state())
    out.set_slice(model.slice_offset, model.slice_cut)
    out.player.set_step(model.player.position)
    out.player.delivered = model.player.delivered  # drawn clean as the window draws it
    return out


#: Lines of caption above each frame and their height in pixels.
CAPTION_LINES = 2
CAPTION_PX = 16


def caption_band(text: str, width: int, height: int) -> np.ndarray:
    """A white band ``height`` pixels high with ``text`` (up to :data:`CAPTION_LINES` lines) in dark grey."""
    from PIL import Image, ImageDraw, ImageFont

    band = Image.new("RGB", (width, height), (255, 255, 255))
    draw = ImageDraw.Draw(band)
    font = ImageFont.load_default(size=CAPTION_PX - 3)
    for j, line in enumerate(text.splitlines()[:CAPTION_LINES]):
        while line and draw.textlength(line, font=font) > width - 8:
            line = line[:-4] + "..."
        draw.text((4, 3 + j * CAPTION_PX), line, fill=(20, 20, 20), font=font)
    return np.asarray(band)


class OffscreenScene:
    """A model drawn by the viewer's adapters into an off-screen plotter.

    Parameters
    ----------
    model : SceneModel
        With a reconstruction set.
    size : (int, int)
        Frame width and height in pixels.
    camera : pyvista camera position, optional
        ``plotter.camera_position`` to use; default the viewer's initial camera.
    """

    def __init__(self, model: SceneModel, size: tuple[int, int] = (640, 480), camera=None) -> None:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
        import pyvista as pv

        from .render import SceneView

        self.model = model
        self.size = size
        self.band = CAPTION_LINES * CAPTION_PX + 6
        self.plotter = pv.Plotter(off_screen=True, window_size=[size[0], max(size[1] - self.band, 16)])
        self.view = SceneView(model, self.plotter)
        self.view.in_window = False  # no docks or sliders to point at in a file
        # the legend's line spacing is a share of the height: keep its font inside it on small frames
        self.view.legend.font_size = max(8, min(13, int(0.032 * (size[1] - self.band) * 0.8)))
        self.view.legend.entries = []
        self.view.on_reconstruction()
        if camera is not None:
            self.plotter.camera_position = camera

    def frame(self, caption: str) -> np.ndarray:
        """The current scene above a band with ``caption``, as an (h, w, 3) uint8 image."""
        img = np.asarray(self.plotter.screenshot(None, return_img=True))[..., :3]
        return np.concatenate([caption_band(caption, img.shape[1], self.band), img], axis=0)

    def replay(self, plan: ReplayPlan) -> Iterator[np.ndarray]:
        """One frame per planned position, captioned with the step and the plan."""
        note = plan.note()
        for i in plan.positions:
            self.model.player.set_step(i)
            yield self.frame(step_caption(self.model, i) + "\n" + note)

    def tour(self, frames: int, fps: float) -> Iterator[np.ndarray]:
        """``frames`` frames of the grand tour, ``1 / fps`` seconds apart, captioned with the basis."""
        tour = self.model.tour
        step = self.model.player.position
        ext = self.model.rec.extraction
        for j in range(frames):
            tour.advance(1.0 / fps)
            yield self.frame(
                f"grand tour of R^{self.model.rec.k}, frame {j + 1} of {frames} (M_S at step {step} of {ext.n_steps})"
            )

    def close(self) -> None:
        self.plotter.close()


def output_kind(path: str | os.PathLike) -> str:
    """``"gif"``, ``"mp4"`` or ``"folder"`` (a path without a suffix, or an existing directory)."""
    p = Path(path)
    if p.is_dir() or not p.suffix or str(path).endswith(os.sep):
        return "folder"
    kind = KINDS.get(p.suffix.lower())
    if kind is None:
        raise ValueError(f"cannot write an animation to '{p.name}': use .gif, .mp4 or a folder")
    return kind


class FrameWriter:
    """Frames appended one at a time to a GIF, an MP4 or a folder of PNGs.

    A GIF or an MP4 is written to a temporary file in the target's folder
    (:class:`crustview.atomic.AtomicFile`: unnamed on Linux) and renamed over
    the target when :meth:`finish` is called, so an interrupted, failed or
    killed export never leaves a file that looks complete and never
    destroys an earlier one; :meth:`abort` drops the temporary file (or the
    PNGs written so far, each of which is written atomically).

    Parameters
    ----------
    path : path-like
        See :func:`output_kind`.
    fps : float
    total : int
        Frames expected (for the PNG numbering).
    """

    def __init__(self, path: str | os.PathLike, fps: float, total: int) -> None:
        self.kind = output_kind(path)
        self.path = Path(path)
        self.fps = float(fps)
        self.total = int(total)
        self.count = 0
        self._frames: list[np.ndarray] = []
        self._writer = None
        self._made_dir = False
        self._written: list[Path] = []
        self._staged: AtomicFile | None = None
        if self.kind == "folder":
            self._made_dir = not self.path.exists()
            self.path.mkdir(parents=True, exist_ok=True)
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)

    @property
    def writing(self) -> bool:
        """Whether a temporary file is open (an MP4 being encoded, or a GIF being written)."""
        return self._staged is not None

    def append(self, img: np.ndarray) -> None:
        """Add one (h, w, 3) uint8 frame."""
        import imageio.v3 as iio

        if self.kind == "folder":
            name = self.path / f"frame-{self.count:0{max(3, len(str(self.total)))}d}.png"
            with atomic_path(name) as tmp:
                iio.imwrite(tmp, img, extension=".png")
            self._written.append(name)
        elif self.kind == "gif":
            self._frames.append(img)
        else:
            if self._writer is None:
                import imageio_ffmpeg

                self._staged = AtomicFile(self.path)
                self._writer = imageio_ffmpeg.write_frames(
                    self._staged.path,
                    (img.shape[1], img.shape[0]),
                    fps=self.fps,
                    codec="libx264",
                    quality=6,
                    macro_block_size=8,
                    pix_fmt_out="yuv420p",
                    ffmpeg_log_level="error",
                    output_params=["-f", "mp4"],  # the temporary file's name has no suffix
                )
                self._writer.send(None)
            self._writer.send(np.ascontiguousarray(img, dtype=np.uint8))
        self.count += 1

    def finish(self) -> Path:
        """Complete the file (rename it over the target); returns the path."""
        import imageio.v3 as iio

        if self.kind == "gif" and self._frames:
            self._staged = AtomicFile(self.path)
            iio.imwrite(self._staged.path, np.stack(self._frames), extension=".gif", duration=1000.0 / self.fps, loop=0)
            self._frames = []
        elif self.kind == "mp4" and self._writer is not None:
            self._writer.close()
            self._writer = None
        if self._staged is not None:
            staged, self._staged = self._staged, None
            try:
                staged.commit()
            finally:
                staged.discard()
        return self.path

    def abort(self) -> None:
        """Stop and remove what was written (the temporary file, or this export's PNGs)."""
        self._frames = []
        try:
            if self._writer is not None:
                try:
                    self._writer.close()
                finally:
                    self._writer = None
        finally:
            if self._staged is not None:
                self._staged.discard()
                self._staged = None
        if self.kind == "folder":
            for f in self._written:
                f.unlink(missing_ok=True)
            if self._made_dir and not any(self.path.iterdir()):
                self.path.rmdir()


def write_frames(
    path: str | os.PathLike, frames: Iterator[np.ndarray], total: int, fps: float, progress: Progress | None = None
) -> int:
    """Encode ``frames`` to ``path`` (see :func:`output_kind`); returns the number written.

    ``progress(done, total)`` is called after every frame; when it returns
    False, writing stops and what was written is removed (:meth:`FrameWriter.abort`).
    """
    writer = FrameWriter(path, fps, total)
    try:
        for img in frames:
            writer.append(img)
            if progress is not None and progress(writer.count, total) is False:
                writer.abort()
                return writer.count
        writer.finish()
    except BaseException:
        writer.abort()
        raise
    return writer.count


def text_progress(stream, label: str, width: int = 30) -> Progress:
    """A progress bar on ``stream`` (stderr): ``label [#####.....] 12/90``."""

    def show(done: int, total: int) -> None:
        filled = int(round(width * done / max(total, 1)))
        stream.write(f"\r{label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total}")
        if done >= total:
            stream.write("\n")
        stream.flush()

    return show


def even_size(size: tuple[int, int]) -> tuple[int, int]:
    """Round a frame size down to multiples of 8 (H.264 wants even sizes; 8 avoids rescaling)."""
    w, h = size
    return max(8 * math.floor(w / 8), 16), max(8 * math.floor(h / 8), 16)
