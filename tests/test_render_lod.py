"""Level of detail and glyph subsets (render tier, no Qt)."""

import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy

from crustview.render.base import Part, set_cell_scalars, set_cells, set_points
from crustview.render.lod import LevelOfDetail, strided_copy
from crustview.scene.subset import even_subset, subset_note


def _mesh(m: int = 1000) -> pv.PolyData:
    mesh = pv.PolyData()
    set_points(mesh, np.random.default_rng(0).normal(size=(m + 2, 3)))
    tris = np.stack([np.arange(m), np.arange(m) + 1, np.arange(m) + 2], axis=1)
    set_cells(mesh, verts=np.arange(10)[:, None], polys=tris)
    set_cell_scalars(mesh, np.arange(10 + m, dtype=float))  # one value per cell: verts, then polys
    return mesh


def test_strided_copy_keeps_every_sth_cell_with_its_own_scalar():
    mesh = _mesh()
    thin = strided_copy(mesh, 7)
    assert thin.GetPoints() is mesh.GetPoints() or thin.n_points == mesh.n_points
    polys = vtk_to_numpy(thin.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    assert np.array_equal(polys[:, 0], np.arange(0, 1000, 7))
    assert thin.GetVerts().GetNumberOfCells() == len(range(0, 10, 7))
    values = vtk_to_numpy(thin.GetCellData().GetArray("values"))
    want = np.concatenate([np.arange(0, 10, 7), 10 + np.arange(0, 1000, 7)])
    assert np.array_equal(values, want)
    assert thin.GetCellData().GetScalars().GetName() == "values"


def test_level_of_detail_thins_only_big_visible_parts_and_restores_them():
    plotter = pv.Plotter(off_screen=True)
    big, small = Part(plotter, "big"), Part(plotter, "small")
    for part, m in ((big, 5000), (small, 50)):
        mesh = _mesh(m)
        set_points(part.mesh, np.asarray(mesh.points))
        set_cells(part.mesh, polys=vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3))
    lod = LevelOfDetail(plotter.renderer, budget=1000)
    assert lod.begin([big, small])
    assert lod.drawn() == {"big": (1000, 5000)}
    assert not big.actor.GetVisibility() and small.actor.GetVisibility()
    # a changed mesh is thinned again on the next begin
    set_cells(big.mesh, polys=np.array([[0, 1, 2]] * 3000))
    lod.begin([big, small])
    assert lod.drawn() == {"big": (1000, 3000)}
    assert lod.end() and big.actor.GetVisibility() and not lod.active
    plotter.close()


def test_even_subset_and_its_note():
    assert np.array_equal(even_subset(10, 20), np.arange(10))
    idx = even_subset(1_000_000, 100_000)
    assert len(idx) == 100_000 and np.all(np.diff(idx) == 10)
    assert subset_note("Normal planes", 10, 10) == ""
    assert subset_note("Normal planes", 100_000, 1_000_000).startswith(
        "Normal planes: drawn 100,000 of 1,000,000 (every 10th sample)"
    )
