"""Real meshes made into the issue's other kinds of input: two objects in one file, and open scans.

``bench_scans.py`` judges each mesh as it is.  Issue 18 also asks that a file
holding several closed objects give one closed component each, and that an
open scan keep its real holes open; the public files with several objects
(foot bones, gears, octopus) only have parts that touch, and its open scans
are few.  This benchmark makes such inputs from any folder of closed meshes
(``--folder``, e.g. the meshes kept aside in ``benchmarks/HELDOUT.md``), so
that both behaviours are judged on objects nobody tuned on:

* ``--pairs GAP[,GAP...]``: each mesh beside the next one in the folder (by
  name, cyclically).  The second is scaled so that its median nearest-neighbour
  distance h is the first one's (one sampling density in the file), then
  placed beside it in x so that its sample of least x lies ``GAP`` h beyond
  the first one's sample of largest x: those two are the closest pair (on a
  CAD part many samples share the extreme x, and a flat face faces the other
  object).  The truth: the closed components and the genera added.
* ``--opened SHARE``: each single-object mesh with every face removed that has a
  vertex in the ball around a random vertex (draw ``--seed``) holding ``SHARE``
  of the vertices, as a scanner leaves a hole where it did not see; the
  vertices of the faces that remain are the sample.  Its rim is the sphere's
  trace on the surface, not a plane.  The truth: the kept faces' Betti
  numbers, open.  A cut that leaves anything but one hole (a rim through a
  vertex twice, two rims where the ball severed a thin part, or the mesh in
  pieces) moves the ball to another vertex of the same draw.

Each case also runs with ``noisy.py``'s Gaussian noise at 0.1 h and 0.3 h
(draw ``--seed``), unless ``--clean-only``.  The table and its closing lines are
``bench_scans.py``'s: right or not, the uncertain features, and the count of
wrong results without a flag (the issue's target: none).

Run: ``python benchmarks/bench_reshaped.py --folder DIR [--pairs 1.5,3,6] [--opened 0.05] [--seed 43]``.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
import zlib
from pathlib import Path

import numpy as np
from _folders import folder_truth
from _kinds import rims
from bench_scans import HEADER, Case, _holes_under_a_spacing, _noisy, line, run_crustview, summarise
from scipy.spatial import cKDTree

from crustview.core.analysis.topology import analyse
from crustview.io import read_mesh


def load(folder: Path) -> list[tuple[str, np.ndarray, np.ndarray, dict]]:
    """The closed meshes of ``folder``: (stem, vertices, triangles, truth), by name."""
    truth = folder_truth(folder)
    out = []
    for fname in sorted(truth):
        t = truth[fname]
        if not t["closed"]:
            continue
        mesh = read_mesh(folder / fname)
        if mesh is None or np.shape(mesh.points)[1] != 3:
            continue
        out.append((Path(fname).stem, np.asarray(mesh.points, float), np.asarray(mesh.simplices(2)), t))
    return out


def spacing(points: np.ndarray) -> float:
    """The median nearest-neighbour distance h."""
    return float(np.median(cKDTree(points).query(points, k=2)[0][:, 1]))


def paired(a: np.ndarray, b: np.ndarray, gap: float) -> np.ndarray:
    """``b`` scaled to ``a``'s spacing and placed beside ``a`` in x, its closest sample ``gap`` h from ``a``'s.

    ``b``'s sample of least x goes to ``a``'s sample of largest x, moved on by ``gap`` h along x: every other
    pair of samples is then at least as far apart in x alone, so the closest pair is that one (tip facing
    tip, as two objects on a table that nearly touch).  Returns the moved ``b``.
    """
    h, hb = spacing(a), spacing(b)
    if not (h > 0 and hb > 0):
        raise ValueError("a mesh whose median nearest-neighbour distance is 0 (repeated vertices) has no spacing")
    b = b * (h / hb)
    tip_a = a[np.argmax(a[:, 0])]
    tip_b = b[np.argmin(b[:, 0])]
    return b - tip_b + tip_a + np.array([gap * h, 0.0, 0.0])


def opened(points: np.ndarray, tris: np.ndarray, share: float, seed: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The mesh with one hole: the faces touching the ball around a random vertex that holds ``share`` of the vertices.

    Tries up to ten vertices of draw ``seed``; None when no cut left one hole (:func:`one_hole`).  Returns the
    kept vertices and the kept faces renumbered to them.
    """
    rng = np.random.default_rng(seed)
    for centre in rng.choice(len(points), size=min(10, len(points)), replace=False):
        dist = np.linalg.norm(points - points[centre], axis=1)
        inside = dist <= np.quantile(dist, share)
        kept = tris[~inside[tris].any(axis=1)]
        used = np.unique(kept)
        renumber = np.full(len(points), -1, np.int64)
        renumber[used] = np.arange(len(used))
        faces = renumber[kept]
        if one_hole(faces, len(used)):
            return points[used], faces
    return None


