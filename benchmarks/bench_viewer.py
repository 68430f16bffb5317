"""Time stepping through Algorithm 3 in the viewer at ~100k candidate simplices.

Reconstructs a point file (default: the Stanford bunny, d = 2), re-extracts
with the angle threshold that admits about ``--target`` candidate
simplices, and then measures with the real render adapters:

* ms per step: ``player.set_step(i)``: every visible adapter updated in
  place, then the one render the view does itself, for consecutive steps and
  for random jumps (scrubbing);
* ms per frame: a render with nothing changed;
* ms per projection change: a plane rotation plus one render.

By default the plotter is off-screen (EGL, software GL); ``--qt`` measures
the real main window (``QtInteractor``) instead and needs an X display (run
under ``xvfb-run -a``).

Usage::

    VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow python benchmarks/bench_viewer.py
    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/bench_viewer.py --qt
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

DEFAULT_FILE = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "stanford-bunny.xyz"


def build(path: Path, d: int, target: int):
    from crustview.core import reconstruct, reextract
    from crustview.io import read_points

    points = read_points(path)
    t = time.perf_counter()
    rec = reconstruct(points, d)
    print(f"reconstruct {path.name}: n = {rec.n}, {time.perf_counter() - t:.1f} s, |T_S| = {len(rec.extraction.simplices)}")
    ang = np.sort(rec.candidates.angles[rec.test])
    theta = float(ang[min(target, len(ang) - 1)])
    theta = min(theta, np.pi / 4)
    if abs(len(rec.extraction.simplices) - target) > 0.05 * target:
        t = time.perf_counter()
        rec = reextract(rec, rec.test, theta)
        print(f"re-extract at θ = {np.degrees(theta):.1f}°: |T_S| = {len(rec.extraction.simplices)}, "
              f"{rec.extraction.n_steps} steps, {time.perf_counter() - t:.1f} s")
    return rec


def measure(model, render, label: str, rng) -> None:
    """Print timings; ``render`` renders one frame without changing anything."""
    ext = model.rec.extraction
    n = ext.n_steps

    def timed(fn, reps):
        out = []
        for _ in range(reps):
            t = time.perf_counter()
            fn()
            out.append(1000 * (time.perf_counter() - t))
        return np.array(out)

    model.player.set_step(0)
    frame0 = timed(render, 10)  # all of T_S on screen
    shown0 = int(ext.alive(0).sum())
    model.player.set_step(n // 2)
    frame = timed(render, 20)
    # the view renders once per change by itself (auto_render)
    seq = timed(model.player.next, 40)
    jumps = rng.integers(0, n + 1, 40)
    it = iter(jumps)
    jump = timed(lambda: model.player.set_step(int(next(it))), 40)
    angles = iter(np.linspace(0.05, 1.5, 20))
    proj = timed(lambda: model.projection.set_angle(0, 2, float(next(angles))), 20)
    alive = int(ext.alive(model.player.position).sum())
    print(f"[{label}] |T_S| = {len(ext.simplices):,}, M_S shown ≈ {alive:,} triangles, {n:,} steps")
    for name, arr in ((f"frame at step 0 ({shown0:,} tri)", frame0), ("frame (render only)", frame), ("step (next, update + render)", seq),
                      ("step (random jump + render)", jump), ("projection change + render", proj)):
        print(f"  {name:30s} median {np.median(arr):6.1f} ms   p90 {np.percentile(arr, 90):6.1f} ms")


def offscreen(rec, size) -> None:
    import pyvista as pv

    from crustview.render import SceneView
    from crustview.scene import SceneModel

    pv.global_theme.multi_samples = 0
    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=size)
    SceneView(model, plotter)
    plotter.show(auto_close=False)
    model.set_reconstruction(rec, source="bench")
    rw = plotter.ren_win
    measure(model, rw.Render, f"off-screen {rw.GetClassName()} {size[0]}x{size[1]}", np.random.default_rng(0))
    plotter.close()


def qt(rec, size) -> None:
    import pyvista as pv

    pv.OFF_SCREEN = False
    from PySide6.QtWidgets import QApplication

    from crustview.qt.window import MainWindow

    app = QApplication.instance() or QApplication([])
    win = MainWindow()
    win.resize(*size)
    win.show()
    app.processEvents()
    win.model.set_reconstruction(rec, source="bench")
    app.processEvents()
    w = win.plotter
    view_size = (w.width(), w.height())

    def render():
        win.plotter.ren_win.Render()

    measure(win.model, render, f"QtInteractor in the main window, view {view_size[0]}x{view_size[1]}",
            np.random.default_rng(0))
    win.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", type=Path, default=DEFAULT_FILE)
    ap.add_argument("-d", type=int, default=2)
    ap.add_argument("--target", type=int, default=100_000, help="candidate simplices wanted in T_S")
    ap.add_argument("--size", type=int, nargs=2, default=None,
                    help="window size (default: 1024 768 off-screen; 1600 1000, the app's default, with --qt)")
    ap.add_argument("--qt", action="store_true", help="measure the Qt main window (needs X)")
    args = ap.parse_args()
    rec = build(args.file, args.d, args.target)
    size = tuple(args.size) if args.size else ((1600, 1000) if args.qt else (1024, 768))
    (qt if args.qt else offscreen)(rec, size)


if __name__ == "__main__":
    main()
