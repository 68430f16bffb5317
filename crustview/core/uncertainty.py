"""How sure a run's result is: every feature of M_S with its support, as the report lists them.

The features of M_S (:func:`~crustview.core.analysis.features.features`, or the robust driver's own), the
features the robust rules removed or decided (cut handles, joined parts, caps kept closed), and, for a robust
surface in R^3 that is not the paper's own result, the checks that can only add doubt: parts held by faces
standing across the normals, handles only such faces carry, one component holding two enclosures, and
``resample-check``.  Split from :mod:`crustview.core.reconstruct`, which runs the stages.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import replace

import numpy as np

from .analysis.contacts import BRIDGED, bridged_handles, hidden_parts
from .analysis.enclosures import enclosure_voids, joined_objects
from .analysis.features import LOOP_MIN, Feature, features
from .analysis.gaps import curve_gaps, straight_gaps
from .analysis.persistence import PERSISTENT_SURE, missing_loops
from .analysis.planar import planar_holes
from .analysis.radii import local_spacing
from .analysis.resample import Resampled, resample_betti, resample_check
from .prepare import DEFAULT_JOGGLE, prepare_points
from .result import Reconstruction, TopologyReport
from .robust.closed_caps import paper_caps
from .robust.unclosed import unclosed_gaps
from .steps import RULE_PRUNE, RULE_RESOLVE, Extraction
from .util.nearest import nearest_distances
from .util.parallel import start_in_background


def result_features(
    rec: Reconstruction,
    ext: Extraction,
    manifold: np.ndarray,
    topo: TopologyReport,
    scale: float,
    *,
    mode: str,
    test: str,
    theta: float,
    resample: bool,
    contacts: bool,
    cancel: object | None,
    report: Callable[[str, float], None],
    pending: Future | None = None,
) -> list[Feature]:
    """Every feature of ``manifold`` and of the rules' decisions, with whether the sample supports it.

    Parameters
    ----------
    rec : Reconstruction
        The run before Algorithm 3 (its samples, normals, Delaunay cells).
    ext : Extraction
        Algorithm 3's run (its features, removed features and step counts).
    manifold : ndarray of shape (s, d + 1)
        M_S.
    topo : TopologyReport
        Its analysis; the messages about removed and uncertain features are appended.
    scale : float
        The exact power-of-two rescaling the run used (sizes are ratios; locations are scaled back).
    mode, test, theta
        The extraction's settings (``resample-check`` reruns with them).
    resample, contacts : bool
        As in :func:`crustview.core.reconstruct.reconstruct`.
    cancel, report
        Cancellation and progress of the run.
    pending : Future, optional
        ``features`` of ``manifold`` begun by the robust driver (see
        :func:`~crustview.core.robust.driver.extract_robust`'s ``measured``); taken instead of measuring again.

    Returns
    -------
    list of Feature
    """
    counts = ext.counts_by_rule()
    # one closed component holding two regions the sample encloses (below): the samples' voids need only the
    # Delaunay cells, so where M_S has loops to measure they are found on the other core while the features
    # are (below 50,000 vertices the loop basis runs on one; feline 0.89 -> 0.57-0.69 s); without loops the
    # features take little and the two only contend (armadillo 0.56 -> 0.61 s); the same call either way
    enclosing = contacts and mode == "robust" and topo.closed_manifold and _beyond(counts)
    enclosing = enclosing and rec.subspace_dim == rec.k
    if enclosing:
        m = len(rec.delaunay_simplices)
        cells = (rec.delaunay_points / scale, rec.delaunay_simplices, rec.voronoi_vertices[:m] / scale)
        lab = getattr(ext, "labelling", None)  # its shared faces are those of the same Delaunay cells
        adjacency = None if lab is None or lab.simplices is not rec.delaunay_simplices else (lab.a, lab.b, lab.faces)
        ahead = (rec.k, rec.d) == (3, 2) and topo.betti[1] > 0
        voids = start_in_background(enclosure_voids, *cells, rec.n, adjacency) if ahead else None
    # the paper's loop closes every opening: a closed result of its own (either mode) gets its caps named,
    # measured as open-cap measures them (robust/closed_caps.py); before waiting on the features measured
    # on the other core, so that the two overlap
    caps = (
        paper_caps(rec.points / scale, manifold)
        if (rec.k, rec.d) == (3, 2) and topo.closed_manifold and not _beyond(counts)
        else []
    )
    # the robust driver began measuring the paper's own result while it analysed it (the same call)
    if ext.features is not None:
        measured = ext.features
    elif pending is not None:
        measured = pending.result()
    else:
        measured = features(rec.points / scale, manifold, rec.d, b1=topo.betti[1])
    # on the rescaled samples (sizes are ratios; locations are scaled back)
    feats = [replace(f, location=f.location * scale) for f in measured + list(ext.disputed)]
    # a handle cut in the band [LOOP_MIN, LOOP_SUPPORTED) stays uncertain: a sample coarser than
    # eps = 1/2 resolves it, so the sample did not decide it; one below LOOP_MIN is below what any
    # eps < 1 sample resolves, and its removal is what the sampling condition implies
    cut = [
        replace(
            f,
            location=f.location * scale,
            # the growing path's cuts (robust/cut_loop.py) come marked removed, sure or not already
            uncertain=f.uncertain if f.removed else f.size_spacings >= LOOP_MIN,
            removed=True,
            reason=f"removed (rule cut-handle): {f.reason}",
        )
        for f in ext.removed_features
        if f.kind == "handle"
    ]
    feats += cut
    # a separation join-parts removed is always uncertain: the gap was below what the sample resolves,
    # and two objects that touch look the same as one thin attachment
    feats += [
        replace(
            f, location=f.location * scale, uncertain=True, removed=True, reason=f"joined (rule join-parts): {f.reason}"
        )
        for f in ext.removed_features
        if f.kind == "component"
    ]
    # open-cap's walls and facing caps name components and handles in their own words (steps.Extraction)
    feats += [replace(f, location=f.location * scale) for f in getattr(ext, "named_features", [])]
    # a cap open-cap kept closed is a possible opening the sample did not decide: always uncertain
    feats += [replace(f, location=f.location * scale) for f in ext.removed_features if f.kind == "hole"]
    if mode == "robust" and rec.d == 1 and _beyond(counts):
        # a curve's holes: the gaps between the ends of its open paths (measured here, not by features(), so
        # the paper mode's report and the robust driver's choices stay as they were), each a gap or a straight
        # piece sampled only at its ends (analysis/gaps.py)
        gaps = curve_gaps(rec.points / scale, manifold)
        feats += straight_gaps([replace(f, location=f.location * scale) for f in gaps])
    feats += [replace(f, location=f.location * scale) for f in caps]
    if mode == "robust" and rec.d >= 2 and _beyond(counts):
        # a hole fill-hole's own bounds call a gap, left open where it could not close it (robust/unclosed.py)
        feats = unclosed_gaps(rec.points, manifold, feats, getattr(ext, "opened", []), rec.spacing)
    if mode == "robust" and (rec.k, rec.d) == (3, 2) and _beyond(counts):
        # a sure hole over a planar rim: a planar cut, or a flat face sampled only on its outline (CAD,
        # decimation); the sample does not tell them apart (analysis/planar.py).  Surfaces only: a 3-manifold's
        # rim, a 2-sphere, always lies in a hyperplane of R^4, and scans are surfaces
        feats = planar_holes(rec.points, feats, rec.spacing, manifold)
    if contacts and mode == "robust" and (rec.k, rec.d) == (3, 2) and _beyond(counts):
        # parts held together only by faces that stand across the normals: a contact no rule decided
        feats += [
            replace(f, location=f.location * scale)
            for f in hidden_parts(rec.points / scale, manifold, rec.normals[:, :, 0], feats)
        ]
        # and handles whose loops only such faces carry (two contacts between the same two parts)
        if _surface(topo) and any(f.kind == "handle" and not f.removed for f in feats):
            bridged = bridged_handles(rec.points / scale, manifold, rec.normals[:, :, 0], feats)
            feats = [
                replace(f, uncertain=True, reason=f"{f.reason} ({BRIDGED})") if i in bridged else f
                for i, f in enumerate(feats)
            ]
    if enclosing:
        # one closed component holding two regions the sample encloses: objects joined where they touch
        # (not on the paper's own result: its guarantees hold, and at 300,000 samples the check costs 3 s)
        found = joined_objects(rec.points / scale, manifold, rec.normals[:, :, 0], cells, feats, adjacency, voids)
        feats += [replace(f, location=f.location * scale) for f in found]
    # closed, or open without a fin (an open scan: session 44, a false bridge of 20.6 radii on the elephant
    # with a hole cut into it, at 0.1 h, was checked nowhere)
    if resample and mode == "robust" and (rec.k, rec.d) == (3, 2) and _surface(topo) and _beyond(counts):
        t1 = time.perf_counter()
        closed = topo.closed_manifold
        feats, said = resample_check(
            rec.points,
            feats,
            topo.betti,
            lambda sub: _resampled(sub, rec, test, theta, cancel, report, closed),
            closed=closed,
        )
        if said:
            topo.messages.append(f"{said} ({time.perf_counter() - t1:.1f} s)")
    # the labelled 3-manifolds and up (of their hull too; not grown on request, labelling=False)
    solid = rec.d >= 3 and rec.subspace_dim == rec.d + 1 and rec.labelling
    if resample and mode == "robust" and solid and topo.closed_manifold and _beyond(counts):
        t1 = time.perf_counter()
        found, said = resample_betti(
            rec.points / scale,
            manifold,
            topo.betti,
            lambda sub: _resampled_complex(sub * scale, rec, test, theta, cancel, report),
        )
        feats += [replace(f, location=f.location * scale) for f in found]
        topo.messages.append(f"{said} ({time.perf_counter() - t1:.1f} s)")
    # the extension's closed results in codimension 2 and more (grown: no inside and outside to label): loops
    # the sample holds for sure and M_S lacks (analysis/persistence.py); the paper's own results are not checked
    grown = rec.subspace_dim - rec.d >= 2 and rec.delaunay_simplices.shape[1] >= 3
    if mode == "robust" and grown and topo.closed_manifold and _beyond(counts):
        t1 = time.perf_counter()
        lost, sure = _missing_loops(rec, manifold, topo.betti[1], cancel)
        feats += lost
        topo.messages.append(
            f"the sample holds {sure} loop{'' if sure == 1 else 's'} for sure (cycles of its union of balls "
            f"born within a sampling radius that live {PERSISTENT_SURE:g} times their birth or more) and M_S "
            f"has {topo.betti[1]}"
            + (f": M_S may lack {len(lost)}" if lost else "")
            + f" ({time.perf_counter() - t1:.1f} s)"
        )
    below = [f for f in feats if f.removed and not f.uncertain]
    if below:
        topo.messages.append(
            f"cut-handle removed {len(below)} "
            + ("handles whose loops (" if len(below) > 1 else "handle whose loop (")
            + ", ".join(f"{f.size_spacings:.3g}" for f in below[:5])
            + (" ..." if len(below) > 5 else "")
            + (" sampling radii) are" if len(below) > 1 else " sampling radii) is")
            + " shorter than any eps < 1 sample resolves (2 pi): noise or a bridge, "
            "below the sample's resolution (the JSON report lists them under removed_features)"
            + _others_cut(cut, len(below))
        )
    if any(f.uncertain for f in feats):
        doubt = [f for f in feats if f.uncertain]
        held = _named_counts([f for f in doubt if not f.removed])
        taken = _named_counts([f for f in doubt if f.removed])
        parts = ([f"{held} of M_S"] if held else []) + (
            [f"{taken} that the extension removed or closed (each may be real)"] if taken else []
        )
        topo.messages.append(
            f"{UNDECIDED}: {' and '.join(parts)} uncertain (each listed with "
            "where it is: the report's uncertain_features, the window's Uncertain features)"
        )
    return feats


#: How the message on the uncertain features begins (the printed summary leaves it to its own suffix).
UNDECIDED = "the sample does not decide every feature"


def _named_counts(feats: list[Feature]) -> str:
    """E.g. "4 handles, 1 hole" ('' for none)."""
    return ", ".join(
        f"{c} {kind if c == 1 else plural}"
        for kind, plural in (("handle", "handles"), ("hole", "holes"), ("component", "components"))
        if (c := sum(f.kind == kind for f in feats))
    )


def _missing_loops(
    rec: Reconstruction, manifold: np.ndarray, b1: int, cancel: object | None
) -> tuple[list[Feature], int]:
    """:func:`~.analysis.persistence.missing_loops` on the run's own Delaunay cells, where they were built.

    The cells come from the joggled working coordinates (:func:`~.prepare.prepare_points`, made again from
    the input: the same call gives the same coordinates) with the bounding points; a sample's unit is the
    larger of its nearest-neighbour distance and M_S's sampling radius there (the features' gap unit).
    """
    relative = rec.joggle / rec.spacing if rec.spacing > 0 else 0.0
    prep = prepare_points(rec.input_points, rec.d, joggle=relative)
    bounds = (rec.bounding_points - prep.center) @ prep.basis / prep.scale
    unit = np.maximum(nearest_distances(rec.points), local_spacing(rec.points, manifold)) / prep.scale
    lost, sure = missing_loops(
        np.vstack([prep.work, bounds]), rec.delaunay_simplices, unit, b1, rec.d, prep.scale, cancel
    )
    return [replace(f, location=rec.points[f.vertices].mean(axis=0)) for f in lost], sure


def _beyond(counts: dict) -> bool:
    """Whether the extraction took steps beyond the paper's Algorithm 3 (its result is not the paper's)."""
    return any(rule not in (RULE_PRUNE, RULE_RESOLVE) and c["steps"] for rule, c in counts.items())


def _surface(topo: TopologyReport) -> bool:
    """Whether M_S is a surface without fins (no face in three or more simplices), closed or with boundary.

    The topology report counts pinched vertices on closed complexes only, so an open M_S with a pinch passes.
    """
    return topo.closed_manifold or (topo.nonmanifold_faces == 0 and topo.singular_vertices == 0)


#: The stages of a run in order, for the progress of ``resample-check``'s run (shown as the topology stage).
_STAGES = ("prepare", "delaunay", "normals", "candidates", "extraction", "topology")


def _resampled(
    sub: np.ndarray,
    rec: Reconstruction,
    test: str,
    theta: float,
    cancel: object | None,
    report: Callable,
    closed: bool = True,
) -> Resampled:
    """The reconstruction of some of the samples, the same way (``resample-check``'s run, without the check).

    Its second value: whether it is a closed manifold (``closed``), else whether it is a surface without fins
    (no face in three or more triangles), closed or with boundary.
    """
    r = _rerun(sub, rec, test, theta, cancel, report)
    t = r.topology
    return t.betti, t.closed_manifold if closed else _surface(t) and t.n_simplices > 0, r.features, r.points


def _resampled_complex(
    sub: np.ndarray,
    rec: Reconstruction,
    test: str,
    theta: float,
    cancel: object | None,
    report: Callable,
) -> tuple[tuple[int, ...], bool, np.ndarray]:
    """:func:`_resampled`'s run, giving M_S on the rows of ``sub``.

    The run numbers its samples its own way (spatially sorted, duplicates merged): its M_S is mapped back to
    the rows it was given (``point_input``), so that the caller can compare it with its own M_S on the same
    samples (until session 37 the run's own order was returned, never matched the caller's, and the two
    complexes were not compared at all).
    """
    r = _rerun(sub, rec, test, theta, cancel, report)
    return r.topology.betti, r.topology.closed_manifold, r.point_input[r.manifold]


def _rerun(
    sub: np.ndarray, rec: Reconstruction, test: str, theta: float, cancel: object | None, report: Callable
) -> Reconstruction:
    """``resample-check``'s own reconstruction of the kept samples, the way ``rec`` was made, without the check."""

    def progress(stage: str, frac: float) -> None:
        i = _STAGES.index(stage) if stage in _STAGES else len(_STAGES) - 1
        report("topology", 0.5 + 0.45 * (i + min(max(frac, 0.0), 1.0)) / len(_STAGES))

    from .reconstruct import reconstruct  # the check's own run (imported here: that module imports this one)

    return reconstruct(
        sub,
        rec.d,
        test=test,
        theta=theta,
        joggle=rec.joggle / rec.spacing if rec.spacing > 0 else DEFAULT_JOGGLE,  # the run's own, relative
        mode="robust",
        normals=rec.normals_method,
        progress=progress,
        cancel=cancel,
        resample=False,
        contacts=False,  # they add flags only; the check reads the Betti numbers and the handles' loops
        labelling=rec.labelling,
    )


def _others_cut(cut: list[Feature], sure: int) -> str:
    """The handles cut-handle removed beside the ``sure`` ones (``cut``: all it removed): those listed as uncertain."""
    band = sum(f.uncertain for f in cut)
    if not band:
        return ""
    return f"; the other {band} it removed {'is' if band == 1 else 'are'} among the uncertain features"
