"""The caps open-cap examines, true openings or not: the sweep behind CAP_RATIO, CAP_SURE and CAP_TYPICAL.

For every mesh of ``../shared/data/scans`` and ``../shared/data/scans2`` and
its noisy copies (0.1 h and 0.3 h, made by ``../shared/tools/noisy.py`` as in
``bench_scans.py``), the robust extraction is run and every cap over
CAP_RATIO that the rule ``open-cap`` examined (removed over CAP_SURE, kept
closed in the band up to it) is listed with its ratio (its largest enclosing radius
over the median one of the faces around it,
:func:`crustview.core.robust.cells.cap_ratios`, and over the median one of all
faces of M_S, :func:`~crustview.core.robust.cells.typical_ratios`), what
open-cap did with it (removed, kept closed, or passed over as no larger than
the surface's faces in general) and whether it is a true
opening: at least half of its samples are vertices of the mesh's own
boundary edges.  The last lines give, per kind, the range of the ratios: the
largest false cap and the smallest true opening are what
:data:`~crustview.core.robust.cells.CAP_SURE` stands between.

Run: ``python benchmarks/bench_caps.py [--only NAME ...] [--clean-only] [--seeds 11,12,13]``; about 4
minutes for all 72 files, as long again with three more draws.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scans import Case, cases  # noqa: E402

from crustview.core import reconstruct  # noqa: E402
from crustview.core.robust.cells import CAP_RATIO, CAP_SURE, CAP_TYPICAL  # noqa: E402
from crustview.io import read_mesh  # noqa: E402


def boundary_vertices(case_name: str) -> np.ndarray:
    """Vertices of the mesh's boundary edges (edges in one face), by the clean mesh's name."""
    from bench_scans import FOLDERS

    stem = case_name.split("-n")[0] if "-n" in case_name else case_name
    for folder in FOLDERS:
        for f in folder.glob(stem + ".*"):
            if f.suffix in (".off", ".obj", ".ply"):
                tris = np.asarray(read_mesh(f).simplices(2))
                e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [0, 2]]]), axis=1)
                u, c = np.unique(e, axis=0, return_counts=True)
                return np.unique(u[c == 1])
    return np.zeros(0, np.int64)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="file stems")
    ap.add_argument("--clean-only", action="store_true")
    ap.add_argument(
        "--seeds",
        default="",
        help="extra noise draws at 0.3 h of every clean mesh, e.g. 11,12,13 (numpy's Gaussian, this seed)",
    )
    ap.add_argument("--noisy-dir", type=Path, default=Path(__file__).resolve().parent / ".noisy")
    ap.add_argument(
        "--lathes",
        action="store_true",
        help="also bench_shapes.py's lathe meshes (closed: every cap there is false) at 0.1 h and 0.3 h, seeds 1-2",
    )
    args = ap.parse_args(argv)
    true_q, false_q = [], []
    print("| file | cap samples | ratio to its ring | to the median face | true opening | open-cap |")
    print("|---|---|---|---|---|---|")
    todo = cases(not args.clean_only, set(args.only) if args.only else None, args.noisy_dir)
    for seed in [int(x) for x in args.seeds.split(",") if x]:
        for case in [c for c in todo if c.noise == 0]:
            h = float(np.median(cKDTree(case.points).query(case.points, k=2)[0][:, 1]))
            pts = case.points + np.random.default_rng(seed).normal(scale=0.3 * h, size=case.points.shape)
            todo.append(replace(case, name=f"{case.name}-n30s{seed}", points=pts, noise=0.3))
    if args.lathes:
        from bench_shapes import noisy_turned

        todo += [Case(name, pts, {}, noise) for name, pts, noise in noisy_turned(("vase", "bottle", "cup", "torus"))]
    for case in todo:
        rec = reconstruct(case.points, 2)
        bnd = boundary_vertices(case.name)
        ext = rec.extraction
        opened = {v.tobytes() for v, _ in getattr(ext, "opened", [])}
        kept = {v.tobytes() for v, _ in getattr(ext, "undecided", [])}
        walls = {v.tobytes() for v, _ in getattr(ext, "walls", [])}
        for verts, ratio, typical in getattr(ext, "examined_caps", []):
            key = verts.tobytes()
            done = (
                "removed"
                if key in opened
                else "kept closed"
                if key in kept
                else "kept closed (a wall)"
                if key in walls
                else "passed over"
            )
            rows = rec.point_input[verts]
            real = bool(np.isin(rows, bnd).mean() >= 0.5) if len(bnd) else False
            (true_q if real else false_q).append((ratio, typical))
            print(
                f"| {case.name} | {len(verts)} | {ratio:.2f} | {typical:.2f} | {'yes' if real else 'no'} | {done} |",
                flush=True,
            )
    print()
    print(f"CAP_RATIO = {CAP_RATIO:g}, CAP_SURE = {CAP_SURE:g}, CAP_TYPICAL = {CAP_TYPICAL:.3g}")
    for kind, qt in (("true openings", true_q), ("false caps", false_q)):
        if qt:
            q, t = [x for x, _ in qt], [y for _, y in qt]
            print(
                f"{kind}: {len(q)}, ratios to the ring {min(q):.2f}-{max(q):.2f} ({sum(x < CAP_SURE for x in q)} under "
                f"CAP_SURE), to the median face {min(t):.2f}-{max(t):.2f} ({sum(y <= CAP_TYPICAL for y in t)} at most "
                "CAP_TYPICAL)"
            )
        else:
            print(f"{kind}: none")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
