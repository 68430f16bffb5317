"""Scanner's holes cut by points: is a closed answer over one ever given without a flag?

For every closed single-object mesh of ``../shared/data/scans`` and ``../shared/data/scans2`` (or the files named
with ``--only``), the samples nearest one random sample are taken away (``--shares``, 2 % and 5 % by default;
``--centres`` random samples per mesh, draw ``--seed``), as a scanner leaves a patch unseen. The cut sample is
open by construction, so every result is one of: ``open`` (it shows an opening), ``closed-flagged`` (closed, with
an uncertain feature: the answer says it may be wrong) or ``QUIET`` (closed, nothing uncertain: an open object
called closed for sure, the issue's worst case).

Unlike ``bench_reshaped.py --opened``, which takes away every face touching the ball and keeps the vertices of the
faces left (one clean rim), this cut takes samples only, as a point cloud with a gap is: the hole's rim is
wherever the remaining samples happen to lie.

Run: ``python benchmarks/bench_cutholes.py [--seed 47] [--centres 3] [--shares 0.02,0.05] [--only NAME ...]
[--json FILE]``; about two minutes on this 2-core machine.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scans import FOLDERS  # noqa: E402

from crustview.core import reconstruct  # noqa: E402
from crustview.io import read_mesh  # noqa: E402


def closed_single(folder: Path) -> list[Path]:
    """The meshes of ``folder`` its ``truth.json`` calls closed and of one component."""
    truth = json.loads((folder / "truth.json").read_text())
    return [folder / name for name, t in sorted(truth.items()) if t.get("closed") and t.get("components") == 1]


def cut(points: np.ndarray, centre: int, share: float) -> np.ndarray:
    """The samples farther from sample ``centre`` than the ``share`` nearest it."""
    far = np.linalg.norm(points - points[centre], axis=1)
    return points[far > np.quantile(far, share)]


def verdict(rec) -> str:  # noqa: ANN001
    """``open``, ``closed-flagged`` or ``QUIET`` (see the module docstring)."""
    if not rec.topology.closed_manifold:
        return "open"
    return "closed-flagged" if rec.uncertain_features else "QUIET"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=47, help="draw of the centres")
    ap.add_argument("--centres", type=int, default=3, help="random samples cut around, per mesh")
    ap.add_argument("--shares", default="0.02,0.05", help="comma-separated shares of the samples cut away")
    ap.add_argument("--only", nargs="*", help="file stems")
    ap.add_argument("--json", type=Path, help="also write the rows as JSON")
    a = ap.parse_args(argv)
    shares = [float(s) for s in a.shares.split(",")]
    if not all(0 < s < 1 for s in shares) or a.centres < 1:
        ap.error("--shares takes shares in (0, 1) and --centres at least 1")
    rows = []
    for path in [p for folder in FOLDERS for p in closed_single(folder)]:
        if a.only and path.stem not in a.only:
            continue
        pts = np.asarray(read_mesh(path).points, float)
        rng = np.random.default_rng(a.seed)
        for centre in rng.choice(len(pts), min(a.centres, len(pts)), replace=False):
            for share in shares:
                rec = reconstruct(cut(pts, int(centre), share), 2)
                kinds = Counter(f.kind for f in rec.uncertain_features)
                row = {"file": path.stem, "centre": int(centre), "share": share, "verdict": verdict(rec)}
                rows.append(row | {"uncertain": kinds})
                print(
                    f"| {path.stem} | {int(centre)} | {share:g} | {rows[-1]['verdict']} | "
                    f"{rec.topology.betti} | {dict(kinds) or '-'} |",
                    flush=True,
                )
    tally = Counter(r["verdict"] for r in rows)
    quiet = [f"{r['file']} ({r['centre']}, {r['share']:g})" for r in rows if r["verdict"] == "QUIET"]
    print(f"\n{len(rows)} cut samples: {dict(tally)}; closed without a flag: {', '.join(quiet) or 'none'}")
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
