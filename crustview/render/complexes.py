"""Adapters of the simplicial layers: T_S, M_S at a step, removed, current step."""

from __future__ import annotations

import numpy as np

from ..core.steps import PLACELESS_RULES
from ..scene import geometry as geo
from ..scene.coloring import coordinate_values
from ..scene.layers import STEP_COLORS
from ..scene.slicing import slice_complex
from .base import LayerAdapter, set_cell_scalars, set_cells, set_point_scalars, set_points

#: Colourings of M_S given per simplex by the model (the others are per vertex).
CELL_COLORINGS = ("distance to M",)

#: Above this many triangles, M_S is drawn without edges (they cost a render pass).
EDGE_LIMIT = 20_000

#: Colour map of the candidate angle.
ANGLE_CMAP = "plasma"
#: Colour map of positions (a coordinate, the hidden depth).
COORD_CMAP = "coolwarm"


class SimplexDrawing:
    """How a fixed table of d-simplices is drawn; subsets are cheap.

    d = 1 gives lines, d = 2 triangles, d >= 3 the boundary triangles of each
    simplex.  When ``shrink < 1`` (or d >= 3) every simplex gets its own copy
    of its vertices, moved towards its centroid, so that neighbours separate.

    Parameters
    ----------
    table : ndarray of shape (m, d + 1)
        Simplices (indices into the samples).
    d : int
    shrink : float
    """

    def __init__(self, table: np.ndarray, d: int, shrink: float = 1.0) -> None:
        self.table = np.asarray(table, dtype=np.int64).reshape(-1, d + 1)
        self.d = d
        self.shrink = float(shrink)
        self.dup = self.shrink < 1.0 or d >= 3
        if d == 1:
            local = np.array([[0, 1]])
        elif d == 2:
            local = np.array([[0, 1, 2]])
        else:
            local = geo.simplex_triangles(d)
        self.per = len(local)
        self.width = local.shape[1]
        m = len(self.table)
        if self.dup:
            self.cells_all = (np.arange(m) * (d + 1))[:, None, None] + local[None]
        else:
            self.cells_all = self.table[:, local]
        if self.cells_all.size and self.cells_all.max() < 2**31:
            # int32 halves the per-step gather and VTK copy (see render.base.cell_array)
            self.cells_all = self.cells_all.astype(np.int32)

    @property
    def lines(self) -> bool:
        return self.d == 1

    def points(self, proj: np.ndarray) -> np.ndarray:
        """View-space vertices from the projected samples ``proj`` (n, 3)."""
        if not self.dup:
            return proj
        if len(self.table) == 0:
            return np.zeros((0, 3))
        return geo.shrink_simplices(proj, self.table, self.shrink)

    def cells(self, mask: np.ndarray | None = None) -> np.ndarray:
        """Cells of the rows selected by ``mask`` (all when None)."""
        # a gather by row numbers is ~3x faster than a boolean index on millions of rows
        c = self.cells_all if mask is None else np.take(self.cells_all, np.flatnonzero(mask), axis=0)
        return c.reshape(-1, self.width)

    def apply(self, mesh, mask: np.ndarray | None) -> None:
        cells = self.cells(mask)
        set_cells(mesh, lines=cells if self.lines else None, polys=None if self.lines else cells)


