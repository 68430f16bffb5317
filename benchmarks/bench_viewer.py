"""Time stepping through Algorithm 3 in the viewer at ~100k candidate simplices.

Reconstructs a point file (default: the Stanford bunny, d = 2), re-extracts
with the angle threshold that admits about ``--target`` candidate
simplices, and then measures with the real render adapters:

* ms per step: ``player.set_step(i)``: every visible adapter updated in
  place, then the one render the view does itself, for consecutive steps and
  for random jumps (scrubbing);
* ms per frame: a render with nothing changed;
* ms per projection change: a plane rotation plus one render;
* at scale (``--torus 1000000``): the raw-point preview, the first frame of
  a result, steps and 2-degree camera rotations both whole and with the
  level of detail on (big layers thinned while moving,
  :mod:`crustview.render.lod`), and the layers drawn as a subset.

Every row is also given as a multiple of the floor: a whole frame with
nothing changed, measured in the same process.

By default the plotter is off-screen (EGL, software GL); ``--qt`` measures
the real main window (``QtInteractor``) instead and needs an X display (run
under ``xvfb-run -a``).

Usage::

    VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow python benchmarks/bench_viewer.py
    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/bench_viewer.py --qt
    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/bench_viewer.py --qt --torus 1000000
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

DEFAULT_FILE = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "stanford-bunny.xyz"


def build(path: Path, d: int, target: int | None, torus: int | None = None):
    from crustview.core import reconstruct, reextract
    from crustview.io import read_points

    if torus:
        from crustview.core.samples.manifolds import get_manifold

        points, name = get_manifold("torus").sample(torus, seed=0, method="random").points, f"torus {torus:,}"
    else:
        points, name = read_points(path), path.name
    t = time.perf_counter()
    rec = reconstruct(points, d)
    print(f"reconstruct {name}: n = {rec.n}, {time.perf_counter() - t:.1f} s, |T_S| = {len(rec.extraction.simplices)}")
    if target is None:
        return rec
    ang = np.sort(rec.candidates.angles[rec.test])
    theta = float(ang[min(target, len(ang) - 1)])
    theta = min(theta, np.pi / 4)
    if abs(len(rec.extraction.simplices) - target) > 0.05 * target:
        t = time.perf_counter()
        rec = reextract(rec, rec.test, theta)
        print(
            f"re-extract at θ = {np.degrees(theta):.1f}°: |T_S| = {len(rec.extraction.simplices)}, "
            f"{rec.extraction.n_steps} steps, {time.perf_counter() - t:.1f} s"
        )
    return rec


def timed(fn, reps: int) -> np.ndarray:
    """Milliseconds of ``reps`` calls of ``fn``."""
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        out.append(1000 * (time.perf_counter() - t))
    return np.array(out)


def report(name: str, arr: np.ndarray, floor: float) -> None:
    print(
        f"  {name:44s} median {np.median(arr):7.1f} ms   p90 {np.percentile(arr, 90):7.1f} ms"
        f"   {np.median(arr) / floor:5.2f}x floor"
    )


def measure(model, view, render, label: str, rng, reps: int = 20) -> None:
    """Print timings; ``render`` renders one frame without changing anything.

    The floor is one whole frame with nothing changed, in the same process.
    "thinned" rows run with the level of detail on (what the window shows
    while the mouse drags the view or the user steps; the whole frame comes
    once they stop).
    """
    ext = model.rec.extraction
    n = ext.n_steps
    view.auto_render = False  # every row below renders explicitly, once per change

    def step_and_render():
        model.player.next()
        render()

    model.player.set_step(0)
    frame0 = timed(render, max(3, reps // 4))  # all of T_S on screen
    shown0 = int(ext.alive(0).sum())
    model.player.set_step(n // 2)
    frame = timed(render, max(3, reps // 4))
    floor = float(np.median(frame))
    whole = timed(step_and_render, max(3, reps // 4))
    update = timed(model.player.next, reps)  # the adapters' updates alone
    camera = view.plotter.camera
    rotate = timed(lambda: (camera.Azimuth(2.0), render()), max(3, reps // 4))
    thinned = view.begin_lod()
    seq = timed(step_and_render, reps)
    jumps = iter(rng.integers(0, n + 1, reps))
    jump = timed(lambda: (model.player.set_step(int(next(jumps))), render()), reps)
    rotate_lod = timed(lambda: (camera.Azimuth(2.0), render()), reps)
    drawn = view.lod.drawn()
    view.end_lod()
    angles = iter(np.linspace(0.05, 1.5, max(3, reps // 4)))
    proj = timed(lambda: (model.projection.set_angle(0, 2, float(next(angles))), render()), max(3, reps // 4))
    view.auto_render = True
    alive = int(ext.alive(model.player.position).sum())
    print(
        f"[{label}] n = {model.rec.n:,}, |T_S| = {len(ext.simplices):,}, M_S shown ≈ {alive:,} triangles, "
        f"{n:,} steps; floor = whole frame {floor:.0f} ms"
    )
    if thinned:
        print("  thinned while moving: " + ", ".join(f"{k} {a:,} of {b:,}" for k, (a, b) in drawn.items()))
    for name, arr in (
        (f"whole frame at step 0 ({shown0:,} tri)", frame0),
        ("whole frame (render only)", frame),
        ("step, whole: update + render", whole),
        ("step: update only", update),
        ("step, thinned: update + render", seq),
        ("random jump, thinned: update + render", jump),
        ("rotate 2 deg, whole", rotate),
        ("rotate 2 deg, thinned", rotate_lod),
        ("projection change + whole render", proj),
    ):
        report(name, arr, floor)
    for layer in model.layers.values():
        if layer.note:
            print(f"  layer note: {layer.note}")


def offscreen(rec, size) -> None:
    import pyvista as pv

    from crustview.render import SceneView
    from crustview.scene import SceneModel

    pv.global_theme.multi_samples = 0
    model = SceneModel()
    plotter = pv.Plotter(off_screen=True, window_size=size)
    view = SceneView(model, plotter)
    plotter.show(auto_close=False)
    rw = plotter.ren_win
    t = time.perf_counter()
    view.show_preview(rec.input_points)
    print(f"raw points drawn (preview, {len(rec.input_points):,} points): {1000 * (time.perf_counter() - t):.0f} ms")
    t = time.perf_counter()
    model.set_reconstruction(rec, source="bench")
    print(f"result shown (every layer built, first frame): {1000 * (time.perf_counter() - t):.0f} ms")
    model.layers["normals"].visible = True  # hidden by default above 3,000 samples: show the subset
    measure(model, view, rw.Render, f"off-screen {rw.GetClassName()} {size[0]}x{size[1]}", np.random.default_rng(0))
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
    t = time.perf_counter()
    win.view.show_preview(rec.input_points)
    app.processEvents()
    print(f"raw points drawn (preview, {len(rec.input_points):,} points): {1000 * (time.perf_counter() - t):.0f} ms")
    from crustview.core.analysis.quality import sampling_quality

    t = time.perf_counter()
    quality = sampling_quality(rec)  # the window's worker thread computes it with the run
    print(f"sampling quality (worker thread, with the run): {1000 * (time.perf_counter() - t):.0f} ms")
    t = time.perf_counter()
    win.model.set_reconstruction(rec, source="bench", quality=quality)
    app.processEvents()
    print(f"result shown (every layer built, first frame): {1000 * (time.perf_counter() - t):.0f} ms")
    win.model.layers["normals"].visible = True  # hidden by default above 3,000 samples: show the subset
    app.processEvents()
    # the window thins big layers on every step by itself; the rows below choose explicitly
    win.model.player.step_changed.disconnect(win.step_detail._stepped)
    w = win.plotter
    view_size = (w.width(), w.height())

    def render():
        win.plotter.ren_win.Render()

    measure(
        win.model,
        win.view,
        render,
        f"QtInteractor in the main window, view {view_size[0]}x{view_size[1]}",
        np.random.default_rng(0),
    )
    win.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", type=Path, default=DEFAULT_FILE)
    ap.add_argument("-d", type=int, default=2)
    ap.add_argument("--target", type=int, default=100_000, help="candidate simplices wanted in T_S")
    ap.add_argument(
        "--torus",
        type=int,
        default=None,
        help="an i.i.d. torus sample of this many points instead of a file (T_S as extracted)",
    )
    ap.add_argument(
        "--size",
        type=int,
        nargs=2,
        default=None,
        help="window size (default: 1024 768 off-screen; 1600 1000, the app's default, with --qt)",
    )
    ap.add_argument("--qt", action="store_true", help="measure the Qt main window (needs X)")
    args = ap.parse_args()
    rec = build(args.file, args.d, None if args.torus else args.target, args.torus)
    size = tuple(args.size) if args.size else ((1600, 1000) if args.qt else (1024, 768))
    (qt if args.qt else offscreen)(rec, size)


if __name__ == "__main__":
    main()
