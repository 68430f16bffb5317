"""Adapters of the per-sample layers: points, poles, normal planes, truth."""

from __future__ import annotations

import numpy as np
import pyvista as pv

from ..scene import geometry as geo
from ..scene.coloring import COORDINATE_COLORINGS
from ..scene.quantities import POLE_FINITE, POLE_INFINITE, POLE_NONE, pole_kinds
from ..scene.subset import even_subset, subset_note
from .base import NAN_COLOR, LayerAdapter, set_cells, set_point_scalars, set_points
from .filecolors import direct_colors

#: Colour maps of the points layer's colourings.
POINT_CMAPS = {"normal error": "magma_r", "pole distance": "viridis", "local spacing": "cividis"}


def epsilon_lut(bounds: dict[str, float], hi: float, n: int = 256) -> pv.LookupTable:
    """Colours of the estimated epsilon on ``[0, hi]`` with the paper's bounds as breaks.

    Below the smallest bound: blue to green (the theorems apply); between the
    bounds: yellow; above the largest: orange to dark red.  Each bound is an
    annotation (a labelled tick) on the colour bar.
    """
    lo_b, hi_b = min(bounds.values()), max(bounds.values())
    x = (np.arange(n) + 0.5) / n * hi
    good = np.array([[0.16, 0.35, 0.75], [0.15, 0.65, 0.35]])
    bad = np.array([[0.98, 0.55, 0.10], [0.45, 0.0, 0.05]])
    rgb = np.empty((n, 3))
    f = np.clip(x / max(lo_b, 1e-12), 0, 1)[:, None]
    rgb[:] = good[0] + f * (good[1] - good[0])
    mid = (x > lo_b) & (x <= hi_b)
    rgb[mid] = (0.93, 0.80, 0.10)
    over = x > hi_b
    g = np.clip((x[over] - hi_b) / max(hi - hi_b, 1e-12), 0, 1)[:, None]
    rgb[over] = bad[0] + g * (bad[1] - bad[0])
    lut = pv.LookupTable(values=np.c_[rgb * 255, np.full(n, 255)].astype(np.uint8))
    lut.nan_color = NAN_COLOR
    lut.scalar_range = (0.0, hi)
    names: dict[float, list[str]] = {}
    for name, b in bounds.items():
        names.setdefault(round(b, 6), []).append(name.replace("theorems ", "").replace("theorem ", ""))
    lut.annotations = {b: f"{b:.3g}: Thm {' & '.join(v)}" for b, v in names.items()}
    return lut


class PointsAdapter(LayerAdapter):
    """The samples, as points; optionally coloured by a per-sample quantity."""

    parts_spec = (("", True),)

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.layer.events.colorby.connect(self.recolor)
        self.scalar_title: str | None = None
        self.clim = (0.0, 1.0)
        self.n_missing = 0  # samples without a value (NaN, drawn in NAN_COLOR)

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        self.xk = rec.points
        self.project()
        set_cells(self.part.mesh, verts=np.arange(rec.n, dtype=np.int64)[:, None])
        self.layer.count = rec.n
        self.layer.total, self.layer.note = 0, ""  # drawn whole (the preview may have drawn a subset)
        self.recolor()

    def recolor(self, *_) -> None:
        got = self.model.point_values(self.layer.colorby) if self.model.rec is not None else None
        self.direct_rgb = False
        if got is None:
            self.scalar_title = None
            self.n_missing = 0
            self.part.solid()
            return
        values, title = got
        direct_colors(self.part, values if values.ndim == 2 else None)  # the file's own RGB, or mapped scalars
        self.direct_rgb = values.ndim == 2
        if self.direct_rgb:
            self.scalar_title, self.n_missing = None, 0
            return
        set_point_scalars(self.part.mesh, values)
        ok = values[np.isfinite(values)]
        self.n_missing = len(values) - len(ok)
        self.scalar_title = title
        if self.layer.colorby == "epsilon":
            bounds = self.model.quality.thresholds
            # the largest bound sits at a quarter of the bar: room for the undersampled tail
            self.clim = (0.0, 4.0 * max(bounds.values()))
            self.part.use_lookup_table(epsilon_lut(bounds, self.clim[1]), self.clim, cell=False)
            return
        by_place = self.layer.colorby in COORDINATE_COLORINGS  # positions: the whole range, no outliers
        hi = float(np.percentile(ok, 100 if by_place else 98)) if len(ok) else 1.0
        lo = float(ok.min()) if len(ok) else 0.0
        self.clim = (lo, max(hi, lo + 1e-12))
        self.n_missing = len(values) - len(ok)
        self.scalar_title = title
        self.part.colormap(POINT_CMAPS.get(self.layer.colorby, "viridis"), self.clim, cell=False)

    def project(self) -> None:
        super().project()
        if self.layer.colorby == "hidden depth":  # the hidden direction turns with the view
            self.recolor()

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, spheres=False)

    def pick(self, part, cell_id):
        return ("sample", int(cell_id))


