"""Issue 19: seeing that the Klein bottle is non-orientable: a one-sided loop drawn on M_S.

Before, nothing in the view showed it (only the word "no" in the topology table).
"""

from __future__ import annotations

import numpy as np
from gui_helpers import load


def _carry(a, b, s):
    """The orientation sign ``b`` gets from ``a`` (sign ``s``) across their shared edge, consistently."""
    u, v = np.intersect1d(a, b)

    def along(t):
        i = int(np.flatnonzero(t == u)[0])
        return 1 if t[(i + 1) % 3] == v else -1

    return -s * along(a) * along(b)


def test_klein_bottle_shows_a_loop_along_which_the_normal_flips(qtbot, window):
    """The layer is on, its triangles are a closed chain, and carrying an orientation once around it reverses it."""
    rec = load(qtbot, window, "flat-klein")
    assert rec.topology.orientable is False
    m = window.model
    layer = m.layers["orientation"]
    loop = m.one_sided_loop()
    assert layer.visible and layer.count == len(loop) > 2
    tris = np.asarray(rec.manifold)[loop]
    s = 1
    for i in range(len(tris)):
        s = _carry(tris[i], tris[(i + 1) % len(tris)], s)
    assert s == -1  # back at the first triangle with the opposite orientation
    a = window.view.adapters["orientation"]
    assert a.parts[1].n_cells == len(loop) and a.part.n_cells > len(loop)
    assert any("one-sided loop" in label for label, _ in window.view.legend_entries())
    assert window.layers_panel.rows["orientation"].visible.isChecked()


def test_an_orientable_surface_has_no_one_sided_loop(qtbot, window):
    load(qtbot, window, "torus")
    assert len(window.model.one_sided_loop()) == 0
    assert not window.model.layers["orientation"].visible
