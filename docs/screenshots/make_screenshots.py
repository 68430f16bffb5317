"""Regenerate the screenshots in this folder from the real main window.

Run from the repository root under a virtual X server::

    xvfb-run -a -s "-screen 0 1600x1000x24" python docs/screenshots/make_screenshots.py [--out DIR] [NAME ...]

Each picture is ``QWidget.grab()`` of the whole window (docks included) at
1440 x 900, saved as a 256-colour PNG (at most ~300 KB).  With names, only those
screenshots are made (e.g. ``torus-step bunny-open``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE.parents[2] / "shared" / "data"
SIZE = (1440, 900)
OUT = HERE


def wait(app, win, timeout: float = 600.0) -> None:
    t0 = time.monotonic()
    while win.runner.busy:
        app.processEvents()
        time.sleep(0.01)
        if time.monotonic() - t0 > timeout:
            raise TimeoutError("reconstruction did not finish")
    for _ in range(5):
        app.processEvents()
    if win.model.rec is None:
        raise RuntimeError(win.last_error or "no result")


def settle(app, win) -> None:
    for _ in range(10):
        app.processEvents()
        time.sleep(0.02)
    win.view.render()
    app.processEvents()


def save(app, win, name: str) -> None:
    from PIL import Image

    settle(app, win)
    path = OUT / f"{name}.png"
    tmp = OUT / f".{name}.tmp.png"
    win.grab().save(str(tmp))
    img = Image.open(tmp).convert("RGB")
    img.quantize(colors=256, method=Image.Quantize.MAXCOVERAGE).save(path, optimize=True)
    tmp.unlink()
    print(f"{path.name}: {path.stat().st_size // 1024} KB")


def scroll_info_to_interpretation(app, win) -> None:
    """Scroll the information panel so that the interpretation and the selection are in view."""
    settle(app, win)
    area = win.docks["info"].widget()
    area.verticalScrollBar().setValue(win.info_panel.interpretation_box.y() - 4)


def front_sample(win, hull: bool | None = None) -> int:
    """A sample facing the camera (optionally a convex-hull sample whose pole at
    infinity points sideways, so that its ray shows)."""
    rec = win.model.rec
    cam = np.array(win.plotter.camera.position)
    p = win.model.projection.project(rec.points)
    dist = np.linalg.norm(p - cam, axis=1)
    if hull is not None:
        is_hull = rec.pole_index[:, 0] >= len(rec.delaunay_simplices)
        dist = np.where(is_hull == hull, dist, np.inf)
        if hull:
            u = win.model.projection.project(rec.voronoi_vertices[rec.pole_index[:, 0]]) - p
            u /= np.linalg.norm(u, axis=1, keepdims=True)
            view = (p - cam) / dist[:, None]
            dist = np.where(np.abs((u * view).sum(axis=1)) < 0.35, dist, np.inf)
    return int(np.argmin(dist))


def torus_step(app, win) -> None:
    win.load_builtin("torus")
    wait(app, win)
    win.model.player.set_step(40)
    win.model.selection.select_sample(front_sample(win, hull=True))
    scroll_info_to_interpretation(app, win)


def torus_framed(app, win) -> None:
    """'Frame each step' on a resolve step, with what earlier steps removed in red."""
    win.load_builtin("torus")
    wait(app, win)
    win.model.layers["removed"].visible = True
    win.model.layers["removed"].opacity = 0.8
    win.steps_panel.follow.setChecked(True)
    win.steps_panel.rule.setCurrentText("resolve-nonmanifold")
    win.model.player.set_step(60)
    win.steps_panel.to_rule.click()


def torus_underside(app, win) -> None:
    """'Frame each step' on the step whose tau lies lowest: seen from below, the top cut away."""
    win.load_builtin("torus")
    wait(app, win)
    m = win.model
    ext = m.rec.extraction
    proj = m.projection.project(m.rec.points)
    j = min((s.index for s in ext.steps if s.kept), key=lambda i: proj[list(ext.steps[i].tau)].mean(axis=0)[2])
    win.steps_panel.follow.setChecked(True)
    m.player.set_step(j + 1)


def trefoil(app, win) -> None:
    win.load_builtin("trefoil")
    wait(app, win)
    win.model.player.last()
    win.model.selection.select_sample(front_sample(win))


def clifford(app, win) -> None:
    win.load_builtin("clifford-torus")
    wait(app, win)
    win.model.player.last()
    win.projection_panel.sliders[(0, 3)].setValue(45)
    win.projection_panel.sliders[(1, 2)].setValue(25)
    win.view.reset_camera()


def s3(app, win) -> None:
    win.load_builtin("s3")
    wait(app, win)
    win.model.player.last()
    win.model.layers["manifold"].shrink = 0.55
    win.model.selection.select_sample(front_sample(win))


def s3_sliced(app, win) -> None:
    """S^3 cut by the hyperplane x4 = -0.4: the cross-section is a 2-sphere (green), and the cap of
    S^3 below it (kept by the half-space cut, coloured by x4) is the 3-ball it bounds."""
    win.load_builtin("s3")
    wait(app, win)
    m = win.model
    m.player.last()
    m.layers["points"].visible = False
    m.layers["normals"].visible = False
    m.layers["manifold"].shrink = 0.6
    win.docks["projection"].raise_()
    panel = win.projection_panel.slice
    panel.show_slice.setChecked(True)
    panel.cut.setChecked(True)
    panel.set_offset(-0.4)
    m.layers["slice"].opacity = 0.45  # the cap inside shows through
    win.view.reset_camera()
    win.plotter.camera.azimuth = 35


def projective_plane(app, win) -> None:
    """The projective plane in R^4, M_S coloured by its 4th coordinate (the one the view drops)."""
    from crustview.core.samples.manifolds import projective_plane_points

    win.start_reconstruction(projective_plane_points(), 2, source="projective plane in R^4 (n = 1000)")
    wait(app, win)
    m = win.model
    m.player.last()
    m.layers["points"].visible = False
    m.layers["normals"].visible = False
    m.layers["manifold"].colorby = "x4"
    win.docks["info"].raise_()
    win.view.reset_camera()


def clifford_stereographic(app, win) -> None:
    """The Clifford torus in R^4 under stereographic projection: a torus of revolution."""
    win.load_builtin("clifford-torus")
    wait(app, win)
    m = win.model
    m.player.last()
    m.layers["points"].visible = False
    m.layers["normals"].visible = False
    win.docks["projection"].raise_()
    win.projection_panel.stereo.setChecked(True)
    win.view.reset_camera()


def look_from(win, direction, zoom: float = 1.0, up=(0.0, 1.0, 0.0)) -> None:
    """Camera for scans with y up (spot, the bunny; ``up`` for others), from ``direction``."""
    cam = win.plotter.camera
    r = win.model.radius
    cam.focal_point = (0.0, 0.0, 0.0)
    cam.position = tuple(r * np.asarray(direction, float))
    cam.up = tuple(up)
    win.plotter.reset_camera(bounds=tuple(np.ravel(np.stack([-np.full(3, r), np.full(3, r)], axis=1))))
    cam.zoom(zoom)


def spot(app, win) -> None:
    win.open_file(DATA / "spot.xyz", d=2)
    wait(app, win)
    win.model.player.last()
    look_from(win, (2.5, 0.8, 1.5), 1.2)
    win.model.selection.select_sample(front_sample(win))


def bunny(app, win, prune: bool = True) -> None:
    win.run_panel.prune.setChecked(prune)
    win.open_file(DATA / "stanford-bunny.xyz", d=2)
    wait(app, win)
    m = win.model
    if prune:  # the paper's prune cascade, part way: what is left, and what it has eaten (red)
        m.layers["removed"].visible = True
        m.player.set_step(int(0.3 * m.player.n_steps))
    else:
        m.player.last()
    look_from(win, (-1.2, 0.5, 3.0), 1.5)


SCANS = DATA / "scans"


def scan(app, win, name: str, mode: str) -> None:
    """Reconstruct the vertices of a real scan (mesh file) in ``mode``."""
    import meshio

    pts = np.asarray(meshio.read(SCANS / name).points, dtype=float)
    win.run_panel.set_mode(mode)
    win.start_reconstruction(pts, 2, source=name)
    wait(app, win)


def scroll_info_to_diagnosis(app, win) -> None:
    """Scroll the information panel to the epsilon histogram and the cascade list."""
    settle(app, win)
    area = win.docks["info"].widget()
    area.verticalScrollBar().setValue(win.info_panel.diagnosis.y() - 4)


def epsilon_and_cascade(app, win, name: str, direction, zoom: float) -> None:
    """Paper mode: samples coloured by the estimated epsilon, the largest cascade highlighted."""
    scan(app, win, name, "paper")
    m = win.model
    m.layers["points"].visible = True
    m.layers["points"].size = 4.0 if m.rec.n < 10000 else 2.0
    m.layers["points"].colorby = "epsilon"
    m.layers["normals"].visible = False
    panel = win.info_panel.diagnosis
    panel.cascades.setCurrentRow(0)
    panel._clicked(panel.cascades.item(0))  # what a click does: highlight and frame
    m.layers["cascade"].opacity = 0.5
    c = m.cascade
    m.player.set_step(c.origin + 1)  # M_S as the cascade starts; teal: all it will remove
    look_from(win, direction, zoom)
    scroll_info_to_diagnosis(app, win)


def robust_result(app, win, name: str, direction, zoom: float, up=(0.0, 1.0, 0.0)) -> None:
    """The robust extraction's final M_S of a real scan, step log at the end."""
    scan(app, win, name, "robust")
    m = win.model
    m.player.last()
    m.layers["normals"].visible = False
    m.layers["points"].visible = False
    look_from(win, direction, zoom, up)


