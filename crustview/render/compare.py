"""Adapter of the comparison layer: simplices in both complexes, only in A, only in B."""

from __future__ import annotations

import numpy as np

from ..scene.layers import COMPARE_COLORS
from .base import LayerAdapter, set_points
from .complexes import SimplexDrawing

#: Parts of the layer in drawing order, with the key of their colour.
KEYS = ("both", "A", "B")


class CompareAdapter(LayerAdapter):
    """Three parts over the comparison's points: ``both``, ``only A`` and ``only B``.

    ``both`` has the layer's colour and opacity, ``only A`` and ``only B``
    fixed colours, opaque and slightly thicker, so differences stand out.
    """

    parts_spec = (("", False), ("-a", False), ("-b", False))

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.drawings: list[SimplexDrawing | None] = [None, None, None]
        self.model.comparison_changed.connect(self.rebuild)

    def rebuild(self) -> None:
        c = self.model.comparison
        rec = self.model.rec
        if c is None or rec is None or c.diff.points.shape[1] != self.model.projection.k:
            self.drawings = [None, None, None]
            for p in self.parts:
                SimplexDrawing(np.zeros((0, 2 if rec is None else rec.d + 1)), 1 if rec is None else rec.d).apply(
                    p.mesh, None
                )
            self.layer.count = 0
            return
        d = c.diff
        shrink = self.model.layers["manifold"].shrink if d.d >= 3 else 1.0
        rows = (d.both, d.only_a, d.only_b)
        self.drawings = [SimplexDrawing(r, d.d, shrink) for r in rows]
        self.project()
        for p, dr in zip(self.parts, self.drawings):
            dr.apply(p.mesh, None)
        self.layer.count = len(d.only_a) + len(d.only_b)
        self.restyle()

    def project(self) -> None:
        c = self.model.comparison
        if c is None or self.drawings[0] is None:
            return
        proj = self.model.projection.project(c.diff.points)
        for p, dr in zip(self.parts, self.drawings):
            set_points(p.mesh, dr.points(proj))

    def restyle(self) -> None:
        lines = self.model.rec is not None and self.model.rec.d == 1
        size = self.layer.size
        for key, p in zip(KEYS, self.parts):
            colour = self.layer.color if key == "both" else COMPARE_COLORS[key]
            opacity = self.layer.opacity if key == "both" else 1.0
            p.style(colour, opacity, size if key == "both" else size + 1.5, lines=lines)
            p.actor.prop.show_edges = not lines and key != "both"
            p.actor.prop.edge_color = "#333333"
            p.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(-1, -1)  # over M_S

    def shown_cells(self) -> int:
        return sum(p.n_cells for p in self.parts)
