"""Drawing the samples in the colours their file gave them (direct RGB scalars, no lookup table)."""

from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk


def direct_colors(part, rgb: np.ndarray | None) -> None:
    """Colour ``part``'s points by ``rgb`` ((n, 3) in [0, 1]) as they are; None returns to mapped scalars."""
    if rgb is None:
        part.mapper.SetColorModeToDefault()
        return
    arr = numpy_to_vtk(np.ascontiguousarray(np.clip(rgb, 0, 1) * 255, dtype=np.uint8), deep=True)
    arr.SetName("file colours")
    data = part.mesh.GetPointData()
    data.AddArray(arr)
    data.SetActiveScalars("file colours")
    part.mesh.Modified()
    part.mapper.SetColorModeToDirectScalars()
    part.mapper.SetScalarModeToUsePointData()
    part.mapper.scalar_visibility = True
