"""Words for what the viewer shows: steps, selections, topology."""

from __future__ import annotations

import numpy as np

from ..core.result import Reconstruction
from ..core.steps import PLACELESS_RULES, Extraction, Step
from .features import uncertain_features, uncertain_summary
from .quantities import hull_samples
from .shapes import name_of, shape_name

#: One line per candidate test: what it asks of a d-face (for tool tips and the inspector).
TEST_WORDS = {
    "cocone": "the dual Voronoi cell meets the tangent cocone of SOME vertex of the face (the paper's quantifier)",
    "cocone-all": "the dual Voronoi cell meets the tangent cocone of EVERY vertex of the face (Cocone's rule)",
    "literal": (
        "the dual Voronoi cell is within θ of AN_s for some vertex s, by orientation only (the paper, literally)"
    ),
}

#: Short name of each test's quantifier.
TEST_QUANTIFIER = {"cocone": "some vertex", "cocone-all": "every vertex", "literal": "orientation only, some vertex"}

#: What each value of ``Extraction.stopped`` means.
STOPPED_WORDS = {
    "closed": "closed: every (d-1)-face lies in 0 or 2 simplices",
    "empty": "empty: every candidate simplex was removed",
    "open": "open: boundary faces kept (prune boundary off), or holes the robust extension left open",
    "stuck": "stuck: no rule applies but the complex is not closed",
}


def deg(angle: float) -> str:
    """An angle in radians as degrees, ``"-"`` for NaN."""
    return "-" if angle is None or not np.isfinite(angle) else f"{np.degrees(angle):.1f}°"


def fmt_tuple(t) -> str:
    return "(" + ", ".join(str(int(v)) for v in t) + ")"


def tau_text(step: Step) -> str:
    """A step's τ for a table cell: "—" for a rule that acts everywhere at once (``PLACELESS_RULES``)."""
    return "—" if step.rule in PLACELESS_RULES else fmt_tuple(step.tau)


#: What a robust run that starts from an empty M_S builds it with, by its first step's rule.
EMPTY_START = {
    "label-cells": "the robust extension builds M_S from the labelled Delaunay cells (Steps: label-cells first)",
    "seed-core": "the robust extension grows M_S from a seed (Steps: seed-core first)",
    "seed": "the robust extension grows M_S from a seed (Steps: seed first)",
}


def step_words(step: Step | None, position: int, n_steps: int, extraction: Extraction | None = None) -> str:
    """One or two sentences about the step just applied at ``position``.

    ``extraction``: the run, for step 0 of a robust run that starts from an empty M_S (the paper's loop was
    abandoned and the extension builds M_S anew), which is not T_S.
    """
    if step is None:
        if n_steps == 0:
            return "Step 0 / 0: T_S already is a closed manifold, so Algorithm 3 had nothing to do; M_S = T_S."
        first = extraction.steps[0].rule if extraction is not None and extraction.steps else None
        if first in EMPTY_START and not extraction.alive(0).any():
            return (
                f"Step 0 / {n_steps}: M_S is empty: the paper's Algorithm 3 could not give a closed manifold "
                f"through every sample, so {EMPTY_START[first]}; T_S has a layer of its own. Press → to apply "
                "the first step."
            )
        return f"Step 0 / {n_steps}: the candidate complex T_S before extraction. Press → to apply the first step."
    rule = {"prune-sharp": "Prune sharp/boundary face", "resolve-nonmanifold": "Resolve non-manifold face"}.get(
        step.rule, step.rule
    )
    kept = f"; kept {fmt_tuple(step.kept)}" if step.kept else ""
    if step.added and not step.removed:
        words = {
            "seed-core": "Seed M_S with the manifold core of T_S",
            "seed": "Seed M_S",
            "grow": "Grow across a boundary face",
            "grow-relaxed": "Grow across a boundary face (θ relaxed)",
            "fill-hole": "Fill a hole",
            "insert-sample": "Insert a left-out sample",
            "label-cells": "Label every Delaunay cell inside or outside (M_S: the faces between the labels)",
        }
        at = "" if step.rule in PLACELESS_RULES else f" at τ = {fmt_tuple(step.tau)}"
        return (
            f"Step {position} / {n_steps} — {words.get(step.rule, step.rule)}{at}: added "
            f"{len(step.added)} {'simplex' if len(step.added) == 1 else 'simplices'} "
            f"{fmt_tuple(step.added[:8])}{' …' if len(step.added) > 8 else ''}"
            + (f"; angle {deg(step.angle)}" if np.isfinite(step.angle) else "")
            + (f". {step.reason[0].upper()}{step.reason[1:]}." if step.reason else ".")
        )
    return (
        f"Step {position} / {n_steps} — {rule} at τ = {fmt_tuple(step.tau)}: removed "
        f"{len(step.removed)} {'simplex' if len(step.removed) == 1 else 'simplices'} "
        f"{fmt_tuple(step.removed[:8])}{' …' if len(step.removed) > 8 else ''}{kept}"
        + (f"; angle {deg(step.angle)}" if np.isfinite(step.angle) else "")
        + (f". {step.reason[0].upper()}{step.reason[1:]}." if step.reason else ".")
    )


