"""A compact colour legend drawn with text actors (dark, readable labels)."""

from __future__ import annotations

import pyvista as pv
from vtkmodules.vtkRenderingCore import vtkTextActor


class Legend:
    """Swatch + label lines in the upper-left corner of a renderer."""

    def __init__(self, plotter, font_size: int = 13) -> None:
        self.plotter = plotter
        self.font_size = font_size
        self.actors: list[vtkTextActor] = []
        self.entries: list[tuple[str, str]] = []

    def _text(self, text: str, color, bold: bool = False) -> vtkTextActor:
        a = vtkTextActor()
        a.SetInput(text)
        tp = a.GetTextProperty()
        tp.SetFontSize(self.font_size)
        tp.SetColor(*pv.Color(color).float_rgb)
        tp.SetBold(bold)
        tp.SetBackgroundColor(1.0, 1.0, 1.0)
        tp.SetBackgroundOpacity(0.75)
        a.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        a.SetPickable(False)
        return a

    def set(self, entries: list[tuple[str, str]]) -> None:
        """Show ``(label, colour)`` lines (no-op when unchanged)."""
        if entries == self.entries:
            return
        self.entries = list(entries)
        for a in self.actors:
            self.plotter.renderer.RemoveViewProp(a)
        self.actors = []
        for j, (label, color) in enumerate(entries):
            y = 0.965 - 0.032 * j
            sw = self._text("    ", color)
            sw.GetTextProperty().SetBackgroundColor(*pv.Color(color).float_rgb)
            sw.GetTextProperty().SetBackgroundOpacity(1.0)
            sw.SetPosition(0.012, y)
            lab = self._text(" " + label + " ", "#222222")
            lab.SetPosition(0.028, y)
            for a in (sw, lab):
                self.plotter.renderer.AddViewProp(a)
                self.actors.append(a)