SCANS2 = DATA / "scans2"


def scan_just_opened(app, win) -> None:
    """A scan opened from a file, as it first shows: the final M_S, framed clear of the legend."""
    win.open_file(SCANS2 / "casting.off", d=2)
    wait(app, win)


def elk_joined(app, win) -> None:
    """The elk opened from a file: its antlers joined back by join-parts, the joins in amber."""
    win.open_file(SCANS2 / "elk.off", d=2)
    wait(app, win)


def _open_noisy(app, win, mesh: str, level: float, seed: int) -> None:
    """Open ``mesh`` (under ``../shared/data``) with Gaussian noise of ``level`` times its median spacing,
    numpy's draw ``seed`` (the noise model of ``../shared/tools/noisy.py``), written to a temporary file."""
    import tempfile

    from scipy.spatial import cKDTree

    from crustview.io import read_points

    pts = read_points(DATA / mesh)
    h = float(np.median(cKDTree(pts).query(pts, k=2)[0][:, 1]))
    noisy = pts + np.random.default_rng(seed).normal(scale=level * h, size=pts.shape)
    path = Path(tempfile.mkdtemp()) / f"{Path(mesh).stem}-noise-{level:g}h-draw{seed}.xyz"
    np.savetxt(path, noisy)
    win.open_file(path, d=2)
    wait(app, win)