def one_hole(faces: np.ndarray, n: int) -> bool:
    """Whether the triangles are one connected surface with exactly one boundary curve, pinched nowhere.

    The rim is the edges of one triangle (:func:`_kinds.rims`); no rim vertex may have more than two rim
    edges (a vertex with four is a pinch, which :func:`~crustview.core.analysis.topology.analyse` does not
    count on a surface with boundary), and the rim edges must form one cycle.
    """
    top = analyse(faces, n, 2)
    if top.nonmanifold_faces or top.closed_manifold or top.betti[0] != 1:
        return False
    return rims(faces, n) == (1, False)


def build(
    meshes: list, pairs: list[float], share: float | None, seed: int
) -> list[tuple[str, np.ndarray, np.ndarray, dict]]:
    """The reshaped meshes: (name, vertices, triangles, truth); the holes' draws are ``seed`` and the mesh's name."""
    out = []
    for i, (stem, pts, tris, t) in enumerate(meshes):
        if len(meshes) > 1:
            stem2, pts2, tris2, t2 = meshes[(i + 1) % len(meshes)]
            for gap in pairs:
                moved = paired(pts, pts2, gap)
                both = np.vstack([pts, moved])
                faces = np.vstack([tris, tris2 + len(pts)])
                truth = {
                    "closed": True,
                    "components": int(t["components"]) + int(t2["components"]),
                    "genus": int(t["genus"]) + int(t2["genus"]),
                    "points": len(both),
                    "boundary_edges": 0,
                }
                out.append((f"{stem}+{stem2}-gap{gap:g}", both, faces, truth))
        if share is not None:
            if int(t["components"]) != 1:
                print(f"{stem}: {t['components']} objects; an open scan is made of one: skipped", file=sys.stderr)
                continue
            cut = opened(pts, tris, share, seed + _seed(stem))
            if cut is None:
                print(f"{stem}: no cut of the ten tried left one hole: skipped", file=sys.stderr)
                continue
            kept, faces = cut
            top = analyse(faces, len(kept), 2)
            truth = {
                "closed": False,
                "components": int(top.betti[0]),
                "genus": None,
                "points": len(kept),
                "boundary_edges": int(top.boundary_faces),
            }
            out.append((f"{stem}-open{round(100 * share):02d}", kept, faces, truth))
    return out


def _seed(stem: str) -> int:
    """A draw of its own for each mesh, the same in every run (Python's ``hash`` of a str is salted)."""
    return zlib.crc32(stem.encode()) % (2**31)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--folder", action="append", type=Path, required=True, metavar="DIR", help="closed meshes")
    ap.add_argument("--pairs", default="", help="comma-separated gaps in h (empty or 'none': no pairs)")
    ap.add_argument("--opened", type=float, metavar="SHARE", help="cut a hole holding this share of the vertices")
    ap.add_argument("--seed", type=int, default=43, help="noisy.py's draw, and the hole's")
    ap.add_argument("--clean-only", action="store_true", help="no noisy copies")
    ap.add_argument("--noisy-dir", type=Path, help="noisy copies' cache (default under .noisy-reshaped-sSEED)")
    a = ap.parse_args(argv)
    try:
        pairs = [float(g) for g in a.pairs.split(",") if g and a.pairs != "none"]
    except ValueError:
        ap.error(f"--pairs takes comma-separated numbers or 'none', not {a.pairs!r}")
    if any(g <= 0 for g in pairs):
        ap.error("--pairs takes gaps above 0")
    if not pairs and a.opened is None:
        ap.error("nothing to make: give --pairs and/or --opened")
    if a.opened is not None and not 0 < a.opened < 1:
        ap.error("--opened takes a share in (0, 1)")
    # one cache per folder set and share (names like open05 round the share), as bench_scans.py keys its folders
    key = hashlib.sha1("\n".join([*(str(f.resolve()) for f in a.folder), repr(a.opened)]).encode()).hexdigest()[:10]
    noisy_dir = a.noisy_dir or Path(__file__).resolve().parent / f".noisy-reshaped-s{a.seed}" / key
    meshes = [m for folder in a.folder for m in load(folder)]
    print(HEADER, flush=True)
    rows = []
    for name, pts, tris, truth in build(meshes, pairs, a.opened, a.seed):
        betti = tuple(int(b) for b in analyse(tris, len(pts), 2).betti)
        small = _holes_under_a_spacing(pts, tris)
        loops = rims(tris, len(pts))
        todo = [Case(name, pts, truth, 0.0, betti, small, tris, loops)]
        if not a.clean_only:
            for level in (0.1, 0.3):
                noisy = _noisy(pts, name, level, noisy_dir, a.seed)
                if len(noisy) != len(pts) or not np.array_equal(np.load(noisy_dir / f"{name}.npy"), pts):
                    print(f"{noisy_dir}: its copy of {name} is of other points; remove it", file=sys.stderr)
                    return 1
                todo.append(Case(f"{name}-n{round(100 * level):02d}", noisy, truth, level, betti, small, tris, loops))
        for case in todo:
            for r in run_crustview(case, ["robust"]):
                print(line(r), flush=True)
                rows.append(r)
    summarise(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
