"""Reading shapes in R^4 in the real window: names, colours by coordinate, slices, stereographic view."""

import numpy as np
import pytest

pytest.importorskip("pytestqt")


def load(qtbot, win, name, n=None):
    assert win.load_builtin(name, n)
    qtbot.waitUntil(lambda: not win.runner.busy, timeout=120_000)
    assert win.model.rec is not None, win.last_error
    return win.model.rec


def topology_row(win, name):
    table = win.info_panel.topology
    for r in range(table.rowCount()):
        if table.item(r, 0).text() == name:
            return table.item(r, 1).text(), table.item(r, 2).text()
    raise KeyError(name)


@pytest.mark.parametrize("name, words", [("hopf-link", "2 circles"), ("flat-klein", "Klein bottle")])
def test_the_window_names_the_shape_and_checks_it_against_the_truth(qtbot, window, name, words):
    load(qtbot, window, name)
    assert words in window.windowTitle()
    assert topology_row(window, "shape") == (words, words)


def test_a_translucent_m_s_keeps_its_edges(qtbot, window):
    load(qtbot, window, "torus")
    window.model.layers["manifold"].opacity = 0.4
    prop = window.view.adapters["manifold"].part.actor.prop
    assert prop.show_edges and prop.opacity == pytest.approx(0.4)