def interpretation_rows(rec: Reconstruction) -> list[tuple[str, str, str]]:
    """(choice, value, explanation) rows: how the core read the paper for this result."""
    rows = []
    rel = rec.joggle / rec.spacing if rec.spacing > 0 else 0.0
    rows.append(
        (
            "joggle",
            "none" if rec.joggle == 0 else f"{rec.joggle:.3g} ({rel:.1e} × spacing)",
            "deterministic perturbation before Qhull, so cospherical points are in general position; "
            "no quantity the algorithm uses moves by more than this",
        )
    )
    if rec.subspace_dim < rec.k:
        rows.append(
            (
                "affine hull",
                f"{rec.subspace_dim}-dimensional (k = {rec.k})",
                f"the pipeline ran in that subspace; the {rec.k - rec.subspace_dim} orthogonal directions "
                "were added to every normal plane (poles 'none')",
            )
        )
    hull = int(hull_samples(rec).sum())
    rows.append(
        (
            "hull samples",
            f"{hull} of {rec.n} with first pole at infinity",
            "samples on the convex hull have unbounded Voronoi cells; their first pole is the vertex at "
            "infinity (mean direction of the cut-off cell), drawn towards the edge of the box",
        )
    )
    rows.append(
        (
            "candidate test",
            f"{rec.test} ({TEST_QUANTIFIER.get(rec.test, '')}), θ = {deg(rec.theta)}",
            f"a d-face is a candidate when {TEST_WORDS.get(rec.test, rec.test)}",
        )
    )
    rows.append(
        (
            "extraction",
            "robust (the paper's Algorithm 3, extended)" if rec.mode == "robust" else "the paper's Algorithm 3",
            "robust: the paper's loop first; if it cannot give a closed manifold through every sample, M_S is "
            "grown across boundaries instead (rules seed, grow, grow-relaxed, fill-hole, drop-stray, insert-sample)"
            if rec.mode == "robust"
            else "exactly as printed: prune sharp and boundary faces, resolve non-manifold faces",
        )
    )
    rows.append(
        (
            "boundary faces",
            "pruned (paper)" if rec.prune_boundary else "kept (prune off)",
            "Algorithm 3 removes simplices at faces with a single simplex; on a scan with holes this "
            "cascades until nothing is left"
            if rec.prune_boundary
            else "faces with a single simplex are kept, so a scan with holes shows as an open surface; "
            "the result cannot be closed",
        )
    )
    rows.append(
        (
            "extraction stopped",
            rec.extraction.stopped,
            STOPPED_WORDS.get(rec.extraction.stopped, rec.extraction.stopped),
        )
    )
    return rows


