"""Every hole of the robust result and how far its rim lies from a plane: the sweep behind PLANAR_RIM.

A hole whose rim lies in a plane may be a planar cut (an open scan) or a flat
face sampled only on its outline (a CAD tessellation, a decimated mesh): the
sample does not tell them apart, so :mod:`crustview.core.analysis.planar`
calls it uncertain.  This benchmark lists, for every hole (not removed, not
disputed) of the robust result of

* every mesh of ``../shared/data/scans`` and ``scans2`` and its noisy copies
  (0.1 h and 0.3 h, ``bench_scans.py``'s, optionally decimated first with
  ``--decimate KEEP``), and
* with ``--shapes``, ``bench_shapes.py``'s turned solids (closed: every hole is
  false) at 0.1 h and 0.3 h, seeds 1 and 2,

its rim's RMS distance from its least-squares plane in the run's median
nearest-neighbour distance h (:func:`~crustview.core.analysis.planar.rim_offset`), the
median distance of its samples from the plane of the half of them nearest to
it (:func:`~crustview.core.analysis.planar.trimmed_offset`),
whether it is a true opening (the mesh is open and the rim's samples lie, in
the median, within 2 h of the mesh's own boundary vertices) and whether the
result calls it uncertain.  The closing lines give the ranges on either
side: true openings above PLANAR_RIM and PLANAR_MEDIAN stay sure, false holes
at most either are flagged.

Run: ``python benchmarks/bench_rims.py [--only NAME ...] [--decimate 0.3] [--shapes]`` (about 3 minutes for the
public files; ``--shapes`` adds 2).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scans import FOLDERS, Case, cases  # noqa: E402

from crustview.core import reconstruct  # noqa: E402
from crustview.core.analysis.planar import PLANAR_MEDIAN, PLANAR_RIM, rim_offset, trimmed_offset  # noqa: E402
from crustview.io import read_mesh  # noqa: E402


def boundary_points(stem: str) -> np.ndarray:
    """Coordinates of the vertices of a mesh's boundary edges (edges in one triangle), by the clean mesh's stem."""
    for folder in FOLDERS:
        for f in folder.glob(stem + ".*"):
            if f.suffix in (".off", ".obj", ".ply"):
                mesh = read_mesh(f)
                tris = np.asarray(mesh.simplices(2))
                e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]]), axis=1)
                u, c = np.unique(e, axis=0, return_counts=True)
                return np.asarray(mesh.points, float)[np.unique(u[c == 1])]
    return np.zeros((0, 3))


def shape_cases() -> list[Case]:
    """``bench_shapes.py``'s turned solids (lathe and CAD outline) with noise: closed, so every hole is false."""
    from bench_shapes import noisy_turned

    turned = ("vase", "bottle", "cup", "torus", "cylinder")
    return [Case(name, pts, {"closed": True}, noise) for name, pts, noise in noisy_turned(turned)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="file stems")
    ap.add_argument("--decimate", type=float, metavar="KEEP", help="decimate every mesh to this share of its faces")
    ap.add_argument("--shapes", action="store_true", help="also bench_shapes.py's turned solids (closed)")
    ap.add_argument("--noisy-dir", type=Path, default=Path(__file__).resolve().parent / ".noisy")
    args = ap.parse_args(argv)
    todo = cases(True, set(args.only) if args.only else None, args.noisy_dir, decimate=args.decimate)
    if args.shapes:
        todo += shape_cases()
    print(
        "| file | hole (spacings across) | rim off its plane (h, RMS) | median off its trimmed plane (h) "
        "| true opening | uncertain |"
    )
    print("|---|---|---|---|---|---|")
    real, false = [], []
    rims: dict[str, np.ndarray] = {}
    for case in todo:
        rec = reconstruct(case.points, 2)
        stem = case.name.split("@")[0].split("-n")[0].split("-qem")[0]
        if not case.truth.get("closed", True) and stem not in rims:
            rims[stem] = boundary_points(stem)
        tree = cKDTree(rims[stem]) if not case.truth.get("closed", True) and len(rims[stem]) else None
        for f in rec.features:
            if f.kind != "hole" or f.removed or f.disputed:
                continue
            off = rim_offset(rec.points, f.vertices, rec.spacing)
            med = trimmed_offset(rec.points, f.vertices, rec.spacing)
            true = bool(tree is not None and np.median(tree.query(rec.points[f.vertices])[0]) < 2 * rec.spacing)
            (real if true else false).append((off, med, f.uncertain))
            print(
                f"| {case.name} | {f.size_spacings:.1f} | {off:.2f} | {med:.2f} | {'yes' if true else 'no'} | "
                f"{'yes' if f.uncertain else 'no'} |",
                flush=True,
            )
    print()
    print(f"PLANAR_RIM = {PLANAR_RIM:g}, PLANAR_MEDIAN = {PLANAR_MEDIAN:.3g}")
    for kind, rows in (("true openings", real), ("false holes", false)):
        if not rows:
            print(f"{kind}: none")
            continue
        offs = [o for o, _, _ in rows]
        meds = [m for _, m, _ in rows]
        beyond = [m for o, m, _ in rows if o > PLANAR_RIM]
        print(
            f"{kind}: {len(rows)}, rims {min(offs):.2f}-{max(offs):.2f} h off their planes; "
            f"{sum(o <= PLANAR_RIM for o in offs)} at most PLANAR_RIM; medians off the trimmed planes "
            f"{min(meds):.2f}-{max(meds):.2f}, of those over PLANAR_RIM "
            + (
                f"{min(beyond):.2f}-{max(beyond):.2f}, {sum(m <= PLANAR_MEDIAN for m in beyond)}"
                if beyond
                else "none, 0"
            )
            + f" at most PLANAR_MEDIAN; {sum(u for _, _, u in rows)} uncertain in all"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
