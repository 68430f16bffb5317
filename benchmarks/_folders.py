"""The truth of a folder of meshes for ``bench_scans.py --folder``: its ``truth.json``, or the meshes' own faces."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from crustview.core.analysis.topology import analyse
from crustview.core.errors import CrustviewError
from crustview.io import read_mesh


def folder_truth(folder: Path) -> dict:
    """``folder``'s ``truth.json``, or, without one, the truth of each mesh in it from its own faces.

    The faces' own topology: ``closed`` when every edge has two triangles and every vertex a disc of them
    (crustview's ``analyse``), ``components`` and ``genus`` from its Z/2 Betti numbers (c, 2g, c), and
    ``boundary_edges``; the table's columns need no more.  A mesh whose faces are not a manifold is
    reported and left out: it has no genus to judge by.
    """
    if (folder / "truth.json").is_file():
        return json.loads((folder / "truth.json").read_text())
    out = {}
    stems: set[str] = set()
    for path in sorted(folder.iterdir()):
        if path.suffix.lower() not in (".off", ".obj", ".ply", ".stl"):
            continue
        if path.stem in stems:  # the noisy copies are named by stem
            print(f"{path.name}: another file has its stem: skipped", file=sys.stderr)
            continue
        try:
            mesh = read_mesh(path)
        except CrustviewError as err:
            print(f"{path.name}: {err}: skipped", file=sys.stderr)
            continue
        if mesh is None:
            print(f"{path.name}: no faces of a surface in R^3 (none, or a flat mesh's): skipped", file=sys.stderr)
            continue
        stems.add(path.stem)
        top = analyse(np.asarray(mesh.simplices(2)), len(mesh.points), 2)
        if top.nonmanifold_faces or top.singular_vertices:
            print(f"{path.name}: its faces are not a manifold: skipped", file=sys.stderr)
            continue
        b = top.betti
        out[path.name] = {
            "points": len(mesh.points),
            "closed": bool(top.closed_manifold),
            "components": int(b[0]),
            "genus": int(b[1]) // 2 if top.closed_manifold else None,
            "boundary_edges": int(top.boundary_faces),
        }
    return out