def open_surface(t) -> bool:
    """A manifold with boundary through every sample: boundary faces, no face in more than two simplices.

    (Pinched vertices are counted only on complexes without boundary, by
    :func:`~crustview.core.analysis.topology.analyse`; the robust extension
    repairs them on every path.)
    """
    return bool(
        t.boundary_faces > 0
        and t.nonmanifold_faces == 0
        and t.singular_vertices == 0
        and t.unused_samples == 0
        and t.n_simplices > 0
    )


def kept_open(rec: Reconstruction) -> bool:
    """A robust result that is a manifold with boundary through every sample (:func:`open_surface`).

    For d >= 3 also every boundary sample's link a disc
    (:func:`~crustview.core.analysis.solidholes.pinched_rim_vertices`): the report counts pinched vertices
    on closed complexes only, and a noisy S^3 left open had rim samples whose links were annuli.
    """
    t = rec.topology
    if rec.mode != "robust" or t.closed_manifold or not open_surface(t):
        return False
    if rec.d >= 3:
        from ..core.analysis.solidholes import pinched_rim_vertices

        return len(pinched_rim_vertices(np.asarray(rec.manifold))) == 0
    return True


def open_shape(d: int) -> str:
    """What a manifold with boundary of dimension ``d`` is called: "open curve", "surface with boundary", ..."""
    return {1: "open curve", 2: "surface with boundary"}.get(d, f"{d}-manifold with boundary")


def boundary_words(rec: Reconstruction) -> str:
    """The boundary in words: "1 hole", "3 holes" (the hole features), or the boundary face count."""
    # not caps kept closed (removed), nor where two answers differ by a hole (disputed: a place, not a hole)
    holes = sum(f.kind == "hole" and not f.removed and not f.disputed for f in (rec.features or []))
    if holes:
        return f"{holes} hole{'s' if holes != 1 else ''}"
    return f"{rec.topology.boundary_faces} boundary faces"


def truth_problems(rec: Reconstruction, truth=None) -> list[str]:
    """Where M_S contradicts a known truth: a built-in's Betti numbers, or those of the file's own mesh.

    ``truth`` is the scene's (``SceneModel.truth``): ``manifold`` for a built-in, ``comparison`` (a
    :class:`~crustview.core.analysis.compare.MeshComparison`) for a file whose faces are known.  Only a
    result that is a closed manifold, or a robust surface with boundary through every sample, is compared
    (anything else is already a failure of its own).
    """
    if truth is None:
        return []
    t = rec.topology
    problems = []
    expected = getattr(truth, "manifold", None)
    if expected is not None and t.closed_manifold and tuple(t.betti) != tuple(expected.betti):
        problems.append(f"Betti {tuple(t.betti)} ≠ true {tuple(expected.betti)}")
    mesh_cmp = getattr(truth, "comparison", None)
    if (
        mesh_cmp is not None
        and _mesh_judges(mesh_cmp)
        and (t.closed_manifold or kept_open(rec))
        and tuple(t.betti) != tuple(mesh_cmp.mesh_topology.betti)
        and not _up_to_unresolved(rec, mesh_cmp)
    ):
        problems.append(f"Betti {tuple(t.betti)} ≠ mesh {tuple(mesh_cmp.mesh_topology.betti)}")
    return problems


def _mesh_judges(mesh_cmp) -> bool:
    """Whether the file's mesh is a manifold (with or without boundary), whose Betti numbers can judge M_S.

    A mesh with an edge in three faces or more, or a pinched vertex, is no surface: its Betti numbers
    count what no manifold reconstruction can have (a new user's beetle.obj: 47 such edges).
    """
    m = mesh_cmp.mesh_topology
    return m.nonmanifold_faces == 0 and m.singular_vertices == 0 and getattr(mesh_cmp, "mesh_pinched", 0) == 0


