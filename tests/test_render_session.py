"""Issue 19: ``crustview render SESSION.crustview.json`` with --camera, --projection, --test, --theta, --frame-steps.

Before, ``render`` rejected a ``.json`` input and had none of these options.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pyvista")


def _session(tmp_path, **kw):
    from crustview.session import BuiltinSource, Session, write_session

    s = Session(BuiltinSource("torus", 400, 0), 2, **kw)
    return write_session(tmp_path / "t.crustview.json", s)


def _main(args, capsys):
    from crustview.__main__ import main

    code = main(args)
    out = capsys.readouterr()
    return code, out


def _png(folder):
    import imageio.v3 as iio

    return [iio.imread(p) for p in sorted(folder.glob("frame-*.png"))]


def test_render_a_session_keeps_its_layers_and_step(tmp_path, capsys, monkeypatch):
    """The session's layers (points hidden) and projection are used; a tour starts at the session's run."""
    monkeypatch.delenv("DISPLAY", raising=False)
    path = _session(tmp_path, layers={"points": {"visible": False}, "manifold": {"color": "#ff0000"}})
    out = tmp_path / "frames"
    code, got = _main(["render", str(path), "--tour", "-o", str(out), "--frames", "2", "--size", "320x240"], capsys)
    assert code == 0, got.err
    frames = _png(out)
    assert len(frames) == 2
    img = frames[0][40:].astype(int)
    red = (img[..., 0] > 110) & (img[..., 1] < 70) & (img[..., 2] < 70)
    assert red.sum() > 2000, red.sum()  # M_S in the session's red


def test_render_options_test_theta_projection_camera_and_frame_steps(tmp_path, capsys, monkeypatch):
    """--test and --theta change the run, --projection and --camera the view, --frame-steps the replay's camera."""
    monkeypatch.delenv("DISPLAY", raising=False)
    path = _session(tmp_path)
    base = ["render", str(path), "--replay", "--frames", "3", "--size", "160x120", "--steps", "1:40"]
    a, b, c = tmp_path / "a", tmp_path / "b", tmp_path / "c"
    assert _main(base + ["-o", str(a)], capsys)[0] == 0
    code, got = _main(
        base + ["-o", str(b), "--test", "cocone-all", "--theta", "20", "--projection", "2,3,1", "--camera", "0,0,1"],
        capsys,
    )
    assert code == 0, got.err
    assert "reconstructed torus" in got.err
    code, got = _main(base + ["-o", str(c), "--frame-steps"], capsys)
    assert code == 0, got.err
    fa, fb, fc = _png(a), _png(b), _png(c)
    assert len(fa) == len(fb) == len(fc) == 3
    assert np.abs(fa[-1][40:].astype(int) - fb[-1][40:].astype(int)).mean() > 1  # another view
    assert np.abs(fa[-1][40:].astype(int) - fc[-1][40:].astype(int)).mean() > 1  # framed on the step


def test_render_session_options_are_checked(tmp_path, capsys):
    path = _session(tmp_path)
    out = str(tmp_path / "x.gif")
    for extra, word in (
        (["--projection", "1,9"], "--projection"),
        (["--camera", "0,0"], "--camera"),
        (["--projection", "stereo"], "R^4"),
    ):
        code, got = _main(["render", str(path), "--replay", "-o", out] + extra, capsys)
        assert code == 2 and word in got.err, got.err
