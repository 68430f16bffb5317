"""The command line's progress bar: on stderr when it is a terminal, nothing otherwise.

:class:`StageProgress` is the ``progress(stage, fraction)`` callback that
:func:`crustview.core.reconstruct` calls; on a terminal it shows the stage,
a bar, the stage's percentage and the time since the start (``rich``, which
meshio already needs).  The bar is transient: when the work ends it is
erased, and only the command's summary stays on the screen.  Piped or with
``-q`` it does nothing.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


def wants_bar(stream: TextIO | None = None, quiet: bool = False) -> bool:
    """Whether to draw a bar on ``stream`` (default stderr): a terminal, and not ``-q``."""
    stream = sys.stderr if stream is None else stream
    try:
        return not quiet and stream.isatty()
    except (AttributeError, ValueError):
        return False


class StageProgress:
    """A ``progress(stage, fraction)`` callback drawing one bar per stage (a context manager).

    Parameters
    ----------
    label : str
        Shown before the stage, e.g. the file's name.
    enabled : bool
        False: every call does nothing (not a terminal, or ``-q``).
    stream : file, optional
        Default stderr.
    """

    def __init__(self, label: str, enabled: bool, stream: TextIO | None = None) -> None:
        self.label = label
        self.enabled = enabled
        self.stream = sys.stderr if stream is None else stream
        self.start = time.perf_counter()
        self.stages: list[str] = []
        self._bar = None
        self._task = None
        self._drawn = -1  # the tenth of the bar last drawn on request

    def __enter__(self) -> StageProgress:
        if self.enabled:
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn

            self._bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                TaskProgressColumn(),
                TimeElapsedColumn(),
                console=Console(file=self.stream),
                transient=True,
                refresh_per_second=8,
            )
            self._bar.start()
            self._task = self._bar.add_task(self.label, total=100.0)
        return self

    def __call__(self, stage: str, fraction: float) -> None:
        new = not self.stages or self.stages[-1] != stage
        if new:
            self.stages.append(stage)
        if self._bar is None:
            return
        # never 100 %: rich would mark the task finished and freeze its elapsed time for the next stages
        pct = 100.0 * min(max(float(fraction), 0.0), 0.999)
        # a new stage is drawn at once (one frame each), so a stage shorter than a frame still shows; so is
        # each tenth of a stage reached, so the bar moves even when the run keeps the refresh thread from
        # drawing (on a loaded machine a 20,000-point run showed only 0 % and 100 %)
        tenth = int(pct // 10)
        draw = new or tenth != self._drawn
        if draw:
            self._drawn = tenth
        self._bar.update(self._task, description=f"{self.label}: {stage}", completed=pct, refresh=draw)

    def note(self, line: str) -> None:
        """A line on the bar's stream, above the bar (or plainly without one)."""
        if self._bar is not None:
            self._bar.console.print(line, markup=False, highlight=False, soft_wrap=True)
        else:
            print(line, file=self.stream, flush=True)

    def __exit__(self, *exc) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None


class CountProgress:
    """A bar of files done out of a total (the batch command), on stderr when it is a terminal."""

    def __init__(self, total: int, enabled: bool, stream: TextIO | None = None) -> None:
        self.total = total
        self.enabled = enabled
        self.stream = sys.stderr if stream is None else stream
        self._bar = None
        self._task = None

    def __enter__(self) -> CountProgress:
        if self.enabled:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(
                TextColumn("{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                console=Console(file=self.stream),
                transient=True,
            )
            self._bar.start()
            self._task = self._bar.add_task("reconstructing", total=self.total)
        return self

    def advance(self, name: str) -> None:
        if self._bar is not None:
            self._bar.update(self._task, advance=1, description=f"done {name}")

    def print(self, line: str) -> None:
        """A line above the bar (or plainly on stdout without one)."""
        if self._bar is not None and sys.stdout.isatty():  # the same screen: above the live bar
            self._bar.console.print(line, markup=False, highlight=False, soft_wrap=True)
        else:
            print(line, flush=True)

    def __exit__(self, *exc) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None
