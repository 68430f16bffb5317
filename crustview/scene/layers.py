"""Layer specs: what each layer shows and its style fields (evented)."""

from __future__ import annotations

from dataclasses import dataclass, field

from psygnal import evented

from .coloring import COORDINATE_COLORINGS
from .fileattrs import FILE_COLORINGS

#: Colourings the points layer offers.
POINT_COLORINGS = (
    (
        "none",
        "epsilon",
        "normal error",
        "pole distance",
        "local spacing",
        "true epsilon",
        "Thm 2 error / bound",
    )
    + COORDINATE_COLORINGS
    + FILE_COLORINGS
)
#: Colourings of the M_S layer: per simplex (the distance to M) or per vertex (coordinates).
MANIFOLD_COLORINGS = ("none", "distance to M") + COORDINATE_COLORINGS
#: Colourings of the removed simplices: by the step or the rule that removed each.
REMOVED_COLORINGS = ("step", "rule", "none")
#: Which poles to show.
POLE_MODES = ("selected", "all")

#: Colours of the current-step highlight: tau, kept pair, removed simplices.
STEP_COLORS = {"tau": "#ffb000", "kept": "#2ca02c", "removed": "#d62728", "added": "#1f5fd6"}
#: Colour of the highlighted prune cascade (every simplex its steps removed).
CASCADE_COLOR = "#00a0a0"
#: Colour of the holes of T_S.
HOLES_COLOR = "#d4006a"
#: Colour of the slice of M_S.
SLICE_COLOR = "#0b6e4f"
#: Colours of the comparison layer: simplices in both complexes, only in A (the shown M_S), only in B.
COMPARE_COLORS = {"both": "#9aa7b0", "A": "#e66101", "B": "#3b6fd6"}
#: Colour of the uncertain features (handles, holes, components the sample does not support).
UNCERTAIN_COLOR = "#ff6a00"
#: Colour of the one-sided loop of a non-orientable surface.
ORIENTATION_COLOR = "#7b2cbf"
#: Colour of the selection highlight.
SELECTION_COLOR = "#ff00ff"


@evented
@dataclass
class Layer:
    """One named layer of the scene and its style.

    Attributes
    ----------
    name : str
        Unique key (``"points"``, ``"manifold"`` ...).
    title : str
        Label in the layer panel.
    visible : bool
    color : str
        Hex colour (ignored while a scalar colouring is active).
    opacity : float
        0..1.
    size : float
        Point size / line width in pixels, or glyph scale for normal planes.
    colorby : str
        Active scalar colouring (``"none"`` for a solid colour).
    colorings : tuple of str
        Colourings this layer offers (empty: solid colour only).
    mode : str
        Layer-specific mode (poles: ``"selected"`` or ``"all"``).
    shrink : float
        Shrink factor of simplices towards their centroid (d >= 3 only).
    count : int
        Number of elements the layer draws at the current state.
    total : int
        Elements the layer would draw whole, when it draws a subset
        (:mod:`crustview.scene.subset`); 0 when it draws everything.
    note : str
        Why and how the layer is thinned ('' when it is not).
    stale : bool
        The layer is hidden and skipped updates since: ``count`` is not current
        (the panel shows a dash until it is shown again).
    tooltip : str
    """

    name: str
    title: str
    visible: bool = True
    color: str = "#808080"
    opacity: float = 1.0
    size: float = 3.0
    colorby: str = "none"
    colorings: tuple[str, ...] = ()
    mode: str = ""
    shrink: float = 1.0
    count: int = 0
    total: int = 0
    note: str = ""
    tooltip: str = ""
    stale: bool = False
    extra: dict = field(default_factory=dict)


