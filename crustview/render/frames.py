"""One frame for one change of the picture: renders asked for during a batch of edits are drawn once, at its end.

Why
---
A new result reaches the view as a chain of model events (layers shown and
styled, the reconstruction, the selection, the camera's reset), and each
handler, and pyvista itself (``reset_camera``, the first ``camera`` access),
asks the plotter for a frame.  Measured on the GUI tests (a plugin counting
``BasePlotter.render``), a finished run drew 5 to 7 frames, about 22 ms each
at 1200 x 800 in software GL and far more for a large scan, of which only the
last was ever seen.  :class:`FrameGate` sits in front of the plotter's
``render``: inside :meth:`FrameGate.held` a render is only *owed*, and the
outermost ``held`` draws it once when it ends (also when the batch raised, so
the picture is never left behind the model).  Outside a batch it renders at
once, as before.

In the window a frame is better not drawn at all where the widget paints
anyway: pyvistaqt's widget renders the scene again in every paint, and a
render of its own schedules that paint, so each frame asked for was drawn
twice (counted on the GUI tests: 527 renders asked for, 413 paints).  With
:attr:`FrameGate.paint` set (the window sets it to the widget's ``update``),
a frame is *asked of the widget*: Qt paints once, at the next turn of its
event loop, however many frames were asked before it.  Reading pixels back
would then read the last painted frame: the gate also stands in front of the
plotter's ``screenshot``, which draws the frame first where a paint asked for
has not run yet (:attr:`FrameGate.stale`) or a batch is open, and draws at
once any render the screenshot itself asks for (at another window size); a
settled view is read as painted, without a frame.  The tests read every
picture they judge through it, as the window's export does.

Nothing here imports Qt: the window decides which of its actions are batches.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager


class FrameGate:
    """Holds a plotter's renders during a batch of edits and draws one frame after it.

    Parameters
    ----------
    plotter : pyvista.Plotter or pyvistaqt.QtInteractor
        Its ``render`` is replaced on the instance by :meth:`render` (pyvista's own calls, such as
        ``Renderer.reset_camera``, go through ``plotter.render`` and so through the gate too).
    """

    def __init__(self, plotter) -> None:
        self._draw: Callable[[], object] = plotter.render
        self._depth = 0
        #: A render was asked for inside the current batch.
        self.owed = False
        #: Frames drawn through the gate (for tests and benchmarks).
        self.frames = 0
        #: Asks a GUI toolkit to repaint soon (its paint draws the frame); None draws at once.
        self.paint: Callable[[], object] | None = None
        #: A paint was asked for and no frame was drawn since (any render, a paint's too, ends it).
        self.stale = False
        ren_win = getattr(plotter, "ren_win", None)
        if ren_win is not None:
            ren_win.AddObserver("EndEvent", lambda *_: setattr(self, "stale", False))
        plotter.render = self.render
        shot = getattr(plotter, "screenshot", None)
        if shot is not None:

            def screenshot(*args, **kwargs) -> object:
                if self.paint is None:
                    return shot(*args, **kwargs)
                # the picture as the model is now, even inside a batch: a paint asked for may not have run
                if self.stale or self._depth:
                    self.draw_now()
                # and renders the screenshot itself asks for (at another window size, say) are drawn at once
                paint, self.paint = self.paint, None
                try:
                    return shot(*args, **kwargs)
                finally:
                    self.paint = paint

            plotter.screenshot = screenshot

    @property
    def holding(self) -> bool:
        """Whether a batch is open (renders are owed, not drawn)."""
        return self._depth > 0

    def render(self, *args, **kwargs) -> object:
        """Draw a frame now, or owe it to the end of the open batch."""
        if self._depth:
            self.owed = True
            return None
        self.frames += 1
        if self.paint is not None:
            self.stale = True
            return self.paint()
        return self._draw(*args, **kwargs)

    def draw_now(self) -> None:
        """Draw a frame at once, even inside a batch or where the toolkit paints (before reading pixels back).

        A batch's owed frame is still drawn at its end (edits after this one may follow).
        """
        self.frames += 1
        self._draw()

    @contextmanager
    def held(self) -> Iterator[None]:
        """A batch: renders asked for inside are drawn as one frame when the outermost batch ends."""
        self._depth += 1
        try:
            yield
        finally:
            self._depth -= 1
            if not self._depth and self.owed:
                self.owed = False
                self.render()
