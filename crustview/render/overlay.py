"""A compact colour legend drawn with text actors (dark, readable labels)."""

from __future__ import annotations

import pyvista as pv
from vtkmodules.vtkRenderingCore import vtkCoordinate, vtkTextActor

#: Colour of the notes above the legend (warnings about the result).
NOTE_COLOR = "#b00000"


class Legend:
    """Swatch + label lines in the upper-left corner of a renderer, optionally
    under a few lines of notes (e.g. "M_S is NOT a closed manifold")."""

    def __init__(self, plotter, font_size: int = 13) -> None:
        self.plotter = plotter
        self.font_size = font_size
        self.actors: list[vtkTextActor] = []
        self.entries: list[tuple[str, str | None]] = []
        self.notes: list[str] = []

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

    def set(self, entries: list[tuple[str, str]], notes: list[str] = ()) -> None:
        """Show ``notes`` (bold red lines) above ``(label, colour)`` lines; no-op when unchanged."""
        state = list(entries) + [(n, None) for n in notes]
        if state == self.entries:
            return
        self.entries = state
        self.notes = list(notes)
        for a in self.actors:
            self.plotter.renderer.RemoveViewProp(a)
        self.actors = []
        for j, note in enumerate(notes):
            a = self._text(" " + note + " ", NOTE_COLOR, 0.965 - 0.032 * j, 8, bold=True)
            self.plotter.renderer.AddViewProp(a)
            self.actors.append(a)
        top = len(notes) + (0.3 if notes else 0)
        for j, (label, color) in enumerate(entries):
            y = 0.965 - 0.032 * (j + top)
            sw = self._text("   ", color, y, 8)
            sw.GetTextProperty().SetBackgroundColor(*pv.Color(color).float_rgb)
            sw.GetTextProperty().SetBackgroundOpacity(1.0)
            lab = self._text(" " + label + " ", "#222222", y, 8 + self.font_size * 1.4)
            for a in (sw, lab):
                self.plotter.renderer.AddViewProp(a)
                self.actors.append(a)
