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
        plotter.render = self.render

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
        return self._draw(*args, **kwargs)

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
