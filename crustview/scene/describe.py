"""Words for what the viewer shows: steps, selections, topology."""

from __future__ import annotations

import numpy as np

from ..core.result import CANDIDATE_TESTS, Reconstruction, Step
from .model import SceneModel


def deg(angle: float) -> str:
    """An angle in radians as degrees, ``"-"`` for NaN."""
    return "-" if angle is None or not np.isfinite(angle) else f"{np.degrees(angle):.1f}°"


def fmt_tuple(t) -> str:
    return "(" + ", ".join(str(int(v)) for v in t) + ")"


def step_words(step: Step | None, position: int, n_steps: int) -> str:
    """One or two sentences about the step just applied at ``position``."""
    if step is None:
        return (
            f"Step 0 / {n_steps}: the candidate complex T_S before extraction. "
            "Press → to apply the first step."
        )
    rule = {"prune-sharp": "Prune sharp/boundary face", "resolve-nonmanifold": "Resolve non-manifold face"}.get(
        step.rule, step.rule
    )
    kept = f"; kept {fmt_tuple(step.kept)}" if step.kept else ""
    return (
        f"Step {position} / {n_steps} — {rule} at τ = {fmt_tuple(step.tau)}: removed "
        f"{len(step.removed)} simplex{'es' if len(step.removed) != 1 else ''} "
        f"{fmt_tuple(step.removed[:8])}{' …' if len(step.removed) > 8 else ''}{kept}; "
        f"angle {deg(step.angle)}. {step.reason}"
    )


def sample_text(model: SceneModel, i: int) -> str:
    """Details of sample ``i``: coordinates, poles, normal error."""
    rec = model.rec
    assert rec is not None
    lines = [f"<b>Sample {i}</b> (input row {int(rec.point_input[i])})"]
    lines.append("x = (" + ", ".join(f"{v:.4g}" for v in rec.points[i]) + ")")
    lines.append(f"local spacing {model.spacing[i]:.4g}")
    for j, p in enumerate(rec.pole_index[i]):
        v = rec.voronoi_vertices[p]
        dist = np.linalg.norm(v - rec.points[i])
        lines.append(f"pole {j + 1}: vertex {int(p)}, distance {dist:.4g}")
    err = model.point_values("normal error")
    if err is not None:
        lines.append(f"angle to the true normal plane: {err[0][i]:.2f}°")
    alive = rec.extraction.alive(model.player.position)
    deg_now = int((rec.extraction.simplices[alive] == i).any(axis=1).sum())
    lines.append(f"in {deg_now} simplices of M_S at this step")
    return "<br>".join(lines)


def simplex_text(model: SceneModel, row: int) -> tuple[str, int | None]:
    """Details of candidate face ``row``; returns the text and the step that removed it."""
    rec = model.rec
    assert rec is not None
    c = rec.candidates
    face = c.faces[row]
    lines = [f"<b>Simplex {fmt_tuple(face)}</b> (candidate {row})"]
    for t in CANDIDATE_TESTS:
        if t in c.angles:
            a = float(c.angles[t][row])
            verdict = "admitted" if a < model.theta else "rejected"
            lines.append(f"{t}: angle {deg(a)} — {verdict} at θ = {deg(model.theta)}")
    e = model.extraction_id(row)
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


def topology_rows(rec: Reconstruction, expected=None) -> list[tuple[str, str, str]]:
    """(quantity, found, expected) rows of the topology table."""
    t = rec.topology
    exp = expected
    rows = [
        ("closed manifold", "yes" if t.closed_manifold else "no", "yes" if exp is not None else ""),
        ("simplices", str(t.n_simplices), ""),
        ("Betti numbers (Z/2)", ", ".join(map(str, t.betti)), ", ".join(map(str, exp.betti)) if exp else ""),
        ("Euler characteristic", str(t.euler), str(exp.euler) if exp else ""),
        (
            "orientable",
            {True: "yes", False: "no", None: "-"}[t.orientable],
            {True: "yes", False: "no"}.get(getattr(exp, "orientable", None), "") if exp else "",
        ),
        ("components", str(t.components), str(exp.betti[0]) if exp else ""),
        ("boundary faces", str(t.boundary_faces), "0" if exp else ""),
        ("non-manifold faces", str(t.nonmanifold_faces), "0" if exp else ""),
        ("singular vertices", str(t.singular_vertices), "0" if exp else ""),
        ("samples not used", str(t.unused_samples), "0" if exp else ""),
        ("extraction stopped", rec.extraction.stopped, "closed" if exp else ""),
    ]
    return rows
