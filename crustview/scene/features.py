"""The features of M_S the sample does not support, in words and as lines to draw (Qt-free).

``rec.features`` (:mod:`crustview.core.analysis.features`) names every
handle, hole and component of the final M_S; those with ``uncertain`` set are
below what the sample can resolve.  The viewer names them in the verdict,
lists them (a click frames one) and draws them in the *Uncertain features*
layer.
"""

from __future__ import annotations

import numpy as np

from . import geometry as geo

#: The kinds of feature, in the order the summary counts them.
KINDS = ("handle", "hole", "component")


def uncertain_features(rec) -> list:
    """The features of ``rec`` its sample does not support (empty for results without features)."""
    if rec is None:
        return []
    return [f for f in getattr(rec, "features", None) or () if f.uncertain]


def _count(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def uncertain_summary(feats: list) -> str:
    """E.g. "uncertain: 2 handles, 0 holes, 1 component" ('' when there is none)."""
    if not feats:
        return ""
    return "uncertain: " + ", ".join(_count(sum(f.kind == k for f in feats), k) for k in KINDS)


def feature_words(f, i: int | None = None, quality: object | None = None) -> str:
    """One list line: "handle 1: loop of 12 samples, 4.1 sampling radii long (…)".

    With the samples' :class:`~crustview.core.analysis.quality.SamplingQuality`, it ends with the estimated
    epsilon there: "[estimated ε 0.57 there (coarsest 2.6)]".
    """
    head = f.kind if i is None else f"{f.kind} {i + 1}"
    eps = epsilon_words(quality, f)
    return f"{head}: {f.reason}" + (f" [{eps}]" if eps else "")


def epsilon_words(quality: object | None, f) -> str:
    """The words 'estimated ε 0.12 there (coarsest 0.3)' over a feature's samples ('' without a quality)."""
    if quality is None:
        return ""
    from ..core.analysis.quality import feature_epsilon

    eps = feature_epsilon(quality.epsilon, f.vertices)
    if eps["epsilon"] is None:
        return ""
    return f"estimated ε {eps['epsilon']:.2g} there (coarsest {eps['epsilon_max']:.2g})"


def feature_lines(rec, feats: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What the layer draws: ``(points, lines, markers)`` in R^k.

    ``points`` (m, k) are the drawn vertices, ``lines`` (e, 2) index them:
    a handle's loop (closed), a hole's rim (the boundary edges of M_S on its
    samples; for a 3-manifold the edges of its boundary faces; for a cap
    ``open-cap`` kept closed, which has none, the outline of the faces of M_S
    on its samples) and a component's closest pair.
    ``markers`` (c,) index the points drawn as big dots: each component's
    closest approach, each feature's location when it has no vertices (or,
    for a disputed feature, no loop or rim: the region two results differ in).
    """
    k = rec.points.shape[1]
    pts: list[np.ndarray] = []
    lines: list[np.ndarray] = []
    markers: list[int] = []
    base = 0
    rim = None
    for f in feats:
        vs = np.asarray(f.vertices, dtype=np.int64)
        loc = np.asarray(f.location, dtype=float).reshape(1, k)
        if f.kind == "hole" and rec.d == 1 and len(vs) == 2:
            # a curve's gap: the segment between the two ends that face each other
            pts.append(rec.points[vs])
            lines.append(np.array([[base, base + 1]]))
            base += 2
            continue
        if f.kind == "hole" and len(vs) >= 2:
            if rim is None:
                faces, inc = geo.facets(np.asarray(rec.manifold, dtype=np.int64).reshape(-1, rec.d + 1))
                rim = faces[np.bincount(inc.ravel(), minlength=len(faces)) == 1]
            mine = rim[np.isin(rim, vs).all(axis=1)] if rim.shape[1] >= 2 else np.zeros((0, 2), np.int64)
            if rim.shape[1] > 2:  # a 3-manifold's hole: the edges of its boundary faces (a sphere's wireframe)
                cols = [mine[:, [a, b]] for a in range(rim.shape[1]) for b in range(a + 1, rim.shape[1])]
                mine = np.unique(np.sort(np.vstack(cols), axis=1), axis=0) if len(mine) else np.zeros((0, 2), np.int64)
            if not len(mine) and getattr(f, "removed", False) and rim.shape[1] == 2:
                mine = _cap_outline(np.asarray(rec.manifold, dtype=np.int64), vs)
            if len(mine):
                order, local = np.unique(mine, return_inverse=True)
                pts.append(rec.points[order])
                lines.append(local.reshape(-1, 2) + base)
                base += len(order)
                continue
        if f.kind == "handle" and len(vs) >= 2 and not getattr(f, "disputed", False):
            # (a disputed handle's vertices are the region where two results differ, no loop: its location)
            pts.append(rec.points[vs])
            m = len(vs)
            lines.append(np.stack([np.arange(m), np.roll(np.arange(m), -1)], axis=1) + base)
            base += m
            continue
        if f.kind == "component" and len(vs) == 2:
            pts.append(np.vstack([rec.points[vs], loc]))
            lines.append(np.array([[base, base + 1]]))
            markers.append(base + 2)
            base += 3
            continue
        pts.append(loc)  # a feature with nothing to trace: its location
        markers.append(base)
        base += 1
    if not pts:
        return np.zeros((0, k)), np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    return (
        np.vstack(pts),
        np.vstack(lines) if lines else np.zeros((0, 2), np.int64),
        np.asarray(markers, dtype=np.int64),
    )


def _cap_outline(triangles: np.ndarray, vs: np.ndarray) -> np.ndarray:
    """The edges in one triangle among the triangles with every vertex in ``vs`` (a kept cap's outline)."""
    cap = triangles[np.isin(triangles, vs).all(axis=1)]
    if not len(cap):
        return np.zeros((0, 2), np.int64)
    faces, inc = geo.facets(cap)  # as the rims are found above
    return faces[np.bincount(inc.ravel(), minlength=len(faces)) == 1]


def feature_samples(rec, f) -> np.ndarray:
    """Sample indices to frame for feature ``f`` (its vertices, or the samples nearest its location)."""
    vs = np.asarray(f.vertices, dtype=np.int64)
    if len(vs):
        return vs
    dist = np.linalg.norm(rec.points - np.asarray(f.location, dtype=float), axis=1)
    return np.argsort(dist)[: min(8, len(dist))]