def default_layers(d: int = 2, k: int = 3, n: int = 0) -> dict[str, Layer]:
    """The layers of a reconstruction of a d-manifold in R^k with n samples."""
    simplex = {1: "edges", 2: "triangles"}.get(d, f"{d}-simplices (boundary triangles)")
    layers = [
        Layer(
            "points",
            "Samples",
            True,
            "#1b2a49",
            1.0,
            7.0 if n < 3000 else 3.0,
            colorings=POINT_COLORINGS,
            tooltip="The sample points S (unique after merging duplicates).",
        ),
        Layer(
            "poles",
            "Poles",
            True,
            "#8e44ad",
            1.0,
            9.0,
            mode="selected",
            tooltip="The k-d Voronoi vertices Algorithm 1 chose for each sample, joined to their "
            "sample; 'selected' shows only the selected sample's. A sample on the convex hull has an "
            "unbounded cell: its first pole is a vertex at infinity, drawn lighter as a ray to the "
            "edge of the box.",
        ),
        Layer(
            "voronoi",
            "Voronoi cells",
            True,
            "#e67e22",
            0.25,
            2.0,
            tooltip="In R^2 every sample's cell; in R^3 and up the selected sample's "
            "cell, clipped to a box around the data (a hull sample's unbounded cell is cut off "
            "by the far bounding points, then by the box).",
        ),
        Layer(
            "normals",
            "Normal planes",
            n <= 3000,
            "#0e9aa7",
            0.7,
            1.0,
            tooltip="Estimated normal plane AN_s of each sample: a segment (k-d = 1), "
            "a disc (k-d = 2) or k-d short axes, scaled to the local spacing (size = scale).",
        ),
        Layer(
            "candidates",
            "Candidates T_S",
            False,
            "#9e9e9e",
            0.6,
            2.0,
            colorby="angle",
            colorings=("angle", "none"),
            tooltip="Candidate d-simplices admitted by the run panel's test and angle θ, coloured by "
            "the test's deciding angle (degrees): cocone = the dual cell meets the tangent cocone of "
            "some vertex; cocone-all = of every vertex; literal = the paper's orientation-only angle.",
        ),
        Layer(
            "manifold",
            "M_S at this step",
            True,
            "#e9b872",
            1.0,
            3.0,
            shrink=0.8 if d >= 3 else 1.0,
            colorings=MANIFOLD_COLORINGS,
            tooltip=f"The complex after the current number of extraction steps, drawn as {simplex}.",
        ),
        Layer(
            "removed",
            "Removed so far",
            False,
            "#c0392b",
            0.3,
            2.0,
            shrink=0.8 if d >= 3 else 1.0,
            colorby="step",
            colorings=REMOVED_COLORINGS,
            tooltip="Simplices removed by the steps up to the current one, coloured by the step that "
            "removed each (early dark, late bright) or by its rule.",
        ),
        Layer(
            "step",
            "Current step",
            True,
            STEP_COLORS["tau"],
            1.0,
            6.0,
            tooltip="The step just applied: the face tau (amber), the kept pair (green), "
            "the simplices it removed (red) and those it added (blue, robust extraction only); "
            "drawn over the other layers, so it shows even inside M_S.",
        ),
        Layer(
            "holes",
            "Holes of T_S",
            False,
            HOLES_COLOR,
            1.0,
            5.0,
            tooltip="The (d-1)-faces of the candidate complex T_S that lie in a single simplex before "
            "extraction starts: the paper's pruning starts its cascades there. Drawn by hole: its rim "
            "(lines for surfaces, dots for curves, triangles for 3-manifolds), a surface hole's patch "
            "faintly shaded, and the five largest labelled with their rim size and span in sample "
            "spacings; the legend gives how many holes and the largest.",
        ),
        Layer(
            "cascade",
            "Highlighted cascade",
            True,
            CASCADE_COLOR,
            0.85,
            6.0,
            tooltip="The prune cascade chosen in the Information panel: every simplex removed by the "
            "steps that descend from its origin, drawn over the other layers, with the origin face thick.",
        ),
        Layer(
            "uncertain",
            "Uncertain features",
            False,
            UNCERTAIN_COLOR,
            1.0,
            5.0,
            tooltip="Handles, holes and components of the final M_S that the sample cannot tell from a gap "
            "(rec.uncertain_features): a handle's short loop and a hole's rim as lines, a component's "
            "closest approach to another one as a dot. On when there are any; the Information panel lists "
            "them (a click frames one).",
        ),
        Layer(
            "orientation",
            "One-sided loop",
            False,
            ORIENTATION_COLOR,
            0.55,
            5.0,
            tooltip="Non-orientable surfaces (Klein bottle, projective plane): a loop of triangles of the final "
            "M_S along which the normal comes back flipped, drawn as a line through them over a band of "
            "its triangles (a Möbius band; this layer's opacity). On when M_S is not orientable.",
        ),
        Layer(
            "selection",
            "Selection",
            True,
            "#ff00ff",
            1.0,
            6.0,
            tooltip="The selected sample, simplex or (d-1)-face with its incident simplices.",
        ),
        Layer(
            "slice",
            "Slice of M_S",
            False,
            "#0b6e4f",
            1.0,
            4.0,
            tooltip="The cross-section of M_S by a hyperplane orthogonal to the direction the view hides "
            "(R^4 and up; the view's depth axis in R^3): closed curves for a surface, 2-spheres for S^3. "
            "Move it and cut M_S to one side in the Projection panel.",
        ),
        Layer(
            "compare",
            "Comparison A / B",
            True,
            COMPARE_COLORS["both"],
            0.35,
            3.0,
            tooltip="The shown M_S (A) compared with a saved result, a mesh's faces or another run (B), set up "
            "in the Information panel: simplices in both (grey, this layer's opacity), only in A (orange) "
            "and only in B (blue).",
        ),
        Layer(
            "truth",
            "Ground truth",
            False,
            "#5d6d7e",
            0.25,
            2.0,
            tooltip="A dense sample of the true manifold (built-in samples), or the faces of "
            "the mesh file whose vertices were reconstructed.",
        ),
    ]
    return {layer.name: layer for layer in layers}
