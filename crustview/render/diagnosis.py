"""Adapters of the layers that say why an extraction failed: holes of T_S, a prune cascade."""

from __future__ import annotations

import numpy as np
import pyvista as pv

from ..scene import geometry as geo
from .base import LayerAdapter, set_cells, set_points
from .complexes import SimplexDrawing


def face_cells(faces: np.ndarray) -> dict[str, np.ndarray]:
    """VTK cells of (d-1)-faces given as rows of vertex ids into the drawn points.

    A vertex (d = 1) is a point, an edge (d = 2) a line, a triangle (d = 3) a
    polygon; larger faces are drawn by their boundary triangles.
    """
    faces = np.asarray(faces, dtype=np.int64)
    w = faces.shape[1] if faces.ndim == 2 else 0
    if len(faces) == 0 or w == 0:
        return {}
    if w == 1:
        return {"verts": faces}
    if w == 2:
        return {"lines": faces}
    if w == 3:
        return {"polys": faces}
    local = geo.simplex_triangles(w - 1)
    return {"polys": faces[:, local].reshape(-1, 3)}


class HolesAdapter(LayerAdapter):
    """The holes of T_S: (d-1)-faces in a single candidate simplex before extraction.

    Drawn by rim (:mod:`crustview.scene.holes`): the rim faces as lines (dots
    for curves, triangles for 3-manifolds), a surface rim's patch faintly
    shaded, and the largest rims labelled with their size (up to
    :attr:`LABELLED`, none over a bigger one's on the screen); the legend names
    how many there are and the largest.
    """

    parts_spec = (("", False), ("-patch", False))
    #: How many of the largest rims get a label in the view.
    LABELLED = 5

    def __init__(self, *args) -> None:
        super().__init__(*args)
        from vtkmodules.vtkRenderingCore import vtkActor2D
        from vtkmodules.vtkRenderingLabel import vtkLabeledDataMapper

        self.rims: list = []
        self.label_points = pv.PolyData()
        self.label_mapper = vtkLabeledDataMapper()
        self.label_mapper.SetInputData(self.label_points)
        self.label_mapper.SetLabelModeToLabelFieldData()
        self.label_mapper.SetFieldDataName("labels")
        tp = self.label_mapper.GetLabelTextProperty()
        tp.SetFontSize(13)
        tp.SetColor(*pv.Color(self.layer.color).float_rgb)
        tp.SetBold(True)
        tp.SetBackgroundColor(1.0, 1.0, 1.0)
        tp.SetBackgroundOpacity(0.8)
        tp.SetShadow(False)
        tp.SetJustificationToCentered()
        tp.SetVerticalJustificationToCentered()
        self.label_actor = vtkActor2D()
        self.label_actor.SetMapper(self.label_mapper)
        self.label_actor.SetPickable(False)
        self.plotter.renderer.AddViewProp(self.label_actor)
        self.label_actor.SetVisibility(bool(self.layer.visible))
        self.labels: list[str] = []
        self._label_xk = np.zeros((0, self.model.projection.k))
        self._label_p3 = np.zeros((0, 3))
        self._placed: tuple = ()
        self.plotter.renderer.AddObserver("StartEvent", self.place_labels)

    def rebuild(self) -> None:
        from ..scene.holes import hole_rims, rim_patches

        rec = self.model.rec
        if rec is None:
            return
        holes = self.model.holes()
        self.rims = hole_rims(holes, rec.points, self.model.spacing)
        centres, patch = rim_patches(self.rims, rec.n)
        self.xk = np.vstack([rec.points, centres]) if len(centres) else rec.points
        # candidates: a few more than are shown; each frame drops a label that would cover a bigger one's
        big = list(enumerate(self.rims[: 2 * self.LABELLED]))  # (rank among all holes, rim)
        # short, and centred on the hole: a label near the view's edge is not cut off as soon
        unit = {1: "end", 2: "edge", 3: "triangle"}.get(rec.d, "face")
        self.labels = [
            f"hole {rank + 1}: {r.size:,} {unit}{'' if r.size == 1 else 's'}, {r.span:.0f} spacings" for rank, r in big
        ]
        self._label_xk = np.array([r.centre for _, r in big]).reshape(-1, rec.k)
        self._label_p3 = np.zeros((0, 3))
        self._placed: tuple = ()
        self.project()
        set_cells(self.part.mesh, **face_cells(holes))
        set_cells(self.parts[1].mesh, polys=patch if len(patch) else None)
        self.layer.count = len(self.rims)  # holes, as the legend counts them (their faces are drawn one line each)

    def project(self) -> None:

        proj = self.model.projection
        if not len(self.xk) or self.xk.shape[1] != proj.k:
            return
        p3 = proj.project(self.xk)
        set_points(self.part.mesh, p3)
        set_points(self.parts[1].mesh, p3)
        self._label_p3 = proj.project(self._label_xk) if len(self.labels) else np.zeros((0, 3))
        self._placed = ()  # placed again at the next frame
        self._show_labels(list(range(min(self.LABELLED, len(self.labels)))))

    def _show_labels(self, chosen: list[int]) -> None:
        from vtkmodules.vtkCommonCore import vtkStringArray

        if tuple(chosen) == self._placed:
            return
        self._placed = tuple(chosen)
        set_points(self.label_points, self._label_p3[chosen] if chosen else np.zeros((0, 3)))
        names = vtkStringArray()
        names.SetName("labels")
        for i in chosen:
            names.InsertNextValue(self.labels[i])
        self.label_points.GetPointData().AddArray(names)
        self.label_points.Modified()

    def place_labels(self, *_) -> None:
        """Before each frame: the largest holes' labels, leaving out one that would cover a bigger one's.

        Up to :attr:`LABELLED`, judged on the screen (a label is about 7 px a
        character wide and 18 px high).
        """
        if not self.layer.visible or not len(self._label_p3):
            return
        from .fitting import display_points

        xy = display_points(self.plotter.renderer, self._label_p3)
        boxes: list = []
        chosen: list[int] = []
        for i, (x, y) in enumerate(xy):
            half = 3.6 * len(self.labels[i]) + 4
            box = (x - half, y - 10, x + half, y + 10)
            if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in boxes):
                continue
            boxes.append(box)
            chosen.append(i)
            if len(chosen) == self.LABELLED:
                break
        self._show_labels(chosen)

    def placed_labels(self) -> list[str]:
        """The labels drawn at the last frame, largest hole first."""
        return [self.labels[i] for i in self._placed]

    def legend_label(self) -> str:
        """The legend's line: how many holes, and the largest one's size."""
        from ..scene.holes import holes_summary

        return holes_summary(self.rims, self.model.rec.d if self.model.rec is not None else 2)

    def apply_visibility(self) -> None:
        super().apply_visibility()
        if hasattr(self, "label_actor"):
            self.label_actor.SetVisibility(bool(self.layer.visible))

    def restyle(self) -> None:
        d = self.model.rec.d if self.model.rec is not None else 2
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size * 0.6, lines=d == 2, spheres=False)
        self.part.actor.prop.point_size = self.layer.size * 2.0
        self.parts[1].style(self.layer.color, 0.25 * self.layer.opacity, 1.0)
        self.label_mapper.GetLabelTextProperty().SetColor(*pv.Color(self.layer.color).float_rgb)
        for p in self.parts:
            p.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(-3, -3)
            p.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(-3, -3)