def lighter(color, amount: float = 0.4) -> tuple[float, float, float]:
    """``color`` blended with white (``amount`` = share of white)."""
    rgb = np.array(pv.Color(color).float_rgb)
    return tuple(float(v) for v in rgb + amount * (1.0 - rgb))


#: Length of the pole ticks drawn for every sample in R^4 and up, in local spacings.
TICK_SPACINGS = 1.5


def _tick(a: np.ndarray, b: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Points at most ``length`` from ``a`` towards ``b`` (row-wise)."""
    v = b - a
    n = np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)
    return a + v / n * np.minimum(n, length[:, None])


class PolesAdapter(LayerAdapter):
    """Poles of every sample or of the selected sample, joined to the sample.

    Finite poles are drawn as a segment to a dot.  The first pole of a sample
    on the convex hull is a vertex at infinity: it is drawn, in a lighter
    colour, as a ray in its direction up to the edge of the clipping box.
    Poles that do not exist (flat input, ``pole_index == -1``) are skipped.
    With every sample's poles in R^4 and up, each is a short tick towards
    its pole (:data:`TICK_SPACINGS` local spacings), without end dots.
    """

    parts_spec = (("", False), ("-ends", False), ("-inf", False))
    uses_selection = True

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.layer.events.mode.connect(lambda *_: self.rebuild())
        self.ends = np.zeros((0, self.model.projection.k))
        self.rays = np.zeros((0, self.model.projection.k))
        self.n_infinite = 0

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        if self.layer.mode == "all":
            idx = even_subset(rec.n)
        elif self.model.selection.sample is not None:
            idx = np.array([self.model.selection.sample])
        else:
            idx = np.zeros(0, dtype=np.int64)
        c = rec.pole_index.shape[1]
        kind = pole_kinds(rec)[idx].ravel()
        owner = np.repeat(idx, c)
        pole = rec.pole_index[idx].ravel()
        lo, hi = self.model.box
        # finite poles: segment sample -> pole, clipped, and a dot when inside the box
        fin = kind == POLE_FINITE
        a = rec.points[owner[fin]]
        b = rec.voronoi_vertices[pole[fin]]
        ticks = self.layer.mode == "all" and rec.k >= 4
        if ticks:  # R^4 and up: thousands of long lines hide everything; short ticks show the directions
            b = _tick(a, b, TICK_SPACINGS * self.model.spacing[owner[fin]])
        inside = np.all((b >= lo) & (b <= hi), axis=1) & (not ticks)
        a2, b2, _ = geo.clip_segments(a, b, lo, hi)
        self.xk = np.vstack([a2, b2]) if len(a2) else np.zeros((0, rec.k))
        m = len(a2)
        set_cells(self.part.mesh, lines=np.stack([np.arange(m), np.arange(m) + m], axis=1))
        self.ends = b[inside]
        set_cells(self.parts[1].mesh, verts=np.arange(len(self.ends))[:, None])
        # vertices at infinity: rays to the edge of the box
        inf = kind == POLE_INFINITE
        s = rec.points[owner[inf]]
        u = rec.voronoi_vertices[pole[inf]] - s
        u /= np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-300)
        reach = 2.0 * float(np.linalg.norm(hi - lo))
        if ticks:
            reach = TICK_SPACINGS * self.model.spacing[owner[inf]][:, None]
        a3, b3, _ = geo.clip_segments(s, s + reach * u, lo, hi)
        self.rays = np.vstack([a3, b3]) if len(a3) else np.zeros((0, rec.k))
        r = len(a3)
        set_cells(self.parts[2].mesh, lines=np.stack([np.arange(r), np.arange(r) + r], axis=1))
        self.n_infinite = int(inf.sum())
        self.layer.count = int(fin.sum() + inf.sum())
        thinned = self.layer.mode == "all" and len(idx) < rec.n
        self.layer.total = int((pole_kinds(rec) != POLE_NONE).sum()) if thinned else 0
        self.layer.note = subset_note("Poles", len(idx), rec.n) if thinned else ""
        self.project()

    def project(self) -> None:
        proj = self.model.projection
        for mesh, xk in ((self.part.mesh, self.xk), (self.parts[1].mesh, self.ends), (self.parts[2].mesh, self.rays)):
            if xk.shape[1] == proj.k:
                set_points(mesh, proj.project(xk) if len(xk) else np.zeros((0, 3)))

    def select(self) -> None:
        if self.layer.mode != "all":
            self.rebuild()

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, max(1.0, self.layer.size / 3), lines=True)
        self.parts[1].style(self.layer.color, self.layer.opacity, self.layer.size, spheres=False)
        self.parts[2].style(lighter(self.layer.color), self.layer.opacity, max(1.0, self.layer.size / 3), lines=True)


class NormalsAdapter(LayerAdapter):
    """Glyphs of the estimated normal planes AN_s, scaled to the local spacing."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._built_size: float | None = None

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        # half-length: 0.45 spacing on surfaces; longer on curves, where sample markers cover short ones
        scale = (0.45 if rec.d >= 2 else 1.5) * self.layer.size * self.model.spacing
        idx = even_subset(rec.n)
        scale = scale[idx] if np.ndim(scale) else scale
        verts, lines, polys = geo.normal_glyphs(rec.points[idx], rec.normals[idx], scale)
        self.xk = verts
        self.project()
        set_cells(self.part.mesh, lines=lines, polys=polys)
        self.layer.count = len(idx)
        self.layer.total = rec.n if len(idx) < rec.n else 0
        self.layer.note = subset_note("Normal planes", len(idx), rec.n)
        self._built_size = self.layer.size

    def restyle(self) -> None:
        if self._built_size is not None and self._built_size != self.layer.size:
            self.rebuild()
        self.part.style(self.layer.color, self.layer.opacity, 4.0, lines=False)
        self.part.actor.prop.line_width = 2.0
        # in front of coincident lines (flat 2-D data: Voronoi edges run along the normals)
        self.part.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(-1, -1)
        self.part.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(-1, -1)


def _outward(faces: np.ndarray, points: np.ndarray) -> np.ndarray | None:
    """The triangles oriented so that the volume they bound is positive.

    None when they are not a closed surface oriented consistently (an edge used twice in the same direction,
    or once: then no face can be told facing away).
    """
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    if len(np.unique(directed, axis=0)) != len(directed):
        return None
    # closed: every directed edge's reverse is there too (an open scan's enclosed volume depends on the origin)
    both = np.unique(np.concatenate([directed, directed[:, ::-1]]), axis=0)
    if len(both) != len(directed):
        return None
    a, b, c = (points[faces[:, i]] for i in range(3))
    volume = float(np.einsum("ij,ij->", a, np.cross(b, c))) / 6.0
    return faces if volume >= 0 else faces[:, ::-1]


class TruthAdapter(LayerAdapter):
    """The ground truth, faint: a dense sample of a built-in manifold, or a mesh file's faces.

    A mesh's faces are drawn as a wireframe, never as a surface: a shaded
    truth would look like a result where M_S has nothing yet.
    """

    N_DENSE = 20_000

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._pending = True

    def rebuild(self) -> None:
        self._pending = True
        self.xk = np.zeros((0, self.model.projection.k))
        set_cells(self.part.mesh)
        truth = self.model.truth
        faces = getattr(truth, "faces", None)
        self.layer.count = 0 if truth is None else (len(faces) if faces is not None else self.N_DENSE)
        if self.layer.visible:
            self._load()

    def _load(self) -> None:
        truth = self.model.truth
        self._pending = False
        if truth is None or self.model.rec is None:
            return
        if getattr(truth, "faces", None) is not None:
            self._load_faces(truth)
            return
        self._in_scene(False)
        ref = np.asarray(truth.manifold.reference(self.N_DENSE), float)
        if ref.shape[1] != self.model.rec.k:
            return
        self.xk = ref
        self.project()
        set_cells(self.part.mesh, verts=np.arange(len(ref))[:, None])
        self.layer.count = len(ref)

    def _load_faces(self, truth) -> None:
        """Mesh faces: triangles (d = 2), segments (d = 1), or edges of higher simplices."""
        pts = np.asarray(truth.points, float)
        if pts.shape[1] != self.model.rec.k:
            return
        faces = np.asarray(truth.faces, dtype=np.int64)
        self.xk = pts
        self.project()
        cull = False
        if faces.shape[1] == 3:
            outward = _outward(faces, pts) if pts.shape[1] == 3 else None
            cull = outward is not None
            set_cells(self.part.mesh, polys=faces if outward is None else outward)
        elif faces.shape[1] == 2:
            set_cells(self.part.mesh, lines=faces)
        else:
            pairs = [faces[:, [i, j]] for i in range(faces.shape[1]) for j in range(i + 1, faces.shape[1])]
            edges = np.unique(np.sort(np.concatenate(pairs), axis=1), axis=0)
            set_cells(self.part.mesh, lines=edges)
        self.layer.count = len(faces)
        # drawn over the scene, a dense mesh's far side and the parts inside other parts showed through as a
        # grey tangle (a gear set's long CAD edges): a mesh's faces are drawn in the scene, where M_S hides
        # what lies behind it, and only those towards the camera where the mesh's orientation says which
        self._cull_faces = cull
        self._cull()
        self._in_scene(True)

    def project(self) -> None:
        super().project()
        self._cull()

    def _cull(self) -> None:
        """Cull the faces turned away from the camera.

        The back faces, or the front ones where the view's projection is a reflection (a PCA basis or a
        swapped axis order in R^3); none where it is not linear.
        """
        on = bool(getattr(self, "_cull_faces", False))
        proj = self.model.projection
        flip = False
        if on and proj.k == 3 and not proj.stereographic:
            linear = proj.project(np.eye(3)) - proj.project(np.zeros(3))
            flip = bool(np.linalg.det(linear) < 0)
        elif on:
            on = False
        prop = self.part.actor.GetProperty()
        prop.SetBackfaceCulling(on and not flip)
        prop.SetFrontfaceCulling(on and flip)

    def _in_scene(self, scene: bool) -> None:
        """Draw this layer in the scene's renderer (hidden behind M_S) or in the overlay over it.

        The overlay is for a built-in's dense sample: faint points that M_S would half cover where the two
        nearly coincide.
        """
        main = self.plotter.renderer
        top = getattr(self, "overlay", None)
        if top is None:
            return
        want, other = (main, top) if scene else (top, main)
        for part in self.parts:
            if other.HasViewProp(part.actor):
                other.RemoveActor(part.actor)
                want.AddActor(part.actor)

    def apply_visibility(self) -> None:
        super().apply_visibility()
        if self.layer.visible and getattr(self, "_pending", False):
            self._load()

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size)
        self.part.actor.prop.style = "wireframe"  # faces as edges; a dense sample stays points
        self.part.actor.prop.line_width = max(1.0, self.layer.size / 2)

    def legend_label(self) -> str:
        """How the legend names the truth, so that it is never taken for the result."""
        if getattr(self.model.truth, "faces", None) is not None:
            return "ground truth: the mesh's faces (wireframe, not the result)"
        return "ground truth: dense sample of the true manifold"