def camel_decimated(app, win) -> None:
    """The camel head decimated to 30 % of its faces (``bench_scans.py --decimate 0.3``), opened from a file:
    the two robust answers are both open and differ by a hole, which the result names (a dispute)."""
    import tempfile

    sys.path.insert(0, str(HERE.parents[1] / "benchmarks"))
    from bench_shapes import decimated

    from crustview.io import read_mesh

    mesh = read_mesh(DATA / "scans" / "camelhead.off")
    pts, _ = decimated(np.asarray(mesh.points, float), np.asarray(mesh.simplices(2)), 0.3)
    path = Path(tempfile.mkdtemp()) / "camelhead-decimated-30.xyz"
    np.savetxt(path, pts)
    win.open_file(path, d=2)
    wait(app, win)


def noisy_resampled(app, win) -> None:
    """nefertiti with scanner noise of 0.3 h (noise draw 13): a noise tunnel above the length bound, flagged
    by resample-check because the reconstruction of 90 % of the samples does not have it."""
    _open_noisy(app, win, "scans/nefertiti.obj", 0.3, 13)


def noisy_cap_kept(app, win) -> None:
    """The elk with scanner noise of 0.1 h (noise draw 13): a cap 3.7 times the faces around it, no cap of the
    sample over CAP_SURE, so open-cap keeps it closed and lists it as an uncertain hole (with the joins);
    framed as a click on it in the list frames it, its outline drawn by the uncertain-features layer."""
    _open_noisy(app, win, "scans2/elk.off", 0.1, 13)
    win.view.frame_feature(next(f for f in win.model.rec.uncertain_features if f.kind == "hole"))
    wait(app, win)


