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
A cap between :data:`~.cells.CAP_RATIO` and CAP_SURE is named too where the sample's own spacing around it does
not explain it (:func:`ring_spread`).  CAP_RATIO is the Lipschitz bound on how much the sampling radius changes
over one radius; what a sample shows is that radius times its own irregularity (how much one sample's
nearest-neighbour distance exceeds the mean of its neighbours' on M_S, :func:`spacing_irregularity`).  So a cap
is named when it is over CAP_RATIO times the largest irregularity among the samples of its ring (the faces
sharing a sample with it: those :func:`~.cells.cap_ratios` measures it against), which is under 2 only where
the sample is even around the cap (CAP_RATIO times 2 is CAP_SURE).  Measured on the ring, not the whole sample:
one stray sample or a few near-duplicates elsewhere do not switch the band off.  An i.i.d. sample is irregular
everywhere: the i.i.d. torus of 20,000 and 100,000 samples has caps of 3.08-3.43 (of 15 and 75 patches of big
faces), and their rings are irregular enough that nothing is named, as before.  An even sample is regular: the
even sphere of 1,500 samples with the 3 % nearest one sample taken away (a scanner's hole) has a cap of 5.05
on a ring of irregularity 1.4, and the bumpy sphere with 5 % of its vertices cut away
(``benchmarks/bench_reshaped.py --opened 0.05 --seed 43``) a cap of 5.91.  Before, both came out closed with
nothing named.  The cut sphere's cap measures 10.9, the owl's open base 58.2.  No new constant: the bounds are
open-cap's, and the irregularity is the sample's own.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.features import Feature
from ..analysis.radii import enclosing_radii
from ..util.nearest import nearest_distances
from .cap_holes import cap_hole
from .cells import CAP_RATIO, CAP_SURE, CAP_TYPICAL, cap_patches, cap_ratios, typical_ratios
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
    if max(ratios) <= CAP_RATIO:
        return []  # no cap to name: no distances to look up
    nn = nearest_distances(points)
    # the sample's own irregularity around each cap in the band it decides (a linear pass, only if there is one)
    band = [CAP_RATIO < q <= CAP_SURE for q in ratios]
    irregular = spacing_irregularity(faces, nn) if any(band) else None
    spreads = [ring_spread(faces, p, irregular) if b else None for p, b in zip(patches, band, strict=True)]
    named = [q > CAP_SURE or (u is not None and q > CAP_RATIO * u) for q, u in zip(ratios, spreads, strict=True)]
    if not any(named):
        return []  # before the radii of every face (the 300,000-sample i.i.d. torus: 0.35 s)
    radii = enclosing_radii(points, faces)
    typical = typical_ratios(faces, patches, radii)
    out = []
    for p, q, t, name, u in zip(patches, ratios, typical, named, spreads, strict=True):
        if not name or t <= CAP_TYPICAL:
            continue
        vs = np.unique(faces[p])
        out.append(cap_hole(points, vs, nn, _why(len(p), len(vs), q, u)))
    return out


def _why(n_faces: int, n_samples: int, q: float, spread: float | None):  # noqa: ANN202
    """The reason of a cap's feature, given its size in spacings."""

    def why(size: float) -> str:
        head = (
            f"a possible opening the paper's loop closed: a cap of {n_faces} faces on {n_samples} samples, "
            f"{size:.3g} spacings across, its faces {q:.2g} times the size of those around it"
        )
        if q > CAP_SURE:
            return head + (
                f" (more than the {CAP_SURE:g} above which open-cap takes a cap for one over an opening): the sample "
                "shows no surface there, and Algorithm 3 closes every opening"
            )
        assert spread is not None  # a cap in the band is named only beside the sample's irregularity
        return head + (
            f", more than {CAP_RATIO * spread:.3g} (the {CAP_RATIO:g} a surface's sampling can change by over one "
            f"radius, times {spread:.3g}, the most a sample's spacing around the cap exceeds its neighbours') and "
            f"less than the {CAP_SURE:g} above which a cap is surely over an opening: the sample does not "
            "decide, and Algorithm 3 closes every opening"
        )

    return why


def spacing_irregularity(triangles: np.ndarray, nn: np.ndarray) -> np.ndarray:
    """Per sample: its nearest-neighbour distance over the mean of its neighbours' on M_S.

    About 1 on an even sample; on an i.i.d. one it varies widely (the 20,000-sample i.i.d. torus: up to 4.8).

    Parameters
    ----------
    triangles : ndarray of shape (t, 3)
        A closed M_S: every edge is in two triangles, so counting each edge once per triangle weighs every
        neighbour the same (twice) and the mean is the neighbours' own.
    nn : ndarray of shape (n,)
        The samples' nearest-neighbour distances.

    Returns
    -------
    ndarray of shape (n,)
        NaN for a sample on no triangle, a duplicate (distance 0), or one whose neighbours' mean is not positive.
    """
    a = triangles.ravel()
    b = np.roll(triangles, -1, axis=1).ravel()  # each triangle's edges (0, 1), (1, 2), (2, 0)
    n = len(nn)
    total = np.bincount(a, nn[b], n) + np.bincount(b, nn[a], n)
    count = np.bincount(a, None, n) + np.bincount(b, None, n)
    out = np.full(n, np.nan)
    ok = (count > 0) & (nn > 0) & np.isfinite(nn) & (total > 0)
    out[ok] = nn[ok] / (total[ok] / count[ok])
    return out


def ring_spread(triangles: np.ndarray, patch: np.ndarray, irregular: np.ndarray) -> float:
    """The largest :func:`spacing_irregularity` among the samples of ``patch``'s faces and of its ring.

    The ring is the faces sharing a sample with the patch (those :func:`~.cells.cap_ratios` measures the patch
    against).  At least 1 (a perfectly even sample); where no sample of the ring has a value, infinity (nothing
    shows the sample is even there).
    """
    on = np.zeros(len(irregular), bool)
    on[triangles[patch]] = True
    ring = np.unique(triangles[on[triangles].any(axis=1)])
    values = irregular[ring]
    values = values[np.isfinite(values)]
    return max(1.0, float(values.max())) if len(values) else math.inf
