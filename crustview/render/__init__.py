"""Render adapters: pyvista only (no Qt).

:class:`SceneView` wires a :class:`~crustview.scene.SceneModel` to a pyvista
plotter; ``ADAPTERS`` maps each layer name to the adapter that draws it.
"""

from .view import ADAPTERS, SceneView

__all__ = ["ADAPTERS", "SceneView"]
