"""Adapters of the per-sample layers: points, poles, normal planes, truth."""

from __future__ import annotations

import numpy as np

from ..scene import geometry as geo
from .base import LayerAdapter, set_cells, set_point_scalars, set_points

#: Colour maps of the points layer's colourings.
POINT_CMAPS = {"normal error": "magma_r", "pole distance": "viridis", "local spacing": "cividis"}


class PointsAdapter(LayerAdapter):
    """The samples, as points; optionally coloured by a per-sample quantity."""

    parts_spec = (("", True),)

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.layer.events.colorby.connect(self.recolor)
        self.scalar_title: str | None = None
        self.clim = (0.0, 1.0)

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        self.xk = rec.points
        self.project()
        set_cells(self.part.mesh, verts=np.arange(rec.n, dtype=np.int64)[:, None])
        self.layer.count = rec.n
        self.recolor()

    def recolor(self, *_) -> None:
        got = self.model.point_values(self.layer.colorby) if self.model.rec is not None else None
        if got is None:
            self.scalar_title = None
            self.part.solid()
            return
        values, title = got
        set_point_scalars(self.part.mesh, values)
        hi = float(np.nanpercentile(values, 98)) if len(values) else 1.0
        lo = float(np.nanmin(values)) if len(values) else 0.0
        self.clim = (lo, max(hi, lo + 1e-12))
        self.scalar_title = title
        self.part.colormap(POINT_CMAPS.get(self.layer.colorby, "viridis"), self.clim, cell=False)

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, spheres=False)

    def pick(self, part, cell_id):
        return ("sample", int(cell_id))


class PolesAdapter(LayerAdapter):
    """Poles of every sample or of the selected sample, joined to the sample."""

    parts_spec = (("", False), ("-ends", False))
    uses_selection = True

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.layer.events.mode.connect(lambda *_: self.rebuild())
        self.ends = np.zeros((0, self.model.projection.k))

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        if self.layer.mode == "all":
            idx = np.arange(rec.n)
        elif self.model.selection.sample is not None:
            idx = np.array([self.model.selection.sample])
        else:
            idx = np.zeros(0, dtype=np.int64)
        c = rec.k - rec.d
        a = np.repeat(rec.points[idx], c, axis=0)
        b = rec.voronoi_vertices[rec.pole_index[idx].ravel()]
        lo, hi = self.model.box
        inside = np.all((b >= lo) & (b <= hi), axis=1)
        a2, b2, keep = geo.clip_segments(a, b, lo, hi)
        self.xk = np.vstack([a2, b2]) if len(a2) else np.zeros((0, rec.k))
        m = len(a2)
        set_cells(self.part.mesh, lines=np.stack([np.arange(m), np.arange(m) + m], axis=1))
        self.ends = b[inside]
        set_cells(self.parts[1].mesh, verts=np.arange(len(self.ends))[:, None])
        self.layer.count = len(b)
        self.project()

    def project(self) -> None:
        proj = self.model.projection
        if self.xk.shape[1] == proj.k:
            set_points(self.part.mesh, proj.project(self.xk) if len(self.xk) else np.zeros((0, 3)))
        if self.ends.shape[1] == proj.k:
            set_points(self.parts[1].mesh, proj.project(self.ends) if len(self.ends) else np.zeros((0, 3)))

    def select(self) -> None:
        if self.layer.mode != "all":
            self.rebuild()

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, max(1.0, self.layer.size / 3), lines=True)
        self.parts[1].style(self.layer.color, self.layer.opacity, self.layer.size, spheres=False)


class NormalsAdapter(LayerAdapter):
    """Glyphs of the estimated normal planes AN_s, scaled to the local spacing."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._built_size: float | None = None

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        scale = 0.45 * self.layer.size * self.model.spacing
        verts, lines, polys = geo.normal_glyphs(rec.points, rec.normals, scale)
        self.xk = verts
        self.project()
        set_cells(self.part.mesh, lines=lines, polys=polys)
        self.layer.count = rec.n
        self._built_size = self.layer.size

    def restyle(self) -> None:
        if self._built_size is not None and self._built_size != self.layer.size:
            self.rebuild()
        self.part.style(self.layer.color, self.layer.opacity, 4.0, lines=False)
        self.part.actor.prop.line_width = 2.0


class TruthAdapter(LayerAdapter):
    """A dense sample of the true manifold (built-in samples only), faint."""

    N_DENSE = 20_000

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._pending = True

    def rebuild(self) -> None:
        self._pending = True
        self.xk = np.zeros((0, self.model.projection.k))
        set_cells(self.part.mesh)
        truth = self.model.truth
        self.layer.count = 0 if truth is None else self.N_DENSE
        if self.layer.visible:
            self._load()

    def _load(self) -> None:
        truth = self.model.truth
        self._pending = False
        if truth is None or self.model.rec is None:
            return
        ref = np.asarray(truth.manifold.reference(self.N_DENSE), float)
        if ref.shape[1] != self.model.rec.k:
            return
        self.xk = ref
        self.project()
        set_cells(self.part.mesh, verts=np.arange(len(ref))[:, None])
        self.layer.count = len(ref)

    def apply_visibility(self) -> None:
        super().apply_visibility()
        if self.layer.visible and getattr(self, "_pending", False):
            self._load()

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size)