class ComplexAdapter(LayerAdapter):
    """A subset of a fixed table of simplices (subclasses choose which)."""

    parts_spec = (("", True),)

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.drawing: SimplexDrawing | None = None
        self.rows = np.zeros(0, dtype=np.int64)
        self.layer.events.shrink.connect(lambda *_: self._redraw())

    def table(self) -> np.ndarray:
        raise NotImplementedError

    def mask(self) -> np.ndarray:
        raise NotImplementedError

    def rebuild(self) -> None:
        if self.model.rec is None:
            return
        self._redraw()

    def _redraw(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        self.drawing = SimplexDrawing(self.table(), rec.d, self.layer.shrink if rec.d >= 2 else 1.0)
        self.project()
        self.update_cells()

    def project(self) -> None:
        rec = self.model.rec
        if rec is None or self.drawing is None:
            return
        set_points(self.part.mesh, self.drawing.points(self.model.projection.project(rec.points)))

    def update_cells(self) -> None:
        if self.drawing is None:
            return
        mask = self.mask()
        self.rows = np.flatnonzero(mask)
        self.drawing.apply(self.part.mesh, mask)
        self.layer.count = len(self.rows)

    def restyle(self) -> None:
        lines = self.model.rec is not None and self.model.rec.d == 1
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=lines)
        # translucent surfaces keep their edges: without them a see-through M_S has no shape
        # (d >= 3 draws every simplex's boundary: there, edges on see-through cells are clutter)
        d = self.model.rec.d if self.model.rec is not None else 2
        self.part.actor.prop.show_edges = (
            (not lines)
            and self.layer.size > 0
            and self.part.n_cells <= EDGE_LIMIT
            and (d <= 2 or self.layer.opacity >= 0.99)
        )
        self.part.actor.prop.edge_color = "#5a4a32"
        # push surfaces slightly back so samples and highlights on them stay visible
        self.part.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(2, 2)

    def row_of(self, cell_id: int) -> int:
        assert self.drawing is not None
        return int(self.rows[cell_id // self.drawing.per])


class CandidatesAdapter(ComplexAdapter):
    """T_S for the run panel's test and threshold, coloured by deciding angle."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.model.candidates_changed.connect(self.update_cells)
        self.layer.events.colorby.connect(lambda *_: self.update_cells())
        self.scalar_title: str | None = None
        self.clim = (0.0, 22.5)

    def table(self):
        return self.model.rec.candidates.faces

    def mask(self):
        return self.model.candidate_mask()

    def update_cells(self, *_) -> None:
        super().update_cells()
        rec = self.model.rec
        if rec is None or self.drawing is None:
            return
        if self.layer.colorby == "angle":
            ang = np.degrees(rec.candidates.angles[self.model.test][self.rows])
            set_cell_scalars(self.part.mesh, np.repeat(ang, self.drawing.per))
            self.clim = (0.0, max(float(np.degrees(self.model.theta)), 1e-6))
            self.scalar_title = f"{self.model.test} angle (deg)"
            self.part.colormap(ANGLE_CMAP, self.clim, cell=True)
        else:
            self.scalar_title = None
            self.part.solid()

    def restyle(self) -> None:
        super().restyle()
        self.part.actor.prop.show_edges = False

    def pick(self, part, cell_id):
        return ("simplex", self.row_of(cell_id))


class ManifoldAdapter(ComplexAdapter):
    """M_S as it stands at the current step: ``extraction.alive(i)``.

    Optionally coloured by a coordinate or by the depth the projection hides
    (:mod:`crustview.scene.coloring`), interpolated over each simplex.
    """

    uses_step = True

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.scalar_title: str | None = None
        self.clim = (0.0, 1.0)
        if type(self) is ManifoldAdapter:
            self.layer.events.colorby.connect(lambda *_: self.recolor())
            self.model.theorems_changed.connect(lambda *_: self.recolor())
            self.model.slice_changed.connect(lambda *_: self.update_cells())
            self.model.layers["slice"].events.visible.connect(lambda *_: self.update_cells())

    def project(self) -> None:
        super().project()
        if type(self) is ManifoldAdapter:
            self.recolor()
            if self.model.slicing and self.model.slice_cut:  # the hyperplane turned with the view
                self.update_cells()

    def recolor(self) -> None:
        """Point scalars from the layer's colouring (one value per drawn vertex)."""
        rec = self.model.rec
        if rec is None or self.drawing is None:
            return
        if self.layer.colorby in CELL_COLORINGS:
            self._color_cells()
            return
        got = coordinate_values(rec.points, self.model.projection, self.layer.colorby)
        if got is None:
            self.scalar_title = None
            self.part.solid()
            return
        values, self.scalar_title = got
        per_vertex = values[self.drawing.table].ravel() if self.drawing.dup else values
        set_point_scalars(self.part.mesh, per_vertex)
        self.clim = (float(values.min()), float(max(values.max(), values.min() + 1e-12)))
        self.part.colormap(COORD_CMAP, self.clim, cell=False)

    def update_cells(self, *_) -> None:
        super().update_cells()
        if type(self) is ManifoldAdapter and self.layer.colorby in CELL_COLORINGS:
            self._color_cells()

    def _color_cells(self) -> None:
        """Cell scalars from the model (the distance of each simplex to M, for built-ins)."""
        if self.model.rec is None or self.drawing is None:
            return
        got = self.model.manifold_values(self.layer.colorby)
        if got is None:
            self.scalar_title = None
            self.part.solid()
            return
        values, title = got
        set_cell_scalars(self.part.mesh, np.repeat(values[self.rows], self.drawing.per))
        ok = values[np.isfinite(values)]
        self.clim = (0.0, max(float(ok.max()) if len(ok) else 1.0, 1e-12))
        self.scalar_title = title
        self.part.colormap("inferno_r", self.clim, cell=True)

    def table(self):
        return self.model.rec.extraction.simplices

    def mask(self):
        alive = self.model.rec.extraction.alive(self.model.player.position)
        if type(self) is ManifoldAdapter and self.model.slicing and self.model.slice_cut:
            below = self.model.slice_values() <= 0  # the half-space cut: keep what lies below the slice
            alive = alive & below[self.model.rec.extraction.simplices].all(axis=1)
        return alive

    def step(self) -> None:
        self.update_cells()

    def pick(self, part, cell_id):
        row = self.model.candidate_row(self.row_of(cell_id))
        return None if row < 0 else ("simplex", row)


#: Colour map of the step that removed each simplex.
STEP_CMAP = "viridis"
#: Colours of the rules that remove simplices.
RULE_COLORS = {
    "prune-sharp": "#d62728",
    "resolve-nonmanifold": "#9467bd",
    "fill-hole": "#8c564b",
    "insert-sample": "#e377c2",
}


class RemovedAdapter(ManifoldAdapter):
    """Simplices removed by the steps up to the current position.

    ``removed_by(i)``, not ``~alive(i)``: in a robust run a simplex that is not
    yet added is not alive either, but it was never removed.  Coloured by the
    step that removed each simplex (``colorby == "step"``) or by its rule.
    """

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.scalar_title: str | None = None
        self.layer.events.colorby.connect(lambda *_: self.update_cells())

    def mask(self):
        return self.model.rec.extraction.removed_by(self.model.player.position)

    def update_cells(self, *_) -> None:
        super().update_cells()
        rec = self.model.rec
        if rec is None or self.drawing is None:
            return
        ext = rec.extraction
        how = self.layer.colorby
        if how == "step":
            set_cell_scalars(self.part.mesh, np.repeat(ext.removed_at[self.rows] + 1.0, self.drawing.per))
            self.scalar_title = "removed by step"
            self.part.colormap(STEP_CMAP, (1.0, float(max(ext.n_steps, 2))), cell=True)
        elif how == "rule":
            code = self.model.rule_codes()
            names = list(RULE_COLORS)
            rule_of = np.array([names.index(r) if r in names else 0 for r in code.names])
            values = rule_of[code.codes[np.minimum(ext.removed_at[self.rows], max(ext.n_steps - 1, 0))]] + 1.0
            set_cell_scalars(self.part.mesh, np.repeat(values, self.drawing.per))
            self.scalar_title = None
            self.part.use_lookup_table(_categorical(list(RULE_COLORS.values())), (1, len(names)), cell=True)
        else:
            self.scalar_title = None
            self.part.solid()

    def restyle(self) -> None:
        super().restyle()
        self.part.actor.prop.show_edges = False


class SliceAdapter(LayerAdapter):
    """The cross-section of M_S (at the current step) by the slicing hyperplane."""

    uses_step = True

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.model.slice_changed.connect(lambda *_: self.layer.visible and self.rebuild())

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        ext = rec.extraction
        simp = ext.simplices[ext.alive(self.model.player.position)]
        if rec.d > 3 or len(simp) == 0:
            self.xk, cells = np.zeros((0, rec.k)), np.zeros((0, rec.d), dtype=np.int64)
        else:
            u = self.model.slice_normal()
            c = self.model.slice_offset + float(self.model.projection.origin @ u)
            self.xk, cells = slice_complex(rec.points, simp, u, c)
        set_points(self.part.mesh, self.model.projection.project(self.xk) if len(self.xk) else np.zeros((0, 3)))
        if rec.d == 1:
            set_cells(self.part.mesh, verts=cells)
        elif rec.d == 2:
            set_cells(self.part.mesh, lines=cells)
        else:
            set_cells(self.part.mesh, polys=cells)
        self.layer.count = len(cells)

    def project(self) -> None:
        self.rebuild()  # the hyperplane is orthogonal to the hidden direction, which turns with the view

    def step(self) -> None:
        self.rebuild()

    def restyle(self) -> None:
        d = self.model.rec.d if self.model.rec is not None else 2
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=d == 2, spheres=d == 1)
        self.part.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(-2, -2)


class StepAdapter(LayerAdapter):
    """The step just applied: tau, the kept pair, the removed and the added simplices."""

    parts_spec = (("", True), ("-tau", True))
    uses_step = True

    def rebuild(self) -> None:
        self.step()

    def step(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        s = self.model.player.shown_step
        ext = rec.extraction
        kept = np.array(s.kept if s else (), dtype=np.int64)
        removed = np.array(s.removed if s else (), dtype=np.int64)
        added = np.array(s.added if s else (), dtype=np.int64)
        ids = np.concatenate([kept, removed, added])
        self.ids = ids
        self.tau = np.array(s.tau if s and s.rule not in PLACELESS_RULES else (), dtype=np.int64)
        # only the step's own vertices are projected (a step is a few simplices; the sample may be 10^6)
        table = ext.simplices[ids]
        self.verts = np.unique(np.concatenate([table.ravel(), self.tau]))
        self.tau_local = np.searchsorted(self.verts, self.tau)
        self.drawing = SimplexDrawing(np.searchsorted(self.verts, table), rec.d, 0.92 if rec.d >= 2 else 1.0)
        self.kind = np.concatenate([np.ones(len(kept)), 2 * np.ones(len(removed)), 3 * np.ones(len(added))])
        self.project()
        self.drawing.apply(self.part.mesh, None)
        set_cell_scalars(self.part.mesh, np.repeat(self.kind, self.drawing.per))
        if getattr(self, "_lut", None) is None:  # made once: a new table on every step costs a rebuild
            self._lut = _categorical([STEP_COLORS["kept"], STEP_COLORS["removed"], STEP_COLORS["added"]])
        if self.part.mapper.lookup_table is not self._lut:
            self.part.mapper.lookup_table = self._lut
        self.part.mapper.scalar_range = (1, 3)
        self.part.mapper.SetScalarModeToUseCellData()
        self.part.mapper.scalar_visibility = True
        # tau: a vertex (d=1), an edge (d=2) or a (d-1)-simplex drawn by its edges
        t = len(self.tau)
        if t == 1:
            set_cells(self.parts[1].mesh, verts=np.array([[0]]))
        elif t >= 2:
            pairs = np.array([(a, b) for a in range(t) for b in range(a + 1, t)])
            set_cells(self.parts[1].mesh, verts=np.arange(t)[:, None], lines=pairs)
        else:
            set_cells(self.parts[1].mesh)
        self.layer.count = 0 if s is None else 1

    def pick(self, part, cell_id):
        """A cell of the step's simplices selects that simplex; tau selects the face."""
        if part is self.parts[1]:
            return ("face", tuple(int(v) for v in self.tau)) if len(self.tau) else None
        if not hasattr(self, "ids") or self.drawing is None:
            return None
        row = self.model.candidate_row(int(self.ids[cell_id // self.drawing.per]))
        return None if row < 0 else ("simplex", row)

    def project(self) -> None:
        rec = self.model.rec
        if rec is None or not hasattr(self, "drawing"):
            return
        proj = self.model.projection.project(rec.points[self.verts])
        set_points(self.part.mesh, self.drawing.points(proj))
        set_points(self.parts[1].mesh, proj[self.tau_local] if len(self.tau) else np.zeros((0, 3)))

    def restyle(self) -> None:
        lines = self.model.rec is not None and self.model.rec.d == 1
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=lines)
        self.parts[1].style(
            STEP_COLORS["tau"],
            1.0,
            self.layer.size * (2.0 if len(getattr(self, "tau", ())) == 1 else 1.0),
            lines=True,
            spheres=False,
        )
        for p, off in ((self.part, -2), (self.parts[1], -4)):
            p.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(off, off)
            p.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(off, off)


def _categorical(colors: list[str]):
    import pyvista as pv

    lut = pv.LookupTable()
    lut.SetNumberOfTableValues(len(colors))
    for i, c in enumerate(colors):
        rgb = pv.Color(c).float_rgb
        lut.SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0)
    lut.SetRange(1, len(colors))
    return lut
