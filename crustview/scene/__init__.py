"""The view model of crustview: no Qt, no VTK.

Layers keep their data in R^k; a :class:`Projection` (a k x 3 orthonormal
basis) is applied when drawing.  :class:`StepPlayer` replays Algorithm 3 and
:class:`Selection` holds what was picked.  All events are psygnal signals.
"""

from .layers import Layer, default_layers
from .model import SceneModel
from .player import StepPlayer
from .projection import Projection, givens
from .selection import Selection
from .tour import GrandTour

__all__ = [
    "GrandTour",
    "Layer",
    "Projection",
    "SceneModel",
    "Selection",
    "StepPlayer",
    "default_layers",
    "givens",
]
