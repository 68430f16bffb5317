"""``sculpt-sample`` batched (session 43): the same flips, held samples and measures as one cell at a time."""

from __future__ import annotations

import numpy as np
from labelled_helpers import cells_of, noisy_torus_editor

from crustview.core.robust.label_repair import LabelEditor
from crustview.core.robust.labelling import Labelling


def test_sculpt_batches_are_the_one_cell_measures():
    """``sculpt-sample`` measures its size bound for whole stars at once (``_star_fits``) and finds the cells with
    only their face opposite the sample on M_S by one gather (``_opposite_on_cut``): on a noisy torus, with a
    unit at which some cells fit and some do not, both give what ``_fits`` and a direct look at each cell's faces
    give, cell by cell, at 300 samples, before and after 300 cells take the other label."""
    rec, lab, ed, rng = noisy_torus_editor()
    unit = ed._unit() * 0.5  # half the sculpting unit: many cells over SIZE_MAX, many under
    vs = sorted(rng.choice(rec.n, 300, replace=False).tolist())  # a fifth of the samples: the loops below are slow
    fit = ed._star_fits(vs, unit)
    assert len(fit) == sum(int((~lab.outside[ed.star(v)]).sum()) for v in vs)
    assert 0 < sum(fit.values()) < len(fit)
    assert all(fit[v, c] == ed._fits(v, c, unit) for v, c in fit)
    found = 0
    for rnd in range(2):
        if rnd:
            ed.flip(rng.choice(np.flatnonzero(~lab.outside), 300, replace=False))
        for v in vs:
            cells = ed.star(v)
            cells = cells[~lab.outside[cells]]
            direct = []
            for c in cells.tolist():
                fs = ed.cell_faces[ed.cell_ptr[c] : ed.cell_ptr[c + 1]]
                on_cut = fs[ed.cut[fs]]
                if len(on_cut) == 1 and not (lab.faces[on_cut[0]] == v).any():
                    direct.append(c)
            assert ed._opposite_on_cut(v, cells) == direct, v
            found += len(direct)
    assert found > 300  # cells with one face on M_S opposite the sample were compared, not only empty lists


def _sculpt_one_cell_at_a_time(ed, free):
    """``sculpt-sample`` as it was written before its batches (session 42): each cell looked at and measured
    alone, in the star's order.  The reference for the test below."""
    from crustview.core.robust.label_repair import SCULPT_ROUNDS

    lab = ed.lab
    ed.cut = lab.cut()
    ed.held = set()
    steps = []
    for _ in range(SCULPT_ROUNDS):
        fv = lab.faces[ed.cut].ravel()
        on = np.zeros(lab.n, bool)
        on[fv[fv < lab.n]] = True
        touched = np.zeros(lab.m, bool)
        done = 0
        unit = ed._unit() if not on.all() else lab.spacing
        for v in np.flatnonzero(~on).tolist():
            cells = ed.star(v)
            cells = cells[~lab.outside[cells]]
            if len(cells) == 0 or touched[cells].any():
                continue
            best, best_conf = -1, np.inf
            for c in cells.tolist():
                fs = ed.cell_faces[ed.cell_ptr[c] : ed.cell_ptr[c + 1]]
                on_cut = fs[ed.cut[fs]]
                if len(on_cut) == 1 and not (lab.faces[on_cut[0]] == v).any():
                    if lab.confidence[c] < best_conf:
                        if v in free or ed._fits(v, c, unit):
                            best, best_conf = c, float(lab.confidence[c])
                        else:
                            ed.held.add(v)
            if best < 0:
                continue
            ed.held.discard(v)
            touched[ed.star(v)] = True
            steps.append((v, np.array([best]), *ed.flip(np.array([best]))))
            done += 1
        if not done:
            break
    return steps


def test_sculpt_takes_the_one_cell_at_a_time_steps(monkeypatch):
    """The batched ``sculpt-sample`` flips the same cells in the same order and holds back the same samples as
    the one-cell-at-a-time loop it replaced, on a noisy torus after ``repair-vertex``, with the unit scaled so
    that some samples are held by the size bound, and again with those samples free of it."""
    rec, _, _, _ = noisy_torus_editor()
    scale = {"f": 1.0}
    unit0 = LabelEditor._unit
    monkeypatch.setattr(LabelEditor, "_unit", lambda self: unit0(self) * scale["f"])

    def run(how, free, f):
        scale["f"] = f
        lab = Labelling(rec.points, *cells_of(rec))
        ed = LabelEditor(lab)
        ed.repair()
        steps = ed.sculpt(free) if how == "batched" else _sculpt_one_cell_at_a_time(ed, free)
        return [(v, c.tolist(), r.tolist(), a.tolist()) for v, c, r, a in steps], sorted(ed.held), lab.inside.copy()

    held_some = False
    for f in (1.0, 0.35):
        steps, held, inside = run("batched", frozenset(), f)
        assert (steps, held) == run("reference", frozenset(), f)[:2]
        held_some |= bool(held)
        if held:
            free = frozenset(held[: len(held) // 2 + 1])
            steps_free, held_free, inside_free = run("batched", free, f)
            ref = run("reference", free, f)
            assert (steps_free, held_free) == ref[:2] and np.array_equal(inside_free, ref[2])
            assert steps_free != steps  # the free samples were sculpted past the bound
        assert steps  # something was sculpted
    assert held_some
