"""How the pipeline scales: stage times, peak memory and growth between sizes.

Cases: torus samples of 30k, 100k, 300k and 1M points in R^3 and the flat
Klein bottle with 2.5k, 5k and 10k points in R^4.  Each case runs in a fresh
subprocess, so its peak RSS (``ru_maxrss``) is its own.  For every case the
table gives each stage's time, the whole run over the Delaunay stage, peak
RSS (total and per point) and the growth factor of the total time from the
previous size of the same manifold.  On the R^4 cases it also times GUDHI's
tangential complex on the same points in the same subprocess, both as
computed and with its repair step (``fix_inconsistencies_using_perturbation``,
which it needs for the right Betti numbers on this input).

The floor: on the R^3 cases the same subprocess also builds the ``cgal``
wheel's ``Delaunay_triangulation_3`` on the same points (the insert alone,
points already made), and ``whole`` is crustview's whole run as the command
line does it: reading the ``.npy`` sample, ``reconstruct`` and writing the
result ``.npz``.  The table gives ``whole/CGAL``, crustview over that floor,
measured in the same run.  The floor runs after crustview, so that the peak
RSS stays crustview's own (the wheel's triangulation is freed before, but
the process's high-water mark would keep it; the peak is read before it).  ``CPU/wall`` is the
process's CPU time over wall time during each stage (2.0 = both cores busy
on a 2-core machine).

Run: ``python benchmarks/bench_scale.py [--huge-pages] [case ...]``, e.g.
``python benchmarks/bench_scale.py torus-30k torus-300k klein-10k``.  ``--huge-pages`` runs crustview with
numpy's transparent-huge-page advice left on (``CRUSTVIEW_HUGE_PAGES=1``; see
:func:`crustview.core.util.memory.numpy_small_pages`), to measure what turning it off gains.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _cases import case_names

#: (manifold, n, sampling method).  The torus samples are i.i.d. by area
#: (``method="random"``): the default even sampler's farthest-point pass is
#: quadratic in n and would take longer than the reconstruction itself.
CASES = {
    "torus-30k": ("torus", 30_000, "random"),
    "torus-100k": ("torus", 100_000, "random"),
    "torus-300k": ("torus", 300_000, "random"),
    "torus-1M": ("torus", 1_000_000, "random"),
    "klein-2.5k": ("flat-klein", 2_500, "even"),
    "klein-5k": ("flat-klein", 5_000, "even"),
    "klein-10k": ("flat-klein", 10_000, "even"),
}


def _gudhi_seconds(points, d: int, fix: bool) -> float:  # noqa: ANN001
    """Seconds of GUDHI's tangential complex (``bench_gudhi.gudhi_betti``, beside this file)."""
    from bench_gudhi import gudhi_betti

    return gudhi_betti(points, d, fix)[2]


def _cgal_wheel_seconds(points) -> float:  # noqa: ANN001
    """Seconds of the ``cgal`` wheel's ``Delaunay_triangulation_3`` inserting ``points`` (the floor)."""
    from CGAL.CGAL_Kernel import Point_3
    from CGAL.CGAL_Triangulation_3 import Delaunay_triangulation_3

    cgal_points = [Point_3(x, y, z) for x, y, z in points.tolist()]
    tri = Delaunay_triangulation_3()
    t0 = time.perf_counter()
    tri.insert(cgal_points)
    seconds = time.perf_counter() - t0
    assert tri.number_of_vertices() == len(points)
    return seconds


def _cpu_over_wall():  # noqa: ANN202
    """A progress callback recording the process's CPU time over wall time per stage, and its record."""
    marks: list[tuple[str, float, float]] = []

    def progress(stage: str, fraction: float) -> None:
        if not marks or marks[-1][0] != stage:
            marks.append((stage, time.perf_counter(), time.process_time()))

    def ratios() -> dict[str, float]:
        ends = [*marks[1:], ("end", time.perf_counter(), time.process_time())]
        out: dict[str, float] = {}
        for (stage, w0, c0), (_, w1, c1) in zip(marks, ends):
            if w1 > w0 and stage not in out:
                out[stage] = (c1 - c0) / (w1 - w0)
        return out

    return progress, ratios


