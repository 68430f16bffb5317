"""crustview render: frame plans, captions and the written files (off-screen, no display)."""

from __future__ import annotations

import numpy as np
import pytest

from crustview.animation import caption_band, output_kind, parse_steps, plan_replay


def test_plan_keeps_every_step_within_budget_and_spreads_longer_ranges():
    p = plan_replay(10, (0, 10), budget=20)
    assert p.positions == list(range(11)) and not p.subsampled
    q = plan_replay(1000, (100, 900), budget=50)
    assert q.positions[0] == 100 and q.positions[-1] == 900 and len(q.positions) == 50
    assert np.all(np.diff(q.positions) > 0) and q.subsampled
    assert "50 frames" in q.note() and "100-900 of 1000" in q.note()


def test_parse_steps():
    assert parse_steps(None, 40) == (0, 40)
    assert parse_steps("5:", 40) == (5, 40)
    assert parse_steps(":-10", 40) == (0, 30)
    assert parse_steps("0:999", 40) == (0, 40)
    with pytest.raises(ValueError):
        parse_steps("20:10", 40)
    with pytest.raises(ValueError):
        parse_steps("7", 40)
    with pytest.raises(ValueError, match="starts after the last step: the extraction has 4 steps"):
        parse_steps("100:200", 4)  # was clipped to the last step alone, silently
    assert parse_steps("4:200", 4) == (4, 4)  # the last step itself, asked for


def test_render_checks_its_output_before_the_reconstruction(tmp_path, capsys):
    """A folder that is a file, or the input itself, is refused in one line before any work; missing folders
    are made by the writer, as before (a reviewer caught a first version that refused them)."""
    from crustview.__main__ import main

    src = tmp_path / "s.npy"
    np.save(src, np.random.default_rng(0).normal(size=(200, 3)))
    (tmp_path / "afile").write_text("x")
    assert main(["render", str(src), "-d", "2", "--tour", "-o", str(tmp_path / "afile" / "a.gif")]) == 2
    err = capsys.readouterr().err
    assert "Cannot write" in err and "is not a folder" in err and "reconstructed" not in err
    gif = tmp_path / "in.gif"  # an input named as an animation: refused before it is read
    gif.write_bytes(b"GIF89a")
    assert main(["render", str(gif), "-d", "2", "--tour", "-o", str(gif)]) == 2
    err = capsys.readouterr().err
    assert "Refusing to write over the input" in err and "reconstructed" not in err


def test_render_makes_missing_folders_for_its_output(tmp_path, capsys):
    from crustview.__main__ import main

    out = tmp_path / "new" / "sub" / "a.gif"
    assert main(["render", "circle", "--tour", "--frames", "4", "--size", "160x120", "-o", str(out)]) == 0
    assert out.is_file()
    assert "rendering [" not in capsys.readouterr().err  # no bar when stderr is no terminal (a new user's log)
    frames = tmp_path / "other" / "deeper" / "frames"
    assert main(["render", "circle", "--tour", "--frames", "3", "--size", "160x120", "-o", str(frames)]) == 0
    assert len(list(frames.glob("*.png"))) == 3


def test_output_kind(tmp_path):
    assert output_kind(tmp_path / "a.gif") == "gif"
    assert output_kind(tmp_path / "a.MP4") == "mp4"
    assert output_kind(tmp_path / "frames") == "folder"
    with pytest.raises(ValueError):
        output_kind(tmp_path / "a.avi")


def test_caption_band_draws_text():
    band = caption_band("step 3 of 9: prune-sharp", 300, 38)
    assert band.shape == (38, 300, 3)
    assert (band < 100).any() and (band == 255).mean() > 0.7  # dark text on white
    assert not (caption_band("", 300, 38) < 100).any()  # no text, no ink
    assert (band != caption_band("step 8 of 9: resolve-nonmanifold", 300, 38)).any()  # the ink is the text's


