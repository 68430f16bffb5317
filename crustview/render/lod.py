"""Level of detail: big layers drawn as a strided subset while the view moves or steps.

Software OpenGL (llvmpipe, the only kind on these machines) draws about
2 million triangles a second, and a million-sample torus has 2 million
triangles in M_S and a million sample points.  A full frame then takes over
a second, which stalls rotation and stepping.  While the user drags the view
or steps through Algorithm 3, every visible part with more than
:data:`LOD_CELLS` cells is replaced by a copy holding every s-th of its cells
(same points, point data, colours and property); the whole part comes back
for the frame drawn once the motion stops.  The current step's simplices are
in the overlay renderer, never thinned, so what a step changes stays on
screen.

The subset is a view of the part's own arrays (one gather of 1/s of the
cells), so starting the level of detail costs a few milliseconds.
"""

from __future__ import annotations

import math

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy

from .base import Part, PolyDataMapper, cell_array

#: Parts with more cells than this are thinned while the view moves.
LOD_CELLS = 40_000


def _fixed_width(ca) -> tuple[np.ndarray, int] | None:  # noqa: ANN001 - a vtkCellArray
    """Connectivity of a cell array whose cells all have one size, as (m, w); None otherwise."""
    m = ca.GetNumberOfCells()
    if m == 0:
        return np.zeros((0, 1), dtype=np.int64), 1
    offsets = vtk_to_numpy(ca.GetOffsetsArray())
    conn = vtk_to_numpy(ca.GetConnectivityArray())
    w = len(conn) // m
    if w * m != len(conn) or offsets[0] != 0 or not (np.diff(offsets) == w).all():
        return None
    return conn.reshape(m, w), w


def strided_copy(mesh: pv.PolyData, stride: int) -> pv.PolyData | None:
    """Every ``stride``-th vertex, line and polygon cell of ``mesh`` with the same points.

    Point data is shared; cell data arrays are subset alongside the cells.
    Returns None when a cell array mixes cell sizes (not written by
    :func:`~crustview.render.base.set_cells`).
    """
    out = pv.PolyData()
    out.SetPoints(mesh.GetPoints())
    out.GetPointData().ShallowCopy(mesh.GetPointData())
    kept, start = [], 0
    for get, put in ((mesh.GetVerts, out.SetVerts), (mesh.GetLines, out.SetLines), (mesh.GetPolys, out.SetPolys)):
        got = _fixed_width(get())
        if got is None:
            return None
        conn, _ = got
        keep = np.arange(0, len(conn), stride)
        if len(keep):
            put(cell_array(conn[keep]))
        kept.append(start + keep)
        start += len(conn)
    rows = np.concatenate(kept)
    cd, od = mesh.GetCellData(), out.GetCellData()
    active = cd.GetScalars().GetName() if cd.GetScalars() is not None else None
    for i in range(cd.GetNumberOfArrays()):
        arr = cd.GetArray(i)
        if arr is None or arr.GetNumberOfTuples() != start:
            continue
        values = vtk_to_numpy(arr)[rows]
        out.cell_data[arr.GetName()] = values
    if active is not None and active in out.cell_data:
        od.SetActiveScalars(active)
    return out


class _Swap:
    """One part drawn thinned: its own mapper and actor, sharing the part's property."""

    def __init__(self, part: Part, renderer, budget: int) -> None:  # noqa: ANN001
        self.part, self.renderer, self.budget = part, renderer, budget
        self.mapper = PolyDataMapper(pv.PolyData())
        self.actor = pv.Actor(mapper=self.mapper)
        self.actor.SetProperty(part.actor.GetProperty())
        self.actor.SetPickable(False)
        self.built = -1
        self.refresh()
        renderer.AddActor(self.actor)
        part.actor.SetVisibility(False)

    def refresh(self) -> None:
        """Re-thin when the part's mesh changed since the last time."""
        mt = self.part.mesh.GetMTime()
        if mt == self.built:
            return
        thin = strided_copy(self.part.mesh, max(1, math.ceil(self.part.n_cells / self.budget)))
        if thin is None:
            return
        self.mapper.SetInputData(thin)
        src = self.part.mapper
        self.mapper.SetLookupTable(src.GetLookupTable())
        self.mapper.SetScalarRange(src.GetScalarRange())
        self.mapper.SetScalarMode(src.GetScalarMode())
        self.mapper.SetScalarVisibility(src.GetScalarVisibility())
        self.mapper.SetResolveCoincidentTopologyToPolygonOffset()
        self.built = mt

    def undo(self) -> None:
        self.renderer.RemoveActor(self.actor)
        self.part.actor.SetVisibility(True)


class LevelOfDetail:
    """Thins the big visible parts of a scene while active (see module docstring).

    Parameters
    ----------
    renderer : vtkRenderer
        The scene's main renderer; parts in other renderers (the overlay of
        the current step) are never thinned.
    budget : int
        Cells a part may keep; bigger ones are drawn with every s-th cell,
        ``s = ceil(cells / budget)`` (again after each change of the part).
    """

    def __init__(self, renderer, budget: int = LOD_CELLS) -> None:  # noqa: ANN001
        self.renderer = renderer
        self.budget = int(budget)
        self.swaps: dict[int, _Swap] = {}

    @property
    def active(self) -> bool:
        return bool(self.swaps)

    def begin(self, parts: list[Part]) -> bool:
        """Thin every visible part above the budget (again if they changed); True if any is thinned."""
        for part in parts:
            swap = self.swaps.get(id(part))
            if swap is not None:
                swap.refresh()
                continue
            n = part.n_cells
            if n <= self.budget or not part.actor.GetVisibility() or not self.renderer.HasViewProp(part.actor):
                continue
            self.swaps[id(part)] = _Swap(part, self.renderer, self.budget)
        return self.active

    def end(self) -> bool:
        """Draw every part whole again; True if anything was thinned."""
        had = self.active
        for swap in self.swaps.values():
            swap.undo()
        self.swaps.clear()
        return had

    def drawn(self) -> dict[str, tuple[int, int]]:
        """``{part name: (cells drawn, cells in the part)}`` of the thinned parts."""
        out = {}
        for swap in self.swaps.values():
            thin = swap.mapper.GetInput()
            out[swap.part.name] = (int(thin.GetNumberOfCells()) if thin is not None else 0, swap.part.n_cells)
        return out