class CascadeAdapter(LayerAdapter):
    """The highlighted prune cascade: every simplex its steps removed, and its origin face.

    Drawn in the overlay renderer (like the current step): the cascade mostly
    lies where M_S no longer is, or inside it.
    """

    parts_spec = (("", False), ("-origin", False))

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.model.cascade_changed.connect(lambda *_: self.rebuild())
        self.drawing: SimplexDrawing | None = None
        self.tau = np.zeros(0, dtype=np.int64)

    def rebuild(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        ids = self.model.cascade_simplices()
        c = self.model.cascade
        self.drawing = SimplexDrawing(rec.extraction.simplices[ids], rec.d, 0.92 if rec.d >= 3 else 1.0)
        self.tau = np.array(c.tau if c is not None else (), dtype=np.int64)
        self.project()
        self.drawing.apply(self.part.mesh, None)
        set_cells(
            self.parts[1].mesh,
            **face_cells(np.arange(len(self.tau))[None] if len(self.tau) else np.zeros((0, 0), np.int64)),
        )
        if len(self.tau) == 2:  # an edge: its end points too, so it reads at any zoom
            set_cells(self.parts[1].mesh, verts=np.array([[0], [1]]), lines=np.array([[0, 1]]))
        self.layer.count = len(ids)

    def project(self) -> None:
        rec = self.model.rec
        if rec is None or self.drawing is None:
            return
        proj = self.model.projection.project(rec.points)
        set_points(self.part.mesh, self.drawing.points(proj))
        set_points(self.parts[1].mesh, proj[self.tau] if len(self.tau) else np.zeros((0, 3)))

    def restyle(self) -> None:
        lines = self.model.rec is not None and self.model.rec.d == 1
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=lines)
        self.parts[1].style("#000000", 1.0, self.layer.size * 1.5, lines=True, spheres=False)
        self.parts[1].actor.prop.point_size = self.layer.size * 2.5
        for p, off in ((self.part, -1), (self.parts[1], -5)):
            p.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(off, off)
            p.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(off, off)


