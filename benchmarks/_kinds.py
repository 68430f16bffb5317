"""Whether a wrong result's flags name the kind that is wrong: components, handles, holes (``bench_scans.py``).

``bench_scans.py`` counts a wrong result as said when it carries any uncertain feature; :func:`unnamed` asks
for one of the kind that is wrong, so that a planar rim flagged beside a sure false handle (the hand at 0.3 h,
noise draw 51) does not pass for an error the result names.  Tested on hand-made rows and triangle sets in
``tests/test_bench_judge.py``.
"""

from __future__ import annotations

import numpy as np

from crustview.core.analysis.cotree import triangle_edges
from crustview.core.analysis.topology import graph_components


def rims(tris: np.ndarray, n: int) -> tuple[int, bool]:
    """How many boundary curves a triangle set has, and whether one is pinched (a vertex with 4+ rim edges).

    The curves are the connected pieces of the edges in one triangle, as ``analysis.dispute`` counts them;
    two holes that touch at a vertex are one piece, so a pinch is said apart.
    """
    if len(tris) == 0:
        return 0, False
    edges, tri_edges = triangle_edges(np.asarray(tris))
    rim = edges[np.bincount(tri_edges.ravel(), minlength=len(edges)) == 1]
    if len(rim) == 0:
        return 0, False
    _, label = graph_components(n, rim)
    pinched = bool((np.bincount(rim.ravel(), minlength=n) > 2).any())
    return len(np.unique(label[np.unique(rim)])), pinched


def unnamed(
    truth: dict,
    true_betti: tuple,
    true_rims: tuple[int, bool],
    small_holes: int,
    betti: tuple,
    closed: bool,
    found_rims: tuple[int, bool],
    uncertain: dict,
) -> list[str]:
    """The kinds in which a wrong result differs from the truth that none of its uncertain features names.

    Kinds: ``component`` (b0 differs), ``handle`` (b1 - rims + b0 - b2, twice the genus of an orientable
    surface, differs) and ``hole`` (the number of boundary curves differs; a closed truth's result that is
    not closed says so itself).  Where either side's rims are pinched (two holes through one vertex count as
    one curve) or its handle count is odd or negative (a non-manifold truth, as the owl's and the vase's
    meshes), handles and holes cannot be told apart: they are judged as one kind, ``handle or hole``, which a
    flag of either names.  Where the true mesh has ``small_holes`` rims under a spacing (no sample shows
    them), a result with up to that many holes fewer is not wrong in its holes.  It asks whether a kind is
    named, not how much of it: one uncertain handle names a result that lost eight.  Samples left out are
    named in every report (``left_out_samples``), so they are never unnamed here.

    ``truth`` is the file's truth (``closed``, and ``components`` and ``genus`` when closed), ``true_betti``
    and ``true_rims`` the true mesh's, ``betti``, ``closed`` and ``found_rims`` the result's, ``uncertain``
    its uncertain features counted by kind.
    """
    (loops, pinched), (true_loops, true_pinched) = found_rims, true_rims
    if truth["closed"]:
        c, g = int(truth["components"]), int(truth["genus"])
        want = (c, 2 * g, 0)
    else:
        b = true_betti
        want = (b[0], b[1] - true_loops + b[0] - b[2], true_loops)
    have = (betti[0], betti[1] - loops + betti[0] - betti[2], loops)
    hole_wrong = not (want[2] - small_holes <= have[2] <= want[2])
    said = {k: uncertain.get(k, 0) > 0 for k in ("component", "handle", "hole")}
    said["hole"] |= truth["closed"] and not closed  # "NOT a closed manifold" names its holes
    out = []
    if want[0] != have[0] and not said["component"]:
        out.append("component")
    if pinched or true_pinched or any(x < 0 or x % 2 for x in (want[1], have[1])):
        if (want[1] != have[1] or hole_wrong) and not (said["handle"] or said["hole"]):
            out.append("handle or hole")
        return out
    if want[1] != have[1] and not said["handle"]:
        out.append("handle")
    if hole_wrong and not said["hole"]:
        out.append("hole")
    return out
