"""Base of the render adapters: one PolyData per part, updated in place.

An adapter wraps one :class:`~crustview.scene.Layer`.  It creates its
PolyData and actor once; later changes (projection, step, style) replace the
points, cells or scalars of the *same* PolyData, never the actor.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
from pyvista.plotting.mapper import _BaseDataSetMapper
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import VTK_TYPE_INT32, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray
from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLPolyDataMapper

from ..scene.layers import Layer
from ..scene.model import SceneModel

_EMPTY = np.zeros((0, 1), dtype=np.int64)

#: Colour of NaN scalars (e.g. the pole distance of a hull sample, whose pole is at infinity).
NAN_COLOR = "#b8b8b8"


def cell_array(cells: np.ndarray | None) -> vtkCellArray:
    """A vtkCellArray of fixed-size cells from an ``(m, w)`` integer array.

    int32 cells (with fewer than 2^31 entries) use VTK's 32-bit storage: half
    the bytes to copy, and no conversion inside ``SetData``.  That is most of
    a step's update of M_S at a million samples.
    """
    ca = vtkCellArray()
    if cells is None or len(cells) == 0:
        return ca
    cells = np.asarray(cells)
    narrow = cells.dtype == np.int32 and cells.size < 2**31
    if not narrow:
        cells = cells.astype(np.int64, copy=False)
    m, w = cells.shape
    kind = VTK_TYPE_INT32 if narrow else None
    # the offsets are a read-only view of a shared ramp: no copy per update (M_S changes every step)
    offsets = _ramp(w, m + 1, np.int32 if narrow else np.int64)
    conn = np.ascontiguousarray(cells).ravel()
    ca.SetData(numpy_to_vtk(offsets, deep=False, array_type=kind), numpy_to_vtk(conn, deep=True, array_type=kind))
    return ca


_RAMPS: dict[tuple[int, type], np.ndarray] = {}


def _ramp(w: int, count: int, dtype: type = np.int64) -> np.ndarray:
    """``arange(0, count * w, w)`` as a read-only view of a cached, grown-on-demand array."""
    got = _RAMPS.get((w, dtype))
    if got is None or len(got) < count:
        got = np.arange(0, max(count, 1024) * w, w, dtype=dtype)
        got.flags.writeable = False
        _RAMPS[(w, dtype)] = got
    return got[:count]


def set_points(mesh: pv.PolyData, pts: np.ndarray) -> None:
    """Replace the points of ``mesh`` (same object), shape ``(p, 3)``."""
    pts = np.ascontiguousarray(pts, dtype=float).reshape(-1, 3)
    vp = vtkPoints()
    vp.SetData(numpy_to_vtk(pts, deep=True))
    mesh.SetPoints(vp)
    mesh.Modified()


def set_cells(mesh: pv.PolyData, verts=None, lines=None, polys=None) -> None:
    """Replace the vertex, line and polygon cells of ``mesh`` in place."""
    mesh.SetVerts(cell_array(verts))
    mesh.SetLines(cell_array(lines))
    mesh.SetPolys(cell_array(polys))
    mesh.Modified()


def set_cell_scalars(mesh: pv.PolyData, values: np.ndarray, name: str = "values") -> None:
    """Attach one scalar per cell (verts, lines, polys order)."""
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
    arr.SetName(name)
    mesh.GetCellData().AddArray(arr)
    mesh.GetCellData().SetActiveScalars(name)
    mesh.Modified()


def set_point_scalars(mesh: pv.PolyData, values: np.ndarray, name: str = "values") -> None:
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
    arr.SetName(name)
    mesh.GetPointData().AddArray(arr)
    mesh.GetPointData().SetActiveScalars(name)
    mesh.Modified()


class PolyDataMapper(_BaseDataSetMapper, vtkOpenGLPolyDataMapper):
    """pyvista's mapper conveniences on a plain poly-data mapper.

    ``pyvista.DataSetMapper`` wraps vtkDataSetMapper, which runs a surface
    filter (a full copy) every time the PolyData changes; our layers are
    PolyData already, so the copy is pure cost on every step.
    """

    def __init__(self, dataset: pv.PolyData) -> None:
        super().__init__(dataset=dataset)


class Part:
    """One PolyData with its mapper and actor."""

    def __init__(self, plotter, name: str, pickable: bool = False) -> None:
        self.mesh = pv.PolyData()
        self.mapper = PolyDataMapper(self.mesh)
        self.mapper.scalar_visibility = False
        self.mapper.SetResolveCoincidentTopologyToPolygonOffset()
        self.actor = pv.Actor(mapper=self.mapper)
        self.actor.SetPickable(pickable)
        self.name = name
        plotter.add_actor(self.actor, name=name, reset_camera=False, pickable=pickable, render=False)

    @property
    def n_cells(self) -> int:
        return int(self.mesh.GetNumberOfCells())

    def style(self, color, opacity: float, size: float, *, lines: bool = False, spheres: bool = False) -> None:
        p = self.actor.prop
        p.color = color
        p.opacity = float(opacity)
        p.point_size = float(size)
        p.line_width = float(size if lines else max(1.0, size / 2))
        p.render_points_as_spheres = spheres

    def colormap(self, cmap: str, clim: tuple[float, float], cell: bool, n_colors: int = 256) -> None:
        """Colour by the active scalars of the mesh."""
        if getattr(self, "_lut", None) is None or self._cmap != (cmap, n_colors):
            self._lut = pv.LookupTable(cmap=cmap, n_values=n_colors)
            self._lut.nan_color = NAN_COLOR
            self._cmap = (cmap, n_colors)
        self._lut.scalar_range = clim
        if self.mapper.lookup_table is not self._lut:
            self.mapper.lookup_table = self._lut
        self.mapper.scalar_range = clim
        if cell:
            self.mapper.SetScalarModeToUseCellData()
        else:
            self.mapper.SetScalarModeToUsePointData()
        self.mapper.scalar_visibility = True

    def use_lookup_table(self, lut, clim: tuple[float, float], cell: bool) -> None:
        """Colour by the active scalars through a ready-made lookup table."""
        lut.scalar_range = clim
        self._lut, self._cmap = lut, None
        self.mapper.lookup_table = lut
        self.mapper.scalar_range = clim
        if cell:
            self.mapper.SetScalarModeToUseCellData()
        else:
            self.mapper.SetScalarModeToUsePointData()
        self.mapper.scalar_visibility = True

    def solid(self) -> None:
        self.mapper.scalar_visibility = False


class LayerAdapter:
    """Draws one layer of a :class:`SceneModel` with pyvista.

    Subclasses implement :meth:`rebuild` (new reconstruction),
    :meth:`project` (projection changed) and optionally :meth:`step`
    (position changed), :meth:`select` (selection changed) and :meth:`pick`.
    """

    #: Parts (PolyData + actor) the adapter creates, by suffix.
    parts_spec: tuple[tuple[str, bool], ...] = (("", False),)
    #: Which model events the adapter reacts to.
    uses_step = False
    uses_selection = False

    def __init__(self, model: SceneModel, layer: Layer, plotter) -> None:
        self.model = model
        self.layer = layer
        self.plotter = plotter
        self.parts = [Part(plotter, f"{layer.name}{suffix}", pickable) for suffix, pickable in self.parts_spec]
        self.xk = np.zeros((0, model.projection.k))  # ambient vertex coordinates
        self.apply_visibility()

    @property
    def part(self) -> Part:
        return self.parts[0]

    # -- events ------------------------------------------------------------
    def rebuild(self) -> None:
        """A new reconstruction was set."""

    def project(self) -> None:
        """The projection changed: move the vertices, keep the cells."""
        if len(self.xk) and self.xk.shape[1] == self.model.projection.k:
            set_points(self.part.mesh, self.model.projection.project(self.xk))

    def step(self) -> None:
        """The step position changed."""

    def select(self) -> None:
        """The selection changed."""

    def restyle(self) -> None:
        """Apply the layer's colour, opacity and size."""
        for p in self.parts:
            p.style(self.layer.color, self.layer.opacity, self.layer.size)

    def apply_visibility(self) -> None:
        for p in self.parts:
            p.actor.SetVisibility(bool(self.layer.visible))

    def pick(self, part: Part, cell_id: int) -> tuple[str, object] | None:
        """Map a picked cell to ``("sample", i)`` / ``("simplex", row)``."""
        return None

    def shown_cells(self) -> int:
        """Number of cells drawn (all parts)."""
        return sum(p.n_cells for p in self.parts)

    def remove(self) -> None:
        for p in self.parts:
            self.plotter.remove_actor(p.actor, render=False)
