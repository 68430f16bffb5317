"""Session files (crustview.session): round trip, moved or changed input, malformed files. No Qt."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from crustview.scene.projection import Projection
from crustview.session import (
    BuiltinSource,
    Session,
    SessionError,
    file_source,
    read_session,
    resolve_input,
    session_path,
    write_session,
)


def _full_session(tmp_path) -> tuple[Session, object]:
    pts = tmp_path / "data" / "points.xyz"
    pts.parent.mkdir()
    np.savetxt(pts, np.random.default_rng(0).normal(size=(30, 3)))
    proj = Projection(4)
    proj.set_angle(0, 3, 0.4)
    s = Session(
        file_source(pts, tmp_path / "s.crustview.json"),
        d=2,
        test="literal",
        theta=0.3,
        prune_boundary=False,
        mode="paper",
        step=17,
        camera={
            "position": [1.0, 2.0, 3.0],
            "focal_point": [0.0, 0.0, 0.0],
            "up": [0.0, 0.0, 1.0],
            "view_angle": 30.0,
            "parallel": False,
            "parallel_scale": 1.0,
            "window_center": [0.1, -0.2],
        },
        projection=proj.state(),
        layers={
            "points": {
                "visible": False,
                "color": "#123456",
                "opacity": 0.5,
                "size": 4.0,
                "colorby": "x4",
                "mode": "",
                "shrink": 1.0,
            }
        },
        slice={"offset": -0.25, "cut": True},
    )
    return s, pts


def test_round_trip_keeps_every_field(tmp_path):
    s, pts = _full_session(tmp_path)
    path = write_session(tmp_path / "s", s)
    assert path.name == "s.crustview.json"
    back = read_session(path)
    assert back == s
    assert back.source.relative == os.path.join("data", "points.xyz")
    raw = json.loads(path.read_text())
    assert raw["crustview_session"] == 1 and math.isclose(raw["theta_degrees"], math.degrees(0.3))
    b = Session(BuiltinSource("torus", 1500, 3), d=2)
    assert read_session(write_session(tmp_path / "b.crustview.json", b)) == b


def test_projection_state_restores_basis_and_angles():
    p = Projection(4)
    p.set_coordinates(1, 2, 3)
    p.set_angle(0, 2, 0.7)
    p.set_stereographic(1.5)
    q = Projection(4)
    q.restore(json.loads(json.dumps(p.state())))
    assert np.allclose(q.basis, p.basis) and q.angles == p.angles and q.stereo_radius == 1.5
    assert q.description == p.description
    with pytest.raises(ValueError, match="R\\^4"):
        Projection(3).restore(p.state())


def test_input_found_unchanged_beside_the_session_or_reported_moved(tmp_path):
    s, pts = _full_session(tmp_path)
    path = write_session(tmp_path / "s.crustview.json", s)
    assert resolve_input(read_session(path).source, path) == (pts.resolve(), "")
    # the folder moved as a whole: found by the relative path, with a note
    moved = tmp_path / "elsewhere"
    moved.mkdir()
    (tmp_path / "data").rename(moved / "data")
    os.replace(path, moved / path.name)
    found, note = resolve_input(read_session(moved / path.name).source, moved / path.name)
    assert found == (moved / "data" / "points.xyz").resolve() and "beside the session" in note
    # the file alone moved: one sentence saying so
    (moved / "data" / "points.xyz").rename(tmp_path / "gone.xyz")
    with pytest.raises(SessionError, match="moved or deleted") as err:
        resolve_input(read_session(moved / path.name).source, moved / path.name)
    assert "\n" not in str(err.value)


def test_changed_input_is_refused_even_at_the_same_size(tmp_path):
    s, pts = _full_session(tmp_path)
    path = write_session(tmp_path / "s.crustview.json", s)
    text = pts.read_bytes()
    pts.write_bytes(text + b"0 0 0\n")
    with pytest.raises(SessionError, match="changed since the session was saved.*bytes then"):
        resolve_input(read_session(path).source, path)
    swapped = bytearray(text)
    i = swapped.index(b"1")
    swapped[i : i + 1] = b"2"  # same size, other content
    pts.write_bytes(bytes(swapped))
    with pytest.raises(SessionError, match="same size, other content"):
        resolve_input(read_session(path).source, path)
    pts.write_bytes(text)  # the same content again, newer mtime: fine
    assert resolve_input(read_session(path).source, path)[0] == pts.resolve()


@pytest.mark.parametrize(
    "content, words",
    [
        ("{not json", "not valid JSON (line 1"),
        ("[1, 2]", "holds no JSON object"),
        ("{}", "no 'crustview_session' version key"),
        ('{"crustview_session": 2}', "version 2 is not supported"),
        ('{"crustview_session": 1, "source": {"kind": "url"}}', "kind 'file' or 'builtin'"),
        ('{"crustview_session": 1, "source": {"kind": "builtin", "name": "torus", "n": 10}, "d": 0}', "'d' must be"),
        (
            '{"crustview_session": 1, "source": {"kind": "builtin", "name": "torus", "n": 10}, "d": 2, '
            '"test": "magic", "theta": 0.3}',
            "'test' is 'magic'",
        ),
        (
            '{"crustview_session": 1, "source": {"kind": "builtin", "name": "torus", "n": 10}, "d": 2, "theta": 3.0}',
            "between 0 and",
        ),
        (
            '{"crustview_session": 1, "source": {"kind": "builtin", "name": "torus", "n": 10}, "d": 2, '
            '"theta": 0.3, "camera": {"position": [1, 2]}}',
            "camera.position",
        ),
        (
            '{"crustview_session": 1, "source": {"kind": "builtin", "name": "torus", "n": 10}, "d": 2, '
            '"theta": 0.3, "layers": {"points": {"opacity": "high"}}}',
            "'opacity' has the wrong type",
        ),
        ('{"crustview_session": 1, "source": {"kind": "file", "path": "/x"}, "d": 2, "theta": 0.3}', "'size'"),
    ],
)
def test_malformed_or_other_version_files_give_one_line(tmp_path, content, words):
    path = tmp_path / "bad.crustview.json"
    path.write_text(content)
    with pytest.raises(SessionError) as err:
        read_session(path)
    assert words in str(err.value) and "\n" not in str(err.value) and "bad.crustview.json" in str(err.value)


def test_missing_and_binary_session_files(tmp_path):
    with pytest.raises(SessionError, match="does not exist"):
        read_session(tmp_path / "none.crustview.json")
    (tmp_path / "bin.crustview.json").write_bytes(b"\xff\xfe\x00\x81")
    with pytest.raises(SessionError, match="not UTF-8"):
        read_session(tmp_path / "bin.crustview.json")


def test_session_path_adds_the_ending():
    assert session_path("a/b").name == "b.crustview.json"
    assert session_path("a/b.json").name == "b.crustview.json"
    assert session_path("a/b.crustview.json").name == "b.crustview.json"


def test_view_command_reports_a_bad_session_in_one_line(tmp_path):
    bad = tmp_path / "x.crustview.json"
    bad.write_text('{"crustview_session": 7}')
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    out = subprocess.run(
        [sys.executable, "-m", "crustview", "view", str(bad)], capture_output=True, text=True, env=env, timeout=60
    )
    assert out.returncode == 2
    assert out.stderr.strip().count("\n") == 0 and "version 7 is not supported" in out.stderr
