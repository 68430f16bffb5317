"""Issue 19: a session keeps the playback speed, the selection and the comparison.

Before, none of the three was written: a reopened session played at 10 steps/s,
selected nothing and had no comparison.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from gui_helpers import wait_idle


def test_speed_selection_and_comparison_come_back(qtbot, window, tmp_path):
    assert window.load_builtin("torus", n=600)
    wait_idle(qtbot, window)
    m = window.model
    rec = m.rec
    window.steps_panel.speed.setValue(750.0)
    tri = sorted(int(v) for v in rec.manifold[3])
    window.info_panel.lookup.setText(" ".join(map(str, tri)))
    window.info_panel.lookup.returnPressed.emit()
    panel = window.info_panel.compare
    spec = {"kind": "run", "test": "literal", "theta": float(np.radians(15.0)), "mode": "robust"}
    assert panel.start(spec)
    qtbot.waitUntil(lambda: m.comparison is not None, timeout=60_000)
    only_b = len(m.comparison.diff.only_b)
    path = window.save_session(tmp_path / "keep")
    assert path is not None, window.last_error
    data = json.loads(path.read_text())
    assert data["speed"] == 750.0 and data["selection"]["simplex"] == tri and data["comparison"]["kind"] == "run"

    assert window.load_builtin("circle", n=80)
    wait_idle(qtbot, window)
    window.steps_panel.speed.setValue(10.0)
    assert window.open_session(path)
    qtbot.waitUntil(lambda: m.source.startswith("torus"), timeout=60_000)
    wait_idle(qtbot, window)
    qtbot.waitUntil(lambda: m.comparison is not None, timeout=60_000)
    assert window.steps_panel.speed.value() == 750.0 and m.player.speed == 750.0
    assert m.selection.simplex is not None and sorted(m.rec.candidates.faces[m.selection.simplex]) == tri
    assert len(m.comparison.diff.only_b) == only_b and m.layers["compare"].visible


def test_bad_kept_fields_are_one_line_errors(tmp_path):
    from crustview.session import BuiltinSource, Session, SessionError, read_session, write_session

    path = write_session(tmp_path / "s", Session(BuiltinSource("torus", 100, 0), 2))
    data = json.loads(path.read_text())
    assert read_session(path).speed == 10.0 and read_session(path).comparison is None
    for key, value, word in (
        ("speed", -1, "speed"),
        ("selection", {"sample": "x"}, "selection.sample"),
        ("comparison", {"kind": "other"}, "comparison"),
        ("comparison", {"kind": "run", "test": "nope", "theta": 0.3}, "comparison.test"),
    ):
        path.write_text(json.dumps({**data, key: value}))
        with pytest.raises(SessionError, match=word):
            read_session(path)