def _up_to_unresolved(rec: Reconstruction, mesh_cmp) -> bool:
    """M_S has the Betti numbers of the mesh with some of its holes below the sample's resolution closed."""
    u = getattr(mesh_cmp, "unresolved", None)
    return u is not None and u.allows(tuple(rec.topology.betti))


def truth_notes(rec: Reconstruction, truth=None) -> list[str]:
    """What the verdict adds about a file's mesh that cannot judge M_S as it stands (empty when it can).

    The mesh is not a manifold, or M_S differs from it only by holes the sample cannot show
    (:class:`~crustview.core.analysis.compare.UnresolvedHoles`): a mesh missing one triangle is open,
    and a closed M_S through its vertices is as right as a sample of them allows.
    """
    mesh_cmp = getattr(truth, "comparison", None) if truth is not None else None
    if mesh_cmp is None:
        return []
    m = mesh_cmp.mesh_topology
    if not _mesh_judges(mesh_cmp):
        what = []
        if m.nonmanifold_faces:
            many = m.nonmanifold_faces != 1
            what.append(f"{m.nonmanifold_faces} edge{'s' if many else ''} in three faces or more")
        pinched = m.singular_vertices or getattr(mesh_cmp, "mesh_pinched", 0)
        if pinched:
            what.append(f"{pinched} pinched vertex" + ("es" if pinched != 1 else ""))
        return [f"the file's mesh is not a manifold ({', '.join(what)}): its Betti numbers judge nothing"]
    t = rec.topology
    if (t.closed_manifold or kept_open(rec)) and tuple(t.betti) != tuple(m.betti) and _up_to_unresolved(rec, mesh_cmp):
        return [f"it has the mesh's topology but for {mesh_cmp.unresolved.words()}"]
    return []


def verdict(rec: Reconstruction, truth=None) -> tuple[str, str]:
    """(level, one-line verdict): level is "ok", "warn" or "bad".

    "bad": M_S contradicts the known truth (:func:`truth_problems`: a built-in's, or the file's own
    mesh's Betti numbers), whatever else holds -- the viewer never calls a result that the file's own
    faces show wrong merely unsure; or M_S is no closed manifold (paper mode).
    "warn": closed but skipping samples, an open surface (robust), or uncertain features; or a file's
    mesh that cannot judge M_S, or that M_S matches only with holes the sample cannot show closed
    (:func:`truth_notes`: said after the verdict).

    A closed manifold through every sample is "ok" only when the sample
    supports every handle, hole and component of it (``rec.uncertain_features``).
    A robust result that is a surface with boundary through every sample (the
    openings of an open scan kept open) is "warn", not "bad": it may be right,
    but it is not the closed manifold the paper's guarantees are about.  In
    paper mode an open result stays "bad".
    """
    level, text, notes = verdict_parts(rec, truth)
    return level, "; ".join([text, *notes])


def verdict_parts(rec: Reconstruction, truth=None) -> tuple[str, str, list[str]]:
    """:func:`verdict` as (level, the sentence on M_S, :func:`truth_notes`), for who lays them out apart."""
    level, text = _verdict(rec, truth)
    notes = truth_notes(rec, truth)
    # a mesh that cannot judge, or that M_S matches only up to holes the sample cannot show, leaves the
    # result unconfirmed: never "sure" beside a known truth it does not match
    return ("warn" if notes and level == "ok" else level), text, notes


