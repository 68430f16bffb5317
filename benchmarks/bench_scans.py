"""crustview on real scans, robust (default) and paper mode, optionally against CGAL.

Every mesh in the scans folder (default ``../shared/data/scans`` beside the repository) is read
with crustview's own reader; its vertices are the sample and ``truth.json``
gives the true shape: a closed surface of genus g has the Z/2 Betti numbers
(1, 2g, 1); an open one is judged by its number of boundary edges.

Both modes run in one process on the same Delaunay and candidates: the paper
mode with :func:`~crustview.core.reconstruct`, then the robust extraction
with :func:`~crustview.core.reextract`, so the robust total is the paper total
minus the paper's extraction (and topology) plus the robust re-extraction.
``robust/paper`` is that total over the paper total (the issue's target is at
most 1.5).  ``total/Delaunay`` is the total over scipy's Delaunay time of the
same run.

With ``--cgal`` (needs ``pip install cgal``), CGAL's Advancing Front Surface
Reconstruction runs on the same vertices and is judged the same way with
:func:`crustview.core.analysis.topology.analyse`; its ratio to Delaunay uses
crustview's Delaunay time on the same points.

Run: ``python benchmarks/bench_scans.py [--only NAME] [--cgal] [--dir DIR]``;
prints a markdown table.  All scans take about two minutes on two cores.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crustview.core import reconstruct, reextract
from crustview.core.analysis.topology import analyse
from crustview.core.result import TopologyReport
from crustview.io import read_mesh

#: ``../shared/data/scans`` beside the repository
SCANS = Path(__file__).resolve().parents[2] / "shared" / "data" / "scans"


@dataclass
class Row:
    """One line of the table."""

    name: str
    method: str
    points: int
    topology: TopologyReport
    n: int
    extraction: float | None
    total: float
    delaunay: float
    versus_paper: float | None = None


def verdict(top: TopologyReport, truth: dict) -> str:
    """Whether the topology is the truth's: genus for closed surfaces, boundary edges for open ones."""
    if truth.get("closed"):
        g = int(truth["genus"])
        ok = top.closed_manifold and tuple(top.betti) == (1, 2 * g, 1)
        return f"{'yes' if ok else 'no'} (g={g}, Betti {tuple(int(b) for b in top.betti)})"
    return f"{top.boundary_faces} bnd edges (truth {truth['boundary_edges']})"


def run_crustview(name: str, points: np.ndarray) -> list[Row]:
    """The paper's Algorithm 3 and the robust extraction on one Delaunay/candidate computation."""
    t0 = time.perf_counter()
    paper = reconstruct(points, 2, mode="paper")
    paper_total = time.perf_counter() - t0
    t0 = time.perf_counter()
    robust = reextract(paper, paper.test, paper.theta, mode="robust")
    robust_after = time.perf_counter() - t0  # robust extraction + its topology report
    robust_total = paper_total - paper.timings["extraction"] - paper.timings["topology"] + robust_after
    dl = paper.timings["delaunay"]
    return [
        Row(
            name,
            "crustview robust",
            len(points),
            robust.topology,
            robust.n,
            robust.timings["extraction"],
            robust_total,
            dl,
            robust_total / paper_total,
        ),
        Row(
            name,
            "crustview --paper",
            len(points),
            paper.topology,
            paper.n,
            paper.timings["extraction"],
            paper_total,
            dl,
        ),
    ]


def run_cgal(name: str, points: np.ndarray, delaunay: float) -> Row:
    """CGAL's Advancing Front Surface Reconstruction on the same vertices."""
    from CGAL.CGAL_Advancing_front_surface_reconstruction import advancing_front_surface_reconstruction
    from CGAL.CGAL_Kernel import Point_3
    from CGAL.CGAL_Point_set_3 import Point_set_3

    t0 = time.perf_counter()
    cloud = Point_set_3()
    for x, y, z in points.tolist():
        cloud.insert(Point_3(x, y, z))
    flat: list[int] = []
    advancing_front_surface_reconstruction(cloud, flat)
    total = time.perf_counter() - t0
    triangles = np.asarray(flat, dtype=np.int64).reshape(-1, 3)
    return Row(
        name,
        "CGAL advancing front",
        len(points),
        analyse(triangles, len(points), 2),
        len(points),
        None,
        total,
        delaunay,
    )


def table_header() -> str:
    cols = [
        "file",
        "method",
        "points",
        "closed",
        "genus right",
        "samples used / n",
        "extraction s",
        "total s",
        "total/Delaunay",
        "robust/paper total",
    ]
    return "| " + " | ".join(cols) + " |\n|" + "---|" * len(cols)


def table_row(row: Row, truth: dict) -> str:
    top = row.topology
    used = row.n - top.unused_samples if top.n_simplices else 0
    cells = [
        row.name,
        row.method,
        f"{row.points:,}",
        "yes" if top.closed_manifold else "no",
        verdict(top, truth),
        f"{used:,} / {row.n:,}",
        "–" if row.extraction is None else f"{row.extraction:.2f}",
        f"{row.total:.2f}",
        f"{row.total / row.delaunay:.2f}",
        "–" if row.versus_paper is None else f"{row.versus_paper:.2f}",
    ]
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dir", type=Path, default=SCANS, help=f"folder of scans with truth.json (default {SCANS})")
    parser.add_argument(
        "--only",
        action="append",
        metavar="NAME",
        help="run only this file (repeatable; the name with or without suffix)",
    )
    parser.add_argument("--cgal", action="store_true", help="also run CGAL's Advancing Front reconstruction")
    args = parser.parse_args(argv)
    truth = json.loads((args.dir / "truth.json").read_text())
    names = sorted(truth, key=lambda f: truth[f]["points"])
    if args.only:
        wanted = set(args.only)
        names = [f for f in names if f in wanted or Path(f).stem in wanted]
        if not names:
            parser.error(f"no scan named {', '.join(sorted(wanted))} in {args.dir}")
    if args.cgal:
        try:
            import CGAL.CGAL_Advancing_front_surface_reconstruction  # noqa: F401
        except ImportError:
            print("CGAL is not importable (pip install cgal); running crustview only", file=sys.stderr)
            args.cgal = False
    print(table_header(), flush=True)
    worst = 0.0
    for name in names:
        mesh = read_mesh(args.dir / name)
        points = np.asarray(mesh.points, dtype=float)
        rows = run_crustview(name, points)
        worst = max(worst, rows[0].versus_paper or 0.0)
        if args.cgal:
            rows.append(run_cgal(name, points, rows[0].delaunay))
        for row in rows:
            print(table_row(row, truth[name]), flush=True)
    print(f"\nlargest robust/paper total time: {worst:.2f} (target <= 1.5)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