def noisy_small_hole(app, win) -> None:
    """The lion with scanner noise of 0.1 h (noise draw 21): a hole 3.7 spacings across over a closed part,
    under HOLE_SUPPORTED, listed as an uncertain hole beside the real opening; framed as a click frames it."""
    _open_noisy(app, win, "scans/lion.off", 0.1, 21)
    win.view.frame_feature(next(f for f in win.model.rec.uncertain_features if f.kind == "hole"))
    wait(app, win)


def hand_fused(app, win) -> None:
    """The hand (an OK sign) with scanner noise of 0.1 h (noise draw 22): two fingers that the true mesh keeps
    about one spacing apart are joined into an extra handle, whose basis loops came back near themselves;
    cut short (analysis/necks.py), they are below what an eps = 1/2 sample resolves; listed as uncertain
    handles, the first framed as a click frames it."""
    _open_noisy(app, win, "scans2/hand.off", 0.1, 22)
    win.view.frame_feature(next(f for f in win.model.rec.uncertain_features if f.kind == "handle"))
    wait(app, win)


def camel_bridge(app, win) -> None:
    """The camel head (an open disk) with scanner noise of 0.3 h (noise draw 23): a false bridge makes
    a handle whose basis loop comes back near itself a sixth of the way on; cut short there it is below what
    an eps = 1/2 sample resolves, and the result is amber, the handle framed as a click frames it."""
    _open_noisy(app, win, "scans/camelhead.off", 0.3, 23)
    win.view.frame_feature(next(f for f in win.model.rec.uncertain_features if f.kind == "handle"))
    wait(app, win)


def objects_touching(app, win) -> None:
    """A sphere and a torus one spacing apart with noise of 0.1 h (``benchmarks/bench_objects.py``, seed 2):
    the labelling fuses them into one closed genus-1 surface; the contact rule flags the torus as a part held
    on only by faces standing across the normals, and the result is amber with the contact framed."""
    import tempfile

    sys.path.insert(0, str(HERE.parents[1] / "benchmarks"))
    from bench_objects import pair

    pts, _ = pair("sphere-torus", 1.0, 0.1, 2)
    path = Path(tempfile.mkdtemp()) / "sphere-and-torus-1h-apart.xyz"
    np.savetxt(path, pts)
    win.open_file(path, d=2)
    wait(app, win)
    contact = next(f for f in win.model.rec.uncertain_features if f.kind == "component")
    win.view.frame_feature(contact)
    # as the click framed it, seen from above and a little in front: the neck where the two meet
    cam = win.plotter.camera
    dist = float(np.linalg.norm(np.subtract(cam.position, cam.focal_point)))
    look = np.array([0.0, -0.45, 1.0]) / np.linalg.norm([0.0, -0.45, 1.0])
    cam.position = tuple(np.asarray(cam.focal_point) + 1.6 * dist * look)
    cam.up = (0.0, 1.0, 0.0)
    wait(app, win)


def turned_vase_caps(app, win) -> None:
    """A vase turned in rings 1.5 times farther apart than the vertices along them, with noise of 0.1 h
    (``benchmarks/bench_shapes.py``, seed 1): right (closed, genus 0, every sample), but amber: near the lid's
    axis the dense rings scrambled by noise leave caps 3.3-4 times the faces around them, which open-cap keeps
    closed and lists as possible openings, outlined on the lid."""
    sys.path.insert(0, str(HERE.parents[1] / "benchmarks"))
    from bench_shapes import lathe, profile_vase

    verts, _ = lathe(profile_vase(), 96, 1.5)
    _open_turned(app, win, verts, "turned-vase-rings-1.5x-noise-0.1h.xyz")


def _open_turned(app, win, verts: np.ndarray, name: str) -> None:  # noqa: ANN001
    """Open a turned mesh's vertices with noise of 0.1 h (seed 1), seen from above its lid (z is the axis)."""
    import tempfile

    from scipy.spatial import cKDTree

    h = float(np.median(cKDTree(verts).query(verts, k=2)[0][:, 1]))
    pts = verts + np.random.default_rng(1).normal(scale=0.1 * h, size=verts.shape)
    path = Path(tempfile.mkdtemp()) / name
    np.savetxt(path, pts)
    win.open_file(path, d=2)
    wait(app, win)
    # the whole vase from above its lid, the outlines on the lid and the base
    look_from(win, (0.5, -1.0, 1.3), 1.2, up=(0.0, 0.0, 1.0))
    wait(app, win)


