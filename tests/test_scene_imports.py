"""The layering of the viewer: the scene model imports no Qt/VTK, render no Qt."""

import subprocess
import sys


def loaded_after(module: str) -> set[str]:
    code = f"import sys, {module}; print(' '.join(sorted({{m.split('.')[0] for m in sys.modules}})))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(out.stdout.split())


def test_scene_is_qt_and_vtk_free():
    mods = loaded_after("crustview.scene")
    assert not mods & {"PySide6", "pyvista", "pyvistaqt", "vtkmodules", "vtk"}


def test_render_is_qt_free():
    mods = loaded_after("crustview.render")
    assert "pyvista" in mods
    assert not mods & {"PySide6", "pyvistaqt"}
