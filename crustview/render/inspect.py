"""Adapters that follow the selection: Voronoi cells and the highlight."""

from __future__ import annotations

import numpy as np

from ..scene import geometry as geo
from ..scene.voronoi import clipped_cell, planar_voronoi_edges
from .base import LayerAdapter, set_cells, set_points


class VoronoiAdapter(LayerAdapter):
    """All cells in R^2; the selected sample's clipped cell in R^3 and up."""

    parts_spec = (("", False), ("-faces", False))
    uses_selection = True

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._cell_of: int | None = None

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        self._cell_of = None
        lo, hi = self.model.box
        if rec.k == 2:
            a, b = planar_voronoi_edges(rec.delaunay_simplices, rec.voronoi_vertices, rec.n, lo, hi)
            m = len(a)
            self.xk = np.vstack([a, b]) if m else np.zeros((0, 2))
            set_cells(self.part.mesh, lines=np.stack([np.arange(m), np.arange(m) + m], axis=1))
            set_cells(self.parts[1].mesh)
            self.faces_xk = np.zeros((0, 2))
            self.layer.count = rec.n
        else:
            self._selected_cell()
        self.project()

    def _selected_cell(self) -> None:
        rec = self.model.rec
        i = self.model.selection.sample
        self.xk = np.zeros((0, rec.k))
        self.faces_xk = np.zeros((0, rec.k))
        set_cells(self.part.mesh)
        set_cells(self.parts[1].mesh)
        self.layer.count = 0
        if i is None:
            return
        lo, hi = self.model.box
        cell = clipped_cell(rec.voronoi_cell(i), rec.points[i], lo, hi)
        if cell is None:
            return
        verts, edges, tris = cell
        self.xk = verts
        self.faces_xk = verts
        set_cells(self.part.mesh, verts=np.arange(len(verts))[:, None], lines=edges)
        set_cells(self.parts[1].mesh, polys=tris if len(tris) else None)
        self.layer.count = 1
        self._cell_of = i

    def project(self) -> None:
        proj = self.model.projection
        if self.xk.shape[1] != proj.k:
            return
        pts = proj.project(self.xk) if len(self.xk) else np.zeros((0, 3))
        set_points(self.part.mesh, pts)
        set_points(self.parts[1].mesh, pts)

    def select(self) -> None:
        rec = self.model.rec
        if rec is None or rec.k == 2 or self.model.selection.sample == self._cell_of:
            return
        self._selected_cell()
        self.project()

    def restyle(self) -> None:
        k = self.model.rec.k if self.model.rec is not None else 3
        flat = k == 2
        if k >= 4:  # R^4: the 2-faces as translucent patches carry the shape; thin, faint edges
            self.part.style(self.layer.color, 0.35, 1.0, lines=True)
        else:
            self.part.style(
                self.layer.color, 0.9 if not flat else max(self.layer.opacity, 0.5), self.layer.size, lines=True
            )
        self.part.actor.prop.point_size = 2 * self.layer.size
        self.parts[1].style(self.layer.color, self.layer.opacity, self.layer.size)


class SelectionAdapter(LayerAdapter):
    """Highlight of the selected sample, simplex, or face with its incident simplices."""

    parts_spec = (("", False),)
    uses_selection = True
    uses_step = True

    def rebuild(self) -> None:
        self.select()

    def step(self) -> None:
        if self.model.selection.face is not None:
            self.select()

    def select(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        sel = self.model.selection
        verts: list[int] = []
        pairs: list[tuple[int, int]] = []

        def edges_of(simplex):
            s = [int(v) for v in simplex]
            for a in range(len(s)):
                for b in range(a + 1, len(s)):
                    pairs.append((s[a], s[b]))

        if sel.sample is not None:
            verts.append(sel.sample)
        if sel.simplex is not None and sel.simplex < len(rec.candidates.faces):
            edges_of(rec.candidates.faces[sel.simplex])
        if sel.feature is not None:  # a clicked feature: its samples (a loop's, a rim's, a part's)
            from ..scene.features import feature_samples

            verts.extend(int(v) for v in feature_samples(rec, sel.feature))
        if sel.face is not None:
            verts.extend(sel.face)
            edges_of(sel.face)
            alive = rec.extraction.alive(self.model.player.position)
            simp = rec.extraction.simplices[alive]
            for r in geo.simplices_at_face(simp, sel.face):
                edges_of(simp[r])
        used = np.unique(np.array(verts + [v for p in pairs for v in p], dtype=np.int64))
        self.xk = rec.points[used]
        remap = {int(v): j for j, v in enumerate(used)}
        set_cells(
            self.part.mesh,
            verts=np.array([[remap[v]] for v in verts], dtype=np.int64) if verts else None,
            lines=np.array([[remap[a], remap[b]] for a, b in pairs], dtype=np.int64) if pairs else None,
        )
        self.layer.count = int(not sel.empty)
        self.project()

    def project(self) -> None:
        proj = self.model.projection
        if self.xk.shape[1] == proj.k:
            set_points(self.part.mesh, proj.project(self.xk) if len(self.xk) else np.zeros((0, 3)))

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=False, spheres=False)
        self.part.actor.prop.point_size = 2.2 * self.layer.size
        # curves: the selected edge must stand out from M_S's own (thick) line
        curve = self.model.rec is not None and self.model.rec.d == 1
        self.part.actor.prop.line_width = self.layer.size * 1.2 if curve else max(2.0, self.layer.size / 2)
        self.part.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(-6, -6)
