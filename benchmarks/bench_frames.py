"""Frame time of stepping in the real main window: from the key press to the frame on screen.

Opens a mesh or point file, reconstructs it, shows it in the main window
(``QtInteractor``, so it needs an X display: run under ``xvfb-run``) and
times, with the render window's own events:

* → and ← (one step), Home, End and random jumps, as key presses on the view;
* a plain frame in which nothing changed (the floor: what this machine needs
  to render the view and composite the window).

Each time runs from the action to the end of the window composition that
follows the render.  It also counts the renders and window compositions
(``frameSwapped``) each action causes within 90 ms: a step should cost one
of each.

Usage::

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/bench_frames.py resources/fertility.off
    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/bench_frames.py scan.off --paper --samples
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np


class Clock:
    """Times actions in ``win`` until their frame is composited; counts renders and compositions."""

    def __init__(self, win) -> None:
        from PySide6.QtCore import QEventLoop

        self.loop = QEventLoop()  # not the static QApplication.processEvents (a PySide6 6.12 refcount bug)
        self.renders: list[float] = []
        self.starts = 0
        self.swaps = 0
        self.swapped: list[float] = []
        rw = win.plotter.ren_win
        rw.AddObserver("StartEvent", lambda *_: setattr(self, "starts", self.starts + 1))
        rw.AddObserver("EndEvent", lambda *_: self.renders.append(time.perf_counter()))
        win.plotter.frameSwapped.connect(self._swapped)

    def _swapped(self) -> None:
        self.swaps += 1
        self.swapped.append(time.perf_counter())

    def time(self, action, settle: float = 0.09) -> tuple[float, int, int]:
        """Seconds to the frame; renders and compositions until ``settle`` s later (:attr:`busy`:
        seconds to the end of the last composition, when the window can take the next key)."""
        self.renders.clear()
        self.swapped.clear()
        self.starts = self.swaps = 0
        t0 = time.perf_counter()
        action()
        while not self.renders and time.perf_counter() - t0 < 10:
            self.loop.processEvents()
        self.loop.processEvents()
        took = time.perf_counter() - t0
        end = time.perf_counter() + settle
        while time.perf_counter() < end:
            self.loop.processEvents()
            time.sleep(0.002)
        self.busy = max(self.swapped[-1] - t0, took) if self.swapped else took
        return took, self.starts, self.swaps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", type=Path)
    ap.add_argument("-d", type=int, default=2)
    ap.add_argument("--paper", action="store_true", help="the paper's Algorithm 3 (default: robust)")
    ap.add_argument("--samples", action="store_true", help="show the samples too")
    ap.add_argument("--size", type=int, nargs=2, default=(1600, 1000))
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--no-edges", action="store_true", help="draw M_S without its edges")
    args = ap.parse_args()

    import pyvista as pv

    pv.OFF_SCREEN = False
    from PySide6.QtCore import QSettings, Qt
    from PySide6.QtTest import QTest
    from PySide6.QtWidgets import QApplication

    from crustview import io
    from crustview.core import reconstruct
    from crustview.qt.window import MainWindow

    mesh = io.read_mesh(args.file)
    points = mesh.points if mesh is not None else io.read_points(args.file)
    rec = reconstruct(points, args.d, mode="paper" if args.paper else "robust")
    app = QApplication.instance() or QApplication([])
    settings = QSettings(str(Path("/tmp") / "crustview-bench-frames.ini"), QSettings.Format.IniFormat)
    win = MainWindow(settings=settings)
    win.resize(*args.size)
    win.show()
    clock = Clock(win)
    clock.time(lambda: win.model.set_reconstruction(rec, source=args.file.name), settle=0.5)
    if args.samples:
        clock.time(lambda: setattr(win.model.layers["points"], "visible", True), settle=0.3)
    if args.no_edges:
        win.view.adapters["manifold"].part.actor.prop.show_edges = False
    view = win.plotter
    view.setFocus()
    n = rec.extraction.n_steps
    rng = np.random.default_rng(0)
    actions = {
        "step →": lambda: QTest.keyClick(view, Qt.Key.Key_Right),
        "step ←": lambda: QTest.keyClick(view, Qt.Key.Key_Left),
        "Home": lambda: QTest.keyClick(view, Qt.Key.Key_Home),
        "End": lambda: QTest.keyClick(view, Qt.Key.Key_End),
        "jump": lambda: win.model.player.set_step(int(rng.integers(1, n))),
    }
    times: dict[str, list[float]] = {name: [] for name in ("frame (floor)", *actions)}
    counts: dict[str, set] = {name: set() for name in actions}
    busy: dict[str, list[float]] = {name: [] for name in actions}
    clock.time(lambda: win.model.player.set_step(n // 2), settle=0.3)
    for _ in range(args.rounds):
        for name, action in actions.items():
            if name == "End":
                clock.time(lambda: win.model.player.set_step(n // 2), settle=0.3)
            times["frame (floor)"].append(clock.time(view.update, settle=0.05)[0])
            took, renders, swaps = clock.time(action, settle=0.3)
            times[name].append(took)
            busy[name].append(clock.busy)
            counts[name].add((renders, swaps))
    w, h = view.width(), view.height()
    print(
        f"{args.file.name}: n = {rec.n}, {n:,} steps ({rec.mode}), "
        f"final M_S {len(np.asarray(rec.manifold).reshape(-1, rec.d + 1)):,} "
        f"simplices; view {w}x{h} in a {args.size[0]}x{args.size[1]} window"
    )
    floor = float(np.median(times["frame (floor)"]))
    for name, values in times.items():
        med = float(np.median(values))
        extra = (
            ""
            if name not in counts
            else (
                f"   busy {1000 * float(np.median(busy[name])):6.1f} ms;  renders, compositions: "
                + "; ".join(f"{r}, {s}" for r, s in sorted(counts[name]))
            )
        )
        print(
            f"  {name:14s} median {1000 * med:6.1f} ms  p90 {1000 * np.percentile(values, 90):6.1f} ms  "
            f"{med / floor:4.2f} x floor{extra}"
        )
    win.close()
    app.quit()


if __name__ == "__main__":
    main()