def _decode(path, w, h) -> np.ndarray:
    """Frames of a video decoded by the ffmpeg binary of imageio-ffmpeg (subprocess.run closes its pipes)."""
    import subprocess

    import imageio_ffmpeg

    raw = subprocess.run(
        [imageio_ffmpeg.get_ffmpeg_exe(), "-v", "error", "-i", str(path), "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
        capture_output=True,
        check=True,
    ).stdout
    return np.frombuffer(raw, np.uint8).reshape(-1, h, w, 3)


def _run_cli(args, capsys):
    from crustview.__main__ import main

    code = main(args)
    out = capsys.readouterr()
    assert code == 0, out.err
    return out


def test_render_replay_gif_has_the_planned_frames_and_differs_between_steps(tmp_path, capsys, monkeypatch):
    import sys

    import imageio.v3 as iio

    monkeypatch.delenv("DISPLAY", raising=False)  # headless: EGL, no X server
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)  # as on a terminal: the bar is drawn
    out = tmp_path / "c.gif"
    got = _run_cli(["render", "torus", "--replay", "-o", str(out), "--frames", "5", "--size", "200x160"], capsys)
    frames = iio.imread(out, index=None)
    assert frames.shape[0] == 5 and frames.shape[1:3] == (160, 200)
    assert "rendering [" in got.err and "5/5" in got.err
    # the caption band differs from frame to frame (it names the step)
    assert np.abs(frames[0, :38].astype(int) - frames[-1, :38].astype(int)).sum() > 0


def test_render_tour_mp4_and_png_folder(tmp_path, capsys, monkeypatch):

    monkeypatch.delenv("DISPLAY", raising=False)
    mp4 = tmp_path / "t.mp4"
    _run_cli(["render", "circle-r4", "--tour", "-o", str(mp4), "--frames", "6", "--size", "203x161"], capsys)
    import imageio_ffmpeg

    assert imageio_ffmpeg.count_frames_and_secs(str(mp4))[0] == 6
    reader = imageio_ffmpeg.read_frames(str(mp4))
    assert next(reader)["size"] == (200, 160)  # the stream's own width and height, rounded to multiples of 8
    reader.close()
    video = _decode(mp4, 200, 160)
    assert video.shape[0] == 6 and video.shape[1:3] == (160, 200)  # rounded to multiples of 8
    # the tour moves the projection: the first and last 3-D views differ
    assert np.abs(video[0, 40:].astype(int) - video[-1, 40:].astype(int)).mean() > 1
    folder = tmp_path / "frames"
    _run_cli(["render", "circle", "--replay", "-o", str(folder), "--frames", "3", "--size", "120x100"], capsys)
    assert len(list(folder.glob("frame-*.png"))) == 1  # the circle needs no step: T_S is M_S


def test_render_reports_bad_arguments_in_one_line(tmp_path, capsys):
    from crustview.__main__ import main

    assert main(["render", "circle", "--replay", "-o", str(tmp_path / "x.avi")]) == 2
    assert "use .gif, .mp4 or a folder" in capsys.readouterr().err
    assert main(["render", "circle", "--replay", "--steps", "9:2", "-o", str(tmp_path / "x.gif")]) == 2
    assert "range is empty" in capsys.readouterr().err


def test_a_rendered_file_points_at_no_window_part():
    """The window's notes send the reader to its Information panel and its rotation sliders; a rendered
    file has neither (a new user found "— see Information" in a GIF)."""
    from pathlib import Path

    from crustview.animation import OffscreenScene
    from crustview.core import reconstruct
    from crustview.io import read_points
    from crustview.scene.model import SceneModel

    rec = reconstruct(read_points(Path(__file__).parents[1] / "resources" / "decimated-knight.off"), 2)
    assert rec.uncertain_features  # an amber verdict: the one whose second line pointed at the panel
    model = SceneModel()
    model.set_reconstruction(rec, source="knight")
    scene = OffscreenScene(model, (320, 240))
    try:
        notes = scene.view.notes()
        assert notes and not any("see Information" in n for n in notes), notes
        assert any("(uncertain" in n for n in notes)
        # the verdict's first line is whole: its text rises above its baseline, and at 96.5 % of a 202-pixel view
        # its top was cut off (session 51)
        import pyvista as pv

        from crustview.render.overlay import WARN_COLOR

        scene.view.update_overlays()
        img = np.asarray(scene.plotter.screenshot(None, return_img=True))[..., :3].astype(int)
        amber = np.abs(img - np.array(pv.Color(WARN_COLOR).int_rgb)).sum(axis=2) < 60
        rows = np.flatnonzero(amber.any(axis=1))
        assert rows.size and rows.min() >= 2, rows[:5]
        model.projection.source = "grand tour"
        scene.view.update_basis_text()
        text = scene.view.basis_text.GetText(0)
        assert text.startswith("view axes: grand tour\n") and "sliders" not in text, text
    finally:
        scene.close()


