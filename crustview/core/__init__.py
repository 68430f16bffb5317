"""The reconstruction core: numpy and scipy only (never Qt, pyvista or VTK).

Entry points
------------
reconstruct(points, d, *, test="cocone", theta=pi/8) -> Reconstruction
reextract(rec, test, theta) -> Reconstruction   (Algorithm 3 again, fast)
"""

from .errors import Cancelled, CrustviewError, InputError, QhullFailure
from .reconstruct import cost_warning, reconstruct, reextract
from .result import CANDIDATE_TESTS, Candidates, Reconstruction, TopologyReport
from .steps import RULES, Extraction, Step

__all__ = [
    "CANDIDATE_TESTS",
    "RULES",
    "Cancelled",
    "Candidates",
    "CrustviewError",
    "Extraction",
    "InputError",
    "QhullFailure",
    "Reconstruction",
    "Step",
    "cost_warning",
    "TopologyReport",
    "reconstruct",
    "reextract",
]
