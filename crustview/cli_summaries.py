"""The printed summary of a reconstruction: ``crustview reconstruct``'s lines after a run.

Split from :mod:`crustview.cli_reconstruct` (which still exports them, as :mod:`crustview.__main__` does):
what the result is (:func:`result_summary`), what the extraction did (:func:`extraction_summary`), how it
compares with a mesh's faces (:func:`comparison_summary`) and the closing verdict (:func:`verdict_line`).
"""

from __future__ import annotations

import math
from pathlib import Path


def verdict_line(level: str, sentence: str, features: bool = False) -> str:
    """The last printed line: how sure the result is, as the window's coloured verdict says it.

    ``features``: the result has uncertain features (the report lists them, with where each is).
    """
    more = (
        "; the report (--report) lists where each uncertain feature is (where the sample is much coarser than "
        "the object, the truth may differ by more than they say)"
        if level == "uncertain" and features
        else ""
    )
    return f"Verdict: {level.upper()} -- {sentence}{more}."


def _empty_side(c) -> str:
    """Why a comparison has no Hausdorff distance: which of the two complexes is empty."""
    empty = [what for what, t in (("M_S", c.result_topology), ("the mesh", c.mesh_topology)) if t.n_simplices == 0]
    return " and ".join(empty) + (" is empty" if len(empty) == 1 else " are empty") if empty else "not measured"


def result_summary(rec, seconds: float, output: Path) -> str:
    """The first summary line: the shape, its topology, the time and the output."""
    from crustview.core.analysis.features import summary_suffix

    top = rec.topology
    word = {1: "curve", 2: "surface"}.get(rec.d, f"{rec.d}-manifold")
    merged = len(rec.input_points) - rec.n
    dup = f" ({merged} duplicates merged)" if merged else ""
    closed = "a closed manifold" if top.closed_manifold else "NOT a closed manifold"
    if top.closed_manifold:  # named, as the window's title names it: "a closed manifold (genus-4 surface)"
        from crustview.scene.shapes import name_of

        b = tuple(int(v) for v in top.betti)
        total = f", total genus {b[1] // 2}" if rec.d == 2 and b[0] > 1 and top.orientable else ""
        closed += f" ({name_of(top, rec.d)}{total})"
    parts = [
        f"Reconstructed a {word} in R^{rec.k} from {rec.n} points{dup}: {top.n_simplices} {rec.d}-simplices, {closed}",
        f"Betti numbers (Z/2) {tuple(int(b) for b in top.betti)}, Euler characteristic {top.euler}",
    ]
    if top.orientable is not None:
        parts.append("orientable" if top.orientable else "non-orientable")
    if not top.closed_manifold:
        parts.append(
            f"{top.boundary_faces} boundary and {top.nonmanifold_faces} non-manifold faces, "
            f"{top.unused_samples} unused samples"
        )
    text = "; ".join(parts) + f"; {seconds:.2f} s; wrote {output}."
    notes = set(rec.extraction.notes)  # said on the extraction line
    from crustview.core.uncertainty import UNDECIDED  # said by the summary's "(uncertain: ...)" suffix

    messages = [m for m in top.messages if m not in notes and not m.startswith(UNDECIDED)]
    if messages:
        text += " Note: " + "; ".join(str(m).rstrip(".") for m in messages) + "."
    suffix = summary_suffix(rec.features)
    return text + (f" {suffix}" if suffix else "")


def extraction_summary(rec) -> str:
    """One sentence: which extraction ran, why, and how many steps of each rule.

    Parameters
    ----------
    rec : Reconstruction

    Returns
    -------
    str
        E.g. ``"extraction: robust (the paper's Algorithm 3 was abandoned after
        127 steps, ...); 2160 steps: seed 1, grow 2068, ..."`` or
        ``"extraction: paper's Algorithm 3; 12 steps: prune-sharp 0,
        resolve-nonmanifold 12."``.  A robust run lists only the rules it
        used; a paper run lists both of the paper's rules.
    """
    ext = rec.extraction
    if rec.mode == "paper":
        head = "extraction: paper's Algorithm 3"
        if not rec.prune_boundary:
            head += " with boundary faces kept (--keep-boundary)"
    else:
        why = "; ".join(str(n).rstrip(".") for n in ext.notes)
        head = "extraction: robust" + (f" ({why})" if why else "")
    counts = ext.counts_by_rule()
    shown = [f"{rule} {c['steps']}" for rule, c in counts.items() if c["steps"] or rec.mode == "paper"]
    steps = f"{ext.n_steps} step" + ("" if ext.n_steps == 1 else "s")
    return f"{head}; {steps}" + (": " + ", ".join(shown) if shown else "") + "."


def comparison_summary(c, name: str) -> str:
    """One sentence: M_S against the mesh's faces."""
    from crustview.core.analysis.compare import MeshComparison

    def top(t) -> str:
        g = MeshComparison.genus(t)
        shape = f"closed, genus {g}" if g is not None else ("closed" if t.closed_manifold else "not closed")
        return f"{shape}, Betti {tuple(int(b) for b in t.betti)}"

    h = c.hausdorff
    collapsed = f" ({c.collapsed_faces} collapsed by duplicate merging)" if c.collapsed_faces else ""
    if c.extra == 0 and c.recovered == c.mesh_faces and c.mesh_faces:
        distance = "Hausdorff distance 0 (the same faces)"
    elif math.isfinite(h.distance):
        distance = (
            f"Hausdorff distance {h.words()} (sampled on grids over both complexes, whose covering radius "
            f"{h.error_bound:.2g} bounds the error)"
        )
    else:
        distance = f"no Hausdorff distance ({_empty_side(c)})"
    return (
        f"Against the faces of {name}: {c.recovered} of {c.mesh_faces} mesh faces recovered "
        f"({100 * c.recovered_share:.1f}%){collapsed}, {c.extra} extra; mesh {top(c.mesh_topology)}; "
        f"M_S {top(c.result_topology)}; {distance}."
    )