def vase_outline_planar(app, win) -> None:
    """A vase tessellated as CAD tools do (rings 3 times farther apart than the vertices along them, flat base
    and lid without an inner vertex; ``bench_shapes.py``'s ``vase-outline-x3``) with noise of 0.1 h, seed 1:
    open-cap opens both flat ends, and since their rims lie in planes (0.09 spacings RMS) the result is amber,
    the two holes named uncertain (analysis/planar.py) instead of a sure open tube."""
    sys.path.insert(0, str(HERE.parents[1] / "benchmarks"))
    from bench_shapes import profile_vase, turned_outline

    verts, _ = turned_outline(profile_vase()[1:-1], 96, 3.0)
    _open_turned(app, win, verts, "vase-outline-rings-3x-noise-0.1h.xyz")


def curve_gap(app, win) -> None:
    """An open plane curve (half an ellipse, 100 samples): the robust report measures the gap
    between its ends and calls it uncertain (two ends lie on a line: a gap or a straight piece sampled only at
    its ends); the uncertain-features layer draws the gap as the segment between the ends."""
    import tempfile

    t = np.linspace(0.0, np.pi, 100)
    path = Path(tempfile.mkdtemp()) / "open-half-ellipse.xyz"
    np.savetxt(path, np.c_[2.0 * np.cos(t), np.sin(t)])
    win.open_file(path, d=1)
    wait(app, win)


def _noisy_builtin_at_step(app, win, name: str, pick) -> None:  # noqa: ANN001
    """Open a built-in with noise of 1 % of its size (``bench_variants.py``'s draw) and go to the step after
    the one ``pick(steps)`` returns, framed as 'frame each step' frames it."""
    import tempfile

    from crustview.core.samples.manifolds import get_manifold

    m = get_manifold(name)
    base = m.sample(m.default_n, seed=0).points
    size = float(np.ptp(base, axis=0).max())
    pts = base + np.random.default_rng(1).normal(scale=0.01 * size, size=base.shape)
    path = Path(tempfile.mkdtemp()) / f"{name}-noise-1pc.xyz"
    np.savetxt(path, pts)
    win.open_file(path, d=m.d)
    wait(app, win)
    step = pick(win.model.rec.extraction.steps)
    win.steps_panel.follow.setChecked(True)
    win.model.player.set_step(step.index + 1)
    wait(app, win)


def klein_loop_cut(app, win) -> None:
    """The flat Klein bottle in R^4 with noise of 1 % of its size: the walk closed three crosscaps or handles
    around three samples; the step just after the first ``cut-handle``, which removed the simplices at the
    loop's samples (red, 'removed now')."""
    _noisy_builtin_at_step(app, win, "flat-klein", lambda steps: next(s for s in steps if s.rule == "cut-handle"))


def s3_unfold(app, win) -> None:
    """S^3 in R^4 with noise of 1 % of its size: ``fill-hole`` has just removed the four tetrahedra folded into
    a hole of 8 triangles on 6 samples (red, 'removed now'), before its cone closes it."""

    def largest_unfold(steps):  # noqa: ANN001, ANN202 - the hole of 8 triangles and its 4 flaps
        return max((s for s in steps if "folded into it" in s.reason), key=lambda s: len(s.removed))

    _noisy_builtin_at_step(app, win, "s3", largest_unfold)


def bunny_holes(app, win) -> None:
    """The holes of T_S on the bunny: rims, faint patches, the largest labelled with their size."""
    win.run_panel.set_mode("paper")  # step 0 of the paper's Algorithm 3: M_S = T_S, with its holes
    win.open_file(DATA / "stanford-bunny.xyz", d=2)
    wait(app, win)
    m = win.model
    m.player.first()
    m.layers["candidates"].visible = False
    m.layers["holes"].visible = True
    m.layers["points"].visible = False
    m.layers["normals"].visible = False
    look_from(win, (-0.4, -3.0, 0.8), 1.3, up=(0.0, 0.0, -1.0))  # from below: the bunny's open base


def cow_head_opened(app, win) -> None:
    """The cow head opened from a file, as it first shows: its neck opening outlined (amber: a planar cut or a
    flat face), no sliver fin from an ear to the chin (session 30: sculpt-sample's size bound)."""
    win.open_file(SCANS2 / "cow-head.off", d=2)
    wait(app, win)


