"""The legend's entries, in the order the legend lists them (split from :mod:`.view`).

What each visible solid-colour layer, the step highlight, a comparison and a cascade show.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..scene.layers import CASCADE_COLOR, COMPARE_COLORS, STEP_COLORS
from .base import NAN_COLOR
from .complexes import RULE_COLORS
from .samples import lighter

if TYPE_CHECKING:  # the view imports this module
    from .view import SceneView

#: Why a built-in's colouring by its true manifold draws nothing yet (it was "needs the true manifold of a
#: built-in sample" on a built-in, and M_S's "distance to M" said nothing at all).
THEOREMS_FIRST = "press Check Theorems 2 and 10 in the Information panel first"
#: The legend's swatch for a complex coloured by a scalar (its colours are those of the bar named beside it).
COLORED_SWATCH = "#9aa7b8"


def legend_entries(view: SceneView) -> list[tuple[str, str]]:
    """(label, colour) of the visible solid-colour layers and the step highlight."""
    out = []
    layers = view.model.layers
    for name in (
        "points",
        "manifold",
        "slice",
        "removed",
        "holes",
        "candidates",
        "normals",
        "poles",
        "voronoi",
        "uncertain",
        "orientation",
        "truth",
    ):
        layer = layers[name]
        a = view.adapters[name]
        if not layer.visible or a.shown_cells() == 0:
            continue
        if name == "points" and getattr(a, "scalar_title", None) and a.n_missing:
            out.append((f"{a.scalar_title}: none (pole at infinity)", NAN_COLOR))
        rgb = getattr(a, "direct_rgb", False)  # the file's own colours: no bar, nothing missing
        if name == "points" and layer.colorby != "none" and not getattr(a, "scalar_title", None) and not rgb:
            why = (
                "needs points in R^4 or more"
                if layer.colorby == "hidden depth"
                else "no such coordinate"
                if layer.colorby.startswith("x")
                else THEOREMS_FIRST
                if view.model.builtin is not None and view.model.theorems is None
                else "needs the true manifold of a built-in sample"
            )
            out.append((f"{layer.colorby}: not available here ({why})", NAN_COLOR))
        if name == "manifold" and layer.colorby == "distance to M" and view.model.theorems is None:
            out.append((f"distance to M: not available yet ({THEOREMS_FIRST})", NAN_COLOR))
        if getattr(a, "scalar_title", None):
            if name != "points":  # the samples' bar names them; a complex's layer is named here
                what = a.scalar_title.partition(" (")[0]
                out.append((f"{layer.title}: coloured by {what} (bar)", COLORED_SWATCH))
            continue
        if name == "removed" and layer.colorby == "rule":
            codes = view.model.rule_codes()
            used = {codes.names[c] for c in np.unique(codes.codes[: view.model.player.position])}
            out.extend((f"removed by {r}", c) for r, c in RULE_COLORS.items() if r in used)
            continue
        if name == "poles" and a.n_infinite:
            if a.parts[0].n_cells:
                out.append((layer.title, layer.color))
            out.append(("Pole at infinity (hull sample)", lighter(layer.color)))
            continue
        if name in ("truth", "holes"):
            out.append((a.legend_label(), layer.color))
            continue
        if name == "orientation":
            out.append((f"one-sided loop ({layer.count} triangles): the normal flips once around it", layer.color))
            continue
        if name == "uncertain":
            from ..scene.features import uncertain_features, uncertain_summary

            final = "" if view.model.player.position >= view.model.player.n_steps else " (of the final M_S)"
            out.append((uncertain_summary(uncertain_features(view.model.rec)) + final, layer.color))
            continue
        out.append((layer.title, layer.color))
    step = view.model.player.shown_step
    if layers["step"].visible and step is not None:
        out.append(("tau (face of the step)", STEP_COLORS["tau"]))
        if step.kept:
            out.append(("kept pair", STEP_COLORS["kept"]))
        if step.removed or not step.added:
            out.append(("removed now", STEP_COLORS["removed"]))
        if step.added:
            out.append(("added now (robust extension)", STEP_COLORS["added"]))
    cmp = view.model.comparison
    if layers["compare"].visible and cmp is not None and cmp.diff.matched:
        out.append(("in both A and B", layers["compare"].color))
        out.append((f"only in A: {len(cmp.diff.only_a):,}", COMPARE_COLORS["A"]))
        out.append((f"only in B: {len(cmp.diff.only_b):,}", COMPARE_COLORS["B"]))
    c = view.model.cascade
    if layers["cascade"].visible and c is not None:
        out.append((f"cascade from step {c.origin + 1}: {c.removed:,} removed", CASCADE_COLOR))
    return out