def test_render_redoes_a_saved_results_own_run(tmp_path):
    """A saved result rendered again runs with its own mode and normal planes, as the window reopens it
    (a reviewer found `render` taking the default mode and Algorithm 1's planes)."""
    from crustview.cli_render import load
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import write_result

    points = get_manifold("sphere").sample(300, seed=3).points
    rec = reconstruct(points, 2, mode="paper", normals="smoothed")
    write_result(tmp_path / "r.npz", rec)
    again, _, _ = load(str(tmp_path / "r.npz"), None, None, {})
    assert (again.mode, again.normals_method) == ("paper", "smoothed")
    assert np.array_equal(
        np.sort(again.manifold_input_simplices(), axis=1), np.sort(rec.manifold_input_simplices(), axis=1)
    )
    other, _, _ = load(str(tmp_path / "r.npz"), None, "robust", {})  # --mode on top still wins
    assert other.mode == "robust"


def test_the_first_frames_caption_counts_what_step_0_shows(default_run, camelhead_run):
    """Step 0 of the paper's loop is T_S (the torus's run: the paper's result, so the candidates at the run's
    test and angle); step 0 of a run whose extension builds M_S anew is empty (the camel head's labelling), and
    the caption says so instead of counting the simplices the extension added."""
    from crustview.animation import step_caption
    from crustview.scene.model import SceneModel

    rec, _ = default_run("torus")
    model = SceneModel()
    model.set_reconstruction(rec, source="torus")
    want = int(rec.candidates.mask(rec.test, rec.theta).sum())
    assert (
        step_caption(model, 0)
        == f"step 0 of {rec.extraction.n_steps}: T_S before Algorithm 3 ({want:,} candidate simplices)"
    )
    model.set_reconstruction(camelhead_run, source="camel head")
    ext = camelhead_run.extraction
    assert not ext.alive(0).any() and len(ext.simplices) > 0
    caption = step_caption(model, 0)
    assert caption.startswith(f"step 0 of {ext.n_steps}: M_S empty") and "candidate" not in caption


def test_render_takes_d_auto_and_a_mesh_files_own_d_and_checks_layers_first(tmp_path, capsys, monkeypatch):
    """As ``reconstruct`` and ``view``: ``-d auto``; a mesh file without ``-d`` takes its faces' d (a new
    user had "invalid int value: 'auto'", then "give the intrinsic dimension"); an unknown layer is refused
    in one line before any reconstruction (it was refused only after it)."""
    from pathlib import Path

    from crustview import cli_render
    from crustview.__main__ import main

    monkeypatch.delenv("DISPLAY", raising=False)
    knight = Path(__file__).resolve().parents[1] / "resources" / "decimated-knight.off"
    seen = []
    real = cli_render.load

    def spy(source, d, *args, **kwargs):
        rec, truth, label = real(source, d, *args, **kwargs)
        seen.append((d, rec.d))
        return rec, truth, label

    monkeypatch.setattr(cli_render, "load", spy)
    for extra in (["-d", "auto"], []):
        out = tmp_path / f"k{len(extra)}"
        assert (
            main(["render", str(knight), *extra, "--replay", "-o", str(out), "--frames", "2", "--size", "96x80"]) == 0
        )
        assert len(list(out.glob("frame-*.png"))) == 2
    assert seen == [("auto", 2), (None, 2)]
    capsys.readouterr()
    seen.clear()
    code = main(["render", str(knight), "--tour", "--layers", "manifold,nonsense", "-o", str(tmp_path / "x")])
    assert code == 2 and seen == []  # refused before the reconstruction
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown layers ['nonsense']" in err[0] and "manifold" in err[0]
    # a replay of one frame has no first and last step: one line before the run (it was "unexpected ValueError")
    assert main(["render", str(knight), "--replay", "-o", str(tmp_path / "y"), "--frames", "1"]) == 2 and seen == []
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--frames 2 or more" in err[0] and "unexpected" not in err[0]
    assert main(["render", "circle", "--tour", "-o", str(tmp_path / "z"), "--frames", "0"]) == 2
    assert "positive integer" in capsys.readouterr().err
