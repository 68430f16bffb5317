"""A mesh file's faces as the ground truth of a reconstruction (Qt-free)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..core.analysis.compare import MeshComparison, compare_to_mesh


@dataclass(frozen=True)
class MeshTruth:
    """The faces of the mesh whose vertices were reconstructed.

    It stands where a built-in ``Sample`` stands in :class:`SceneModel.truth`;
    ``manifold`` and ``tangents`` are None because a mesh has no closed-form
    manifold or true normals.

    Attributes
    ----------
    points : ndarray of shape (n_in, k)
        The mesh vertices (the input points).
    faces : ndarray of shape (m, d + 1)
        The faces as d-simplices on input rows (quads split).
    name : str
        File name.
    comparison : MeshComparison or None
        M_S against these faces, once computed for a result.
    """

    points: np.ndarray
    faces: np.ndarray
    name: str
    comparison: MeshComparison | None = None
    manifold = None
    tangents = None

    def compared(self, rec) -> MeshTruth:
        """A copy holding the comparison with ``rec``'s M_S."""
        return replace(self, comparison=compare_to_mesh(rec, self.faces))


def comparison_rows(c: MeshComparison) -> list[tuple[str, str, str]]:
    """Rows (what, M_S, mesh) for the information panel."""

    def shape(t) -> str:
        g = MeshComparison.genus(t)
        if g is not None:
            return f"closed, genus {g}"
        return "closed" if t.closed_manifold else f"not closed ({t.boundary_faces} boundary faces)"

    h = c.hausdorff
    collapsed = f" ({c.collapsed_faces} collapsed)" if c.collapsed_faces else ""
    return [
        ("faces", f"{c.result_faces:,}", f"{c.mesh_faces:,}{collapsed}"),
        ("shape", shape(c.result_topology), shape(c.mesh_topology)),
        (
            "Betti numbers (Z/2)",
            ", ".join(map(str, c.result_topology.betti)),
            ", ".join(map(str, c.mesh_topology.betti)),
        ),
        ("mesh faces recovered", f"{c.recovered:,} ({100 * c.recovered_share:.1f} %)", ""),
        ("extra faces (not in mesh)", f"{c.extra:,}", ""),
        (
            "Hausdorff distance",
            h.words(),
            f"mesh→M_S {h.a_to_b:.3g}, M_S→mesh {h.b_to_a:.3g}" if np.isfinite(h.distance) else "one side is empty",
        ),
    ]
