"""Caps over possible openings in a closed result of the paper's loop: the measure ``open-cap`` uses.

Why
---
The paper's Algorithm 3 reconstructs closed manifolds: on an open scan its M_S, when it closes at all,
spans every opening with a cap of large faces (the owl's open base: a closed surface of genus 0, judged
wrong, with no uncertain feature in the paper mode's table).  The robust extension measures such caps
(``open-cap``, :mod:`.cells`): a patch of at least OPEN_MIN_FACES faces each larger than SIZE_MAX local
spacings, whose largest face is many times the faces around it and more than CAP_TYPICAL times the faces of
M_S in general, spans a part of space where the sample shows no surface.

The rule
--------
A closed M_S of the paper's own loop, in either mode (the robust mode returns the paper's result
unchanged whenever it is a closed manifold through every sample: the unit sphere's sample cut at
z = 0.5 came out that way, green, an open object called closed for sure), gets one uncertain ``hole``
feature per cap over :data:`~.cells.CAP_SURE` = 6 times the faces around it (open-cap's bound for a cap
surely over an opening; and over CAP_TYPICAL times the faces of M_S in general), marked ``removed`` as a
cap ``open-cap`` keeps closed is (a possible opening that is not a hole of M_S), at the cap's samples.
Caps between CAP_RATIO and CAP_SURE are what an uneven sample makes over a closed surface: the i.i.d.
torus of 20,000 and 100,000 samples has caps of 3.08-3.43 (of 15 and 75 patches of big faces), the cut
sphere's measures 10.9, the owl's open base 58.2.  No new constant: the bounds are open-cap's.
"""

from __future__ import annotations

import numpy as np

from ..analysis.features import Feature
from ..analysis.radii import enclosing_radii
from ..util.nearest import nearest_distances
from .cap_holes import cap_hole
from .cells import CAP_SURE, CAP_TYPICAL, cap_patches, cap_ratios, typical_ratios
from .grow import SIZE_MAX, size_ratio


def paper_caps(points: np.ndarray, triangles: np.ndarray) -> list[Feature]:
    """Uncertain, removed ``hole`` features for the caps of a closed surface M_S (see the module docstring).

    Parameters
    ----------
    points : ndarray of shape (n, 3)
    triangles : ndarray of shape (t, 3)
        A closed M_S in R^3.
    """
    faces = np.asarray(triangles, dtype=np.int64)
    if len(faces) == 0:
        return []
    patches = cap_patches(faces, size_ratio(points, faces) > SIZE_MAX, len(points))
    if not patches:
        return []
    ratios = cap_ratios(faces, patches, points)  # radii near the patches only
    if max(ratios) <= CAP_SURE:
        return []
    radii = enclosing_radii(points, faces)
    typical = typical_ratios(faces, patches, radii)
    nn = nearest_distances(points)
    out = []
    for p, q, t in zip(patches, ratios, typical, strict=True):
        if q <= CAP_SURE or t <= CAP_TYPICAL:
            continue
        vs = np.unique(faces[p])
        out.append(
            cap_hole(
                points,
                vs,
                nn,
                lambda size, p=p, vs=vs, q=q: (
                    f"a possible opening the paper's loop closed: a cap of {len(p)} "
                    f"faces on {len(vs)} samples, {size:.3g} spacings across, its faces {q:.2g} times the size of "
                    f"those around it (more than the {CAP_SURE:g} above which open-cap takes a cap for one over an "
                    "opening): the sample shows no surface there, and Algorithm 3 closes every opening"
                ),
            )
        )
    return out
