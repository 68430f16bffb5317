"""The peers ``bench_scans.py --peers`` runs on the same points, when installed: CGAL's and Open3D's reconstructions.

Each returns a :class:`PeerResult` (the topology of what it made, and its time), or None where its package is
not installed.  ``bench_scans.py`` judges them as it judges crustview.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from crustview.core.analysis.topology import analyse


@dataclass
class PeerResult:
    """What a peer made of a sample: its method's name, Z/2 Betti numbers, closedness, samples used, boundary
    faces and time; ``interpolates`` is False for a method whose vertices are not the samples."""

    method: str
    betti: tuple
    closed: bool
    used: int
    boundary: int
    total: float
    interpolates: bool = True


def cgal_advancing_front(points: np.ndarray) -> PeerResult | None:
    """CGAL's Advancing Front Surface Reconstruction (``pip install cgal``) on ``points``."""
    try:
        from CGAL.CGAL_Advancing_front_surface_reconstruction import advancing_front_surface_reconstruction
        from CGAL.CGAL_Kernel import Point_3
        from CGAL.CGAL_Point_set_3 import Point_set_3
    except ImportError:
        return None
    t0 = time.perf_counter()
    cloud = Point_set_3()
    for x, y, z in points.tolist():
        cloud.insert(Point_3(x, y, z))
    flat: list[int] = []
    advancing_front_surface_reconstruction(cloud, flat)
    total = time.perf_counter() - t0
    tri = np.asarray(flat, dtype=np.int64).reshape(-1, 3)
    top = analyse(tri, len(points), 2)
    n = len(points)
    return PeerResult(
        "CGAL advancing front", tuple(top.betti), top.closed_manifold, n - top.unused_samples, top.boundary_faces, total
    )


def open3d_poisson(points: np.ndarray) -> PeerResult | None:
    """Open3D's screened Poisson (``pip install open3d``, depth 8) with Open3D's normals; topology only."""
    try:
        import open3d as o3d
    except ImportError:
        return None
    t0 = time.perf_counter()
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    pc.estimate_normals()
    pc.orient_normals_consistent_tangent_plane(10)
    mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pc, depth=8)
    total = time.perf_counter() - t0
    tri = np.asarray(mesh.triangles, dtype=np.int64)
    top = analyse(tri, len(mesh.vertices), 2)
    return PeerResult(
        "Open3D Poisson (topology)",
        tuple(top.betti),
        top.closed_manifold,
        len(points),
        top.boundary_faces,
        total,
        interpolates=False,
    )
