"""A compact colour legend drawn with text actors (dark, readable labels)."""

from __future__ import annotations

import re

import pyvista as pv
from vtkmodules.vtkRenderingCore import vtkCoordinate, vtkTextActor

#: Colour of the notes above the legend (warnings about the result).
NOTE_COLOR = "#b00000"
#: Colour of the notes about a result that is closed but not all supported by its sample.
WARN_COLOR = "#9a5800"
#: Colour of the note over the view for a result the sample supports throughout (the Information box's green).
OK_COLOR = "#1d6b2a"


class Legend:
    """Swatch + label lines in the upper-left corner of a renderer.

    Optionally under a few lines of notes (e.g. "M_S is NOT a closed manifold").
    """

    def __init__(self, plotter, font_size: int = 13, renderer=None) -> None:
        self.plotter = plotter
        #: Where the lines are drawn (the plotter's renderer unless given: the view's text layer).
        self.renderer = renderer if renderer is not None else plotter.renderer
        self.font_size = font_size
        self.actors: list[vtkTextActor] = []
        self.entries: list[tuple[str, str | None]] = []
        self.notes: list[str] = []
        self._shown: list[tuple] = []

    def _text(self, text: str, color, y: float, x_px: float, bold: bool = False) -> vtkTextActor:
        """A text line at height ``y`` (normalised viewport), ``x_px`` pixels from the left edge."""
        a = vtkTextActor()
        a.SetInput(text)
        tp = a.GetTextProperty()
        tp.SetFontSize(self.font_size)
        tp.SetColor(*pv.Color(color).float_rgb)
        tp.SetBold(bold)
        tp.SetBackgroundColor(1.0, 1.0, 1.0)
        tp.SetBackgroundOpacity(0.75)
        ref = vtkCoordinate()
        ref.SetCoordinateSystemToNormalizedViewport()
        ref.SetValue(0.0, y)
        pos = a.GetPositionCoordinate()
        pos.SetCoordinateSystemToDisplay()  # an offset in pixels from the reference
        pos.SetReferenceCoordinate(ref)
        pos.SetValue(x_px, 0.0)
        a.SetPickable(False)
        return a

    def set(self, entries: list[tuple[str, str]], notes: list[str] = (), note_color: str = NOTE_COLOR) -> None:
        """Show ``notes`` (bold red lines) above ``(label, colour)`` lines; no-op when unchanged.

        Text actors are reused line by line: a vtkTextActor renders its text to a
        texture again only when that text or its style changes, and stepping
        through Algorithm 3 changes one or two lines of the legend at a time.
        """
        state = list(entries) + [(n, note_color) for n in notes]
        budget = self._chars()
        if (
            state == self.entries
            and budget == getattr(self, "_budget", None)
            and self._line_step() == getattr(self, "_step", None)
        ):
            return
        self.entries = state
        self._budget = budget
        self._args = (list(entries), list(notes), note_color)
        self.notes = list(notes)
        # a note longer than the view is wide goes on over lines of its own (a verdict was cut off at the edge)
        notes = [part for note in notes for part in (_wrap(note, budget) if budget else [note]) or [note]]
        lines: list[tuple[str, str, float, float, bool, str | None]] = []  # text, colour, y, x, bold, swatch
        step = self._step = self._line_step()
        first = self._first_line()
        for j, note in enumerate(notes):
            lines.append((" " + note + " ", note_color, first - step * j, 8, True, None))
        # the entries 0.3 of a line below the notes, or just below them where the notes had to come down
        below = min(0.965 - step * (len(notes) + 0.3), first - step * len(notes)) if notes else first
        for j, (label, color) in enumerate(entries):
            y = below - step * j
            lines.append(("   ", "#222222", y, 8, False, color))
            lines.append((" " + label + " ", "#222222", y, 8 + self.font_size * 1.4, False, None))
        while len(self.actors) > len(lines):
            self.renderer.RemoveViewProp(self.actors.pop())
        for j, line in enumerate(lines):
            if j < len(self.actors):
                if self._shown[j] != line:
                    self._restyle(self.actors[j], *line)
            else:
                a = self._text(line[0], line[1], line[2], line[3], bold=line[4])
                self._restyle(a, *line)
                self.renderer.AddViewProp(a)
                self.actors.append(a)
        self._shown = lines

    def refit(self) -> None:
        """Wrap the notes again if the view's width changed since they were set (cheap when it did not)."""
        args = getattr(self, "_args", None)
        if args is not None and (self._chars() != self._budget or self._line_step() != self._step):
            self.set(*args)

    def _line_step(self) -> float:
        """The height of a line, as a share of the renderer's.

        3.2 %, or more where that is less than the font needs (a 240-pixel export drew its legend lines
        over each other).
        """
        height = self.renderer.GetSize()[1] if hasattr(self.renderer, "GetSize") else 0
        return max(0.032, 1.3 * self.font_size / height) if height > 0 else 0.032

    def _first_line(self) -> float:
        """Where the first line's baseline is, as a share of the renderer's height.

        96.5 %, or lower where the font would not fit above it: a 320 x 240 export cut the top of its verdict
        off (the text rises about one font size above its baseline).
        """
        height = self.renderer.GetSize()[1] if hasattr(self.renderer, "GetSize") else 0
        return min(0.965, 1.0 - 1.25 * self.font_size / height) if height > 0 else 0.965

    def _chars(self) -> int | None:
        """How many characters of a bold note fit across the renderer (None before it has a size)."""
        width = self.renderer.GetSize()[0] if hasattr(self.renderer, "GetSize") else 0
        if width <= 0:
            return None
        # a bold sans character is about 0.51 of the font size wide (measured here: 93 in 620 px at 13): 0.53
        # leaves room for wider letters; the note's 8 px margin and its padding spaces aside
        return max(30, int((width - 24) / (0.53 * self.font_size)))

    def _restyle(
        self, a: vtkTextActor, text: str, color, y: float, x_px: float, bold: bool, swatch: str | None
    ) -> None:
        a.SetInput(text)
        tp = a.GetTextProperty()
        tp.SetColor(*pv.Color(color).float_rgb)
        tp.SetBold(bold)
        if swatch is None:
            tp.SetBackgroundColor(1.0, 1.0, 1.0)
            tp.SetBackgroundOpacity(0.75)
        else:
            tp.SetBackgroundColor(*pv.Color(swatch).float_rgb)
            tp.SetBackgroundOpacity(1.0)
        a.GetPositionCoordinate().GetReferenceCoordinate().SetValue(0.0, y)
        a.GetPositionCoordinate().SetValue(x_px, 0.0)


def _wrap(text: str, width: int) -> list[str]:
    """``text`` in lines of at most ``width`` characters, broken at spaces only.

    A tuple like "(1, 0, 0)" is never split (a reviewer saw "≠ mesh (1," end a line); a word longer than
    the width stands alone.
    """
    lines: list[str] = []
    line = ""
    for token in re.findall(r"\([\d, ]+\)\S*|\S+", text):
        if line and len(line) + 1 + len(token) > width:
            lines.append(line)
            line = token
        else:
            line = f"{line} {token}" if line else token
    return lines + [line] if line else lines
