"""The inspector's words for a selected sample, simplex or face (split from :mod:`.describe`)."""

from __future__ import annotations

import numpy as np

from ..core.result import CANDIDATE_TESTS
from .describe import TEST_QUANTIFIER, deg, fmt_tuple
from .model import SceneModel
from .quantities import POLE_INFINITE, POLE_NONE, pole_direction, pole_kinds


def sample_text(model: SceneModel, i: int) -> str:
    """Details of sample ``i``: coordinates, poles, normal error."""
    rec = model.rec
    assert rec is not None
    lines = [f"<b>Sample {i}</b> ({input_rows_words(rec, i)})"]
    lines.append("x = (" + ", ".join(f"{v:.4g}" for v in rec.points[i]) + ")")
    lines.append(f"local spacing {model.spacing[i]:.4g}")
    lines.append(epsilon_line(model, i))
    kinds = pole_kinds(rec)[i]
    for j, p in enumerate(rec.pole_index[i]):
        if kinds[j] == POLE_NONE:
            lines.append(
                f"pole {j + 1}: none (normal direction orthogonal to the samples' "
                f"{rec.subspace_dim}-dimensional affine hull)"
            )
        elif kinds[j] == POLE_INFINITE:
            u = pole_direction(rec, i, j)
            lines.append(
                f"pole {j + 1}: vertex at infinity (hull sample), direction (" + ", ".join(f"{v:.3f}" for v in u) + ")"
            )
        else:
            dist = np.linalg.norm(rec.voronoi_vertices[p] - rec.points[i])
            lines.append(f"pole {j + 1}: vertex {int(p)}, distance {dist:.4g}")
    err = model.point_values("normal error")
    if err is not None:
        lines.append(f"angle to the true normal plane: {err[0][i]:.2f}°")
    alive = rec.extraction.alive(model.player.position)
    deg_now = int((rec.extraction.simplices[alive] == i).any(axis=1).sum())
    lines.append(f"in {deg_now} simplices of M_S at this step")
    return "<br>".join(lines)


def epsilon_line(model: SceneModel, i: int) -> str:
    """Sample ``i``'s estimated epsilon against the paper's bounds (as the epsilon colouring shows it)."""
    q = model.quality
    eps = float(q.epsilon[i])
    if not np.isfinite(eps):
        return "estimated ε: none (no finite pole)"
    beyond = [name for name, b in sorted(q.thresholds.items(), key=lambda t: t[1]) if eps > b]
    words = "within every bound" if not beyond else "beyond " + ", ".join(beyond)
    return f"estimated ε {eps:.3g} ({words})"


def simplex_text(model: SceneModel, row: int) -> tuple[str, int | None]:
    """Details of candidate face ``row``; returns the text and the step that removed it."""
    rec = model.rec
    assert rec is not None
    c = rec.candidates
    face = c.faces[row]
    e = model.extraction_id(row)
    # the number the steps use (T_S of the extraction); other Delaunay faces by their row
    ident = f"T_S simplex {e}" if e >= 0 else f"Delaunay {rec.d}-face {row}, not in T_S"
    lines = [f"<b>Simplex {fmt_tuple(face)}</b> ({ident})"]
    lines.append(f"deciding angle of each test, verdict at θ = {deg(model.theta)}:")
    for t in CANDIDATE_TESTS:
        if t in c.angles:
            a = float(c.angles[t][row])
            verdict = "admitted" if a < model.theta else "rejected"
            used = " (used by the extraction)" if t == rec.test else ""
            lines.append(f"&nbsp;&nbsp;{t} ({TEST_QUANTIFIER.get(t, '')}): {deg(a)} — <b>{verdict}</b>{used}")
    if c.vertex_angles is not None:
        va = c.vertex_angles[row]
        parts = [f"{int(v)}: {deg(float(a))}" for v, a in zip(face, va)]
        lines.append("cocone angle at each vertex: " + ", ".join(parts) + " (cocone = smallest, cocone-all = largest)")
    removed_step = None
    if e < 0:
        lines.append(f"not in T_S of the extraction ({rec.test}, θ = {deg(rec.theta)})")
    else:
        r = int(rec.extraction.removed_at[e])
        if r >= rec.extraction.n_steps:
            lines.append("never removed: part of the final M_S")
        else:
            removed_step = r + 1
            s = rec.extraction.steps[r]
            lines.append(f"removed by step {r + 1} ({s.rule} at τ = {fmt_tuple(s.tau)})")
    return "<br>".join(lines), removed_step


def face_text(model: SceneModel, face) -> str:
    rec = model.rec
    assert rec is not None
    alive = rec.extraction.alive(model.player.position)
    from .geometry import simplices_at_face

    inc = simplices_at_face(rec.extraction.simplices[alive], face)
    kind = "boundary" if len(inc) == 1 else ("non-manifold" if len(inc) > 2 else "manifold")
    return f"<b>Face {fmt_tuple(face)}</b>: {len(inc)} incident simplices at this step ({kind})"


#: Most input rows the inspector lists for one sample (the others are counted).
ROWS_LISTED = 4


def input_rows_words(rec, i: int) -> str:
    """E.g. "input row 5", or "input rows 5, 9 (one point)" for rows merged into sample ``i``."""
    rows = np.flatnonzero(np.asarray(rec.input_index) == i)
    if len(rows) <= 1:
        return f"input row {int(rec.point_input[i])}"
    shown = ", ".join(str(int(r)) for r in rows[:ROWS_LISTED])
    more = f" and {len(rows) - ROWS_LISTED:,} more" if len(rows) > ROWS_LISTED else ""
    return f"input rows {shown}{more} (one point)"