def footbones_wrong(app, win) -> None:
    """The foot bones opened from a file: the file's own mesh says 26 bones, M_S has fewer parts, and every
    verdict (the note over the view, the Information box, the Run bar) says WRONG the same way."""
    win.open_file(SCANS2 / "footbones.ply", d=2)
    wait(app, win)
    win.docks["info"].raise_()


def torus_green(app, win) -> None:
    """The built-in torus as the demo opens: the verdict over the view, green, whatever dock is in front."""
    win.load_builtin("torus")
    wait(app, win)


#: Window sizes other than :data:`SIZE`.
SIZES = {
    "scan-just-opened": (1600, 1000),
    "elk-joined": (1600, 1000),
    "camel-decimated": (1600, 1000),
    "noisy-resampled": (1600, 1000),
    "noisy-cap-kept": (1600, 1000),
    "noisy-small-hole": (1600, 1000),
    "hand-fused": (1600, 1000),
    "camel-bridge": (1600, 1000),
    "objects-touching": (1600, 1000),
    "turned-vase-caps": (1600, 1000),
    "vase-outline-planar": (1600, 1000),
    "curve-gap": (1600, 1000),
    "klein-loop-cut": (1600, 1000),
    "s3-unfold": (1600, 1000),
    "cow-head-opened": (1600, 1000),
    "footbones-wrong": (1600, 1000),
}

CASES = {
    "scan-just-opened": scan_just_opened,
    "elk-joined": elk_joined,
    "camel-decimated": camel_decimated,
    "noisy-resampled": noisy_resampled,
    "noisy-cap-kept": noisy_cap_kept,
    "noisy-small-hole": noisy_small_hole,
    "hand-fused": hand_fused,
    "camel-bridge": camel_bridge,
    "objects-touching": objects_touching,
    "turned-vase-caps": turned_vase_caps,
    "vase-outline-planar": vase_outline_planar,
    "curve-gap": curve_gap,
    "klein-loop-cut": klein_loop_cut,
    "s3-unfold": s3_unfold,
    "cow-head-opened": cow_head_opened,
    "footbones-wrong": footbones_wrong,
    "torus-green": torus_green,
    "bunny-holes": bunny_holes,
    "fertility-epsilon": lambda app, win: epsilon_and_cascade(app, win, "fertility.off", (0.3, 0.4, 3.0), 2.0),
    "nefertiti-epsilon": lambda app, win: epsilon_and_cascade(app, win, "nefertiti.obj", (0.3, 0.4, 3.0), 1.6),
    "fertility-robust": lambda app, win: robust_result(app, win, "fertility.off", (0.3, 0.4, 3.0), 2.0),
    "nefertiti-robust": lambda app, win: robust_result(
        app, win, "nefertiti.obj", (1.2, -3.0, 0.6), 1.5, up=(0.0, 0.0, 1.0)
    ),
    "torus-step": torus_step,
    "torus-framed": torus_framed,
    "torus-underside": torus_underside,
    "trefoil-r3": trefoil,
    "clifford-torus-r4": clifford,
    "s3-r4": s3,
    "s3-sliced": s3_sliced,
    "projective-plane-x4": projective_plane,
    "clifford-stereographic": clifford_stereographic,
    "spot": spot,
    "bunny": lambda app, win: bunny(app, win, True),
    "bunny-open": lambda app, win: bunny(app, win, False),
}


def main(names: list[str]) -> int:
    global OUT
    if names[:1] == ["--out"]:
        OUT = Path(names[1])
        OUT.mkdir(parents=True, exist_ok=True)
        names = names[2:]
    import pyvista

    pyvista.global_theme.multi_samples = 0
    from PySide6.QtCore import QSettings
    from PySide6.QtWidgets import QApplication

    from crustview.qt.window import MainWindow

    app = QApplication.instance() or QApplication(sys.argv[:1])
    settings = QSettings(str(HERE / ".settings.ini"), QSettings.Format.IniFormat)
    for name in names or list(CASES):
        win = MainWindow(settings=settings)
        win.resize(*SIZES.get(name, SIZE))
        win.show()
        settle(app, win)
        CASES[name](app, win)
        save(app, win, name)
        win.close()
        app.processEvents()
    (HERE / ".settings.ini").unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