class UncertainAdapter(LayerAdapter):
    """The features of the final M_S the sample does not support (:mod:`crustview.scene.features`).

    A handle's loop and a hole's rim as thick lines, a component's closest
    approach as a segment with a big dot; drawn in the overlay renderer, so a
    loop on the far side of M_S still shows.
    """

    parts_spec = (("", False), ("-markers", False))

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.markers = np.zeros(0, dtype=np.int64)

    def rebuild(self) -> None:
        from ..scene.features import feature_lines, uncertain_features

        rec = self.model.rec
        if rec is None:
            return
        feats = uncertain_features(rec)
        self.xk, lines, self.markers = feature_lines(rec, feats)
        self.project()
        set_cells(self.part.mesh, lines=lines)
        set_cells(self.parts[1].mesh, verts=np.arange(len(self.markers))[:, None])
        self.layer.count = len(feats)

    def project(self) -> None:
        proj = self.model.projection
        if self.xk.shape[1] != proj.k:
            return
        p3 = proj.project(self.xk) if len(self.xk) else np.zeros((0, 3))
        set_points(self.part.mesh, p3)
        set_points(self.parts[1].mesh, p3[self.markers] if len(self.markers) else np.zeros((0, 3)))

    def restyle(self) -> None:
        self.part.style(self.layer.color, self.layer.opacity, self.layer.size, lines=True)
        self.parts[1].style(self.layer.color, self.layer.opacity, self.layer.size * 3.0, spheres=True)


class OrientationAdapter(LayerAdapter):
    """The one-sided loop of a non-orientable M_S: a line through its triangles over a faint band of them.

    In the overlay renderer, so the whole loop shows, also where it runs behind M_S.
    """

    parts_spec = (("", False), ("-band", False))

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.band = np.zeros((0, 3), dtype=np.int64)
        self.path = np.zeros((0, self.model.projection.k))

    def rebuild(self) -> None:
        from ..scene.orientation import loop_polyline

        rec = self.model.rec
        if rec is None:
            return
        loop = self.model.one_sided_loop()
        tris = np.asarray(rec.manifold, dtype=np.int64).reshape(-1, rec.d + 1)
        self.path = loop_polyline(rec.points, tris, loop) if len(loop) else np.zeros((0, rec.k))
        self.band = tris[loop] if len(loop) else np.zeros((0, 3), dtype=np.int64)
        self.project()
        m = len(self.path)
        set_cells(self.part.mesh, lines=np.stack([np.arange(m), (np.arange(m) + 1) % m], axis=1) if m else None)
        set_cells(self.parts[1].mesh, polys=self.band if len(self.band) else None)
        self.layer.count = len(loop)

    def project(self) -> None:
        rec = self.model.rec
        proj = self.model.projection
        if rec is None or rec.k != proj.k:
            return
        set_points(self.part.mesh, proj.project(self.path) if len(self.path) else np.zeros((0, 3)))
        set_points(self.parts[1].mesh, proj.project(rec.points))

    def restyle(self) -> None:
        self.part.style(self.layer.color, 1.0, self.layer.size, lines=True)
        self.parts[1].style(self.layer.color, self.layer.opacity, 1.0)