def run_one(case: str) -> dict:
    """Run one case in this process and return its measurements."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import read_points, write_result

    name, n, method = CASES[case]
    m = get_manifold(name)
    pts = m.sample(n, seed=0, method=method).points
    progress, ratios = _cpu_over_wall()
    with tempfile.TemporaryDirectory(prefix="bench-scale-") as tmp:
        np.save(Path(tmp) / "in.npy", pts)
        t0 = time.perf_counter()
        points = read_points(Path(tmp) / "in.npy")
        read = time.perf_counter() - t0
        t0 = time.perf_counter()
        rec = reconstruct(points, m.d, progress=progress)
        total = time.perf_counter() - t0
        t0 = time.perf_counter()
        write_result(Path(tmp) / "out.npz", rec)
        write = time.perf_counter() - t0
    top = rec.topology
    out = {
        "case": case,
        "n": n,
        "k": m.k,
        "timings": dict(rec.timings),
        "cpu_over_wall": ratios(),
        "total": total,
        "read": read,
        "write": write,
        "whole": read + total + write,
        "delaunay_simplices": int(len(rec.delaunay_simplices)),
        "correct": bool(top.closed_manifold and top.betti == m.betti and top.unused_samples == 0),
        "betti": list(top.betti),
    }
    del rec
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # before the floor and GUDHI
    if m.k == 3:
        out["cgal_wheel"] = _cgal_wheel_seconds(pts)
    if m.k >= 4:
        out["gudhi"] = _gudhi_seconds(pts, m.d, fix=False)
        out["gudhi_fix"] = _gudhi_seconds(pts, m.d, fix=True)
    return out


def main(cases: list[str], huge_pages: bool = False) -> None:
    previous: dict[str, dict] = {}
    # set either way: a shell that exports CRUSTVIEW_HUGE_PAGES=1 would otherwise measure huge pages by default
    env = {**os.environ, "CRUSTVIEW_HUGE_PAGES": "1" if huge_pages else "0"}
    env.pop("NUMPY_MADVISE_HUGEPAGE", None)  # numpy's own variable would also leave its advice as it is
    for case in cases:
        proc = subprocess.run(
            [sys.executable, str(Path(__file__).resolve()), "--one", case],
            capture_output=True,
            text=True,
            check=False,
            env=env,
        )
        if proc.returncode != 0:
            print(f"{case}: failed\n{proc.stderr.strip()[-2000:]}", flush=True)
            continue
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        t = r["timings"]
        stages = "  ".join(f"{k} {v:6.2f}" for k, v in t.items())
        name = CASES[case][0]
        growth = ""
        if name in previous:
            p = previous[name]
            growth = f"  growth x{r['total'] / p['total']:.2f} for x{r['n'] / p['n']:.2f} points"
        previous[name] = r
        after = sum(v for k, v in t.items() if k not in ("prepare", "delaunay"))
        print(
            f"{case:11s} n={r['n']:8d} | {stages} | total {r['total']:7.2f} s | "
            f"read {r['read']:5.2f} write {r['write']:5.2f} whole {r['whole']:7.2f} s",
            flush=True,
        )
        busy = "  ".join(f"{k} {v:4.2f}" for k, v in r["cpu_over_wall"].items())
        print(f"{'':11s} CPU/wall: {busy}", flush=True)
        if "cgal_wheel" in r:
            print(
                f"{'':11s} floor: cgal wheel Delaunay_triangulation_3 {r['cgal_wheel']:6.2f} s; "
                f"whole/CGAL {r['whole'] / r['cgal_wheel']:5.2f}x  total/CGAL {r['total'] / r['cgal_wheel']:5.2f}x",
                flush=True,
            )
        print(
            f"{'':11s} total/Delaunay {r['total'] / t['delaunay']:5.2f}  "
            f"normals+candidates/Delaunay {(t['normals'] + t['candidates']) / t['delaunay']:5.2f}  "
            f"after/Delaunay {after / t['delaunay']:5.2f}  "
            f"peak RSS {r['peak_rss_mb']:8.0f} MB ({r['peak_rss_mb'] * 1024 / r['n']:5.2f} KB/point)  "
            f"{r['delaunay_simplices']} simplices  correct {r['correct']} {tuple(r['betti'])}{growth}",
            flush=True,
        )
        if "gudhi" in r:
            print(
                f"{'':11s} GUDHI tangential {r['gudhi']:6.2f} s, with repair {r['gudhi_fix']:6.2f} s; "
                f"crustview/GUDHI {r['total'] / r['gudhi']:5.1f}x, /GUDHI+repair {r['total'] / r['gudhi_fix']:5.1f}x",
                flush=True,
            )


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--one":
        print(json.dumps(run_one(sys.argv[2])))
    else:
        args = [a for a in sys.argv[1:] if a != "--huge-pages"]
        main(case_names(__doc__, CASES, args), huge_pages=len(args) < len(sys.argv) - 1)