def _verdict(rec: Reconstruction, truth=None) -> tuple[str, str]:
    """:func:`verdict` without the notes on a mesh that cannot judge (:func:`truth_notes`)."""
    t = rec.topology
    unc = uncertain_summary(uncertain_features(rec))
    problems = truth_problems(rec, truth)
    if problems:
        skips = [f"{t.unused_samples} unused"] if t.closed_manifold and t.unused_samples else []
        return "bad", "M_S is WRONG: " + ", ".join(problems + skips) + (f" ({unc})" if unc else "")
    if t.closed_manifold and not t.unused_samples and unc:
        return (
            "warn",
            f"M_S is a closed manifold through every sample, but the sample does not decide everything ({unc})",
        )
    if t.closed_manifold and not t.unused_samples:
        return "ok", "M_S is a closed manifold through every sample"
    if t.closed_manifold:
        return "warn", f"M_S is closed but skips {t.unused_samples} samples" + (f" ({unc})" if unc else "")
    if kept_open(rec):
        # the robust extension keeps real openings open (an open scan): a surface with boundary through
        # every sample is a possible right answer, not a failure -- but not the paper's closed manifold
        what = f"a{'n' if rec.d == 1 else ''} {open_shape(rec.d)}"
        hint = ": an open scan?" if rec.d <= 2 else ""  # a scan is a curve or a surface
        return "warn", f"M_S is {what} through every sample ({boundary_words(rec)}{hint}" + (
            f"; {unc})" if unc else ")"
        )
    why = f"extraction stopped: {rec.extraction.stopped}" + (f"; {unc}" if unc else "")
    return "bad", f"M_S is NOT a closed manifold ({why})"


#: The word for each :func:`verdict` level that the command line, the JSON report and the batch summary print.
VERDICT_WORDS = {"ok": "sure", "warn": "uncertain"}


def verdict_word(rec: Reconstruction, truth=None) -> tuple[str, str]:
    """:func:`verdict` in one word and its sentence, as the command line and the report give it.

    "sure" (the window's green): a closed manifold through every sample whose every handle, hole and
    component the sample supports; "uncertain" (amber): a result that may be right, whose doubts the report
    lists; "wrong" (red): contradicted by a known truth (the input mesh's own faces); "failed" (red): no
    closed manifold where one was asked for (the paper mode, or the robust extension stuck).  The features
    an uncertain result names are the ones the sample leaves undecided; where it is much coarser than the
    object (handles under its resolution), the truth may differ by more than they say.
    """
    level, text = verdict(rec, truth)
    if level == "bad":
        return ("wrong" if truth_problems(rec, truth) else "failed"), text
    return VERDICT_WORDS[level], text


def topology_rows(rec: Reconstruction, expected=None, mesh=None) -> list[tuple[str, str, str]]:
    """(quantity, found, expected) rows of the topology table.

    ``expected`` is a built-in's manifold; else ``mesh``, the file's own mesh's
    :class:`~crustview.core.result.TopologyReport`, fills the column.
    """
    t = rec.topology
    exp = expected
    if exp is None and mesh is not None:
        return _mesh_rows(rec, mesh)
    rows = [
        ("shape", name_of(t, rec.d), shape_name(exp.d, exp.betti, exp.orientable) if exp else ""),
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
    ]
    return rows


def _mesh_rows(rec: Reconstruction, mesh) -> list[tuple[str, str, str]]:
    """The topology table against the file's own mesh (its faces: what the scan's maker saw)."""
    t = rec.topology

    def yes(v: bool | None) -> str:
        return {True: "yes", False: "no", None: "-"}[v]

    return [
        ("shape", name_of(t, rec.d), name_of(mesh, rec.d)),
        ("closed manifold", yes(t.closed_manifold), yes(mesh.closed_manifold)),
        ("simplices", str(t.n_simplices), ""),  # another triangulation of the same surface may have more or fewer
        ("Betti numbers (Z/2)", ", ".join(map(str, t.betti)), ", ".join(map(str, mesh.betti))),
        ("Euler characteristic", str(t.euler), str(mesh.euler)),
        ("orientable", yes(t.orientable), yes(mesh.orientable)),
        ("components", str(t.components), str(mesh.components)),
        ("boundary faces", str(t.boundary_faces), str(mesh.boundary_faces)),
        ("non-manifold faces", str(t.nonmanifold_faces), str(mesh.nonmanifold_faces)),
        ("singular vertices", str(t.singular_vertices), str(mesh.singular_vertices)),
        ("samples not used", str(t.unused_samples), "0"),
    ]
