"""The whole pipeline: prepare -> Delaunay -> Algorithm 1 -> 2 -> 3 -> topology."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from .analysis.topology import analyse
from .delaunay.triangulation import backend_label, bounding_points, circumcenters, delaunay
from .errors import InputError, check_cancel
from .paper import candidates as cand
from .paper.candidates import SCORE_LIMIT
from .paper.extraction import extract
from .paper.normals import complete_bases, greedy_poles
from .prepare import DEFAULT_JOGGLE, prepare_points, prescale
from .result import CANDIDATE_TESTS, EXTRACTION_MODES, CandidateAngles, Candidates, Reconstruction
from .robust.driver import extract_robust
from .robust.smooth_normals import smoothed_normals
from .uncertainty import result_features
from .util.hullframe import hull_frame
from .util.memory import TRIM_MIN_POINTS, gc_paused, release_free_memory, small_pages
from .util.nearest import remember
from .util.parallel import start_in_background

ProgressFn = Callable[[str, float], None]


def _next_stage(cancel: object | None, n: int) -> None:
    """Between stages: check cancel, and on a large run hand freed memory back (the next peak starts from it)."""
    if n >= TRIM_MIN_POINTS:
        release_free_memory()
    check_cancel(cancel)


def _validate_params(test: str, theta: float, mode: str = "robust") -> float:
    if mode not in EXTRACTION_MODES:
        raise InputError(f"unknown extraction mode {mode!r}; choose one of {', '.join(EXTRACTION_MODES)}")
    if test not in CANDIDATE_TESTS:
        raise InputError(f"unknown candidate test {test!r}; choose one of {', '.join(CANDIDATE_TESTS)}")
    try:
        theta = float(theta)
    except (TypeError, ValueError):
        raise InputError(f"theta must be an angle in radians; got {theta!r}") from None
    if not 0 < theta <= SCORE_LIMIT:
        raise InputError(f"theta must lie in (0, {np.degrees(SCORE_LIMIT):.0f} deg]; got {np.degrees(theta):.3g} deg")
    return theta


#: Algorithm 1 as printed, and its planes averaged over the samples nearby (beyond the paper).
NORMAL_METHODS = ("paper", "smoothed")


def cost_warning(k: int, d: int) -> str | None:
    """A sentence to show before a run that will be slow, or None.

    crustview is built and measured for k <= 5.  Beyond, the Delaunay
    triangulation of n points in R^k has up to n^ceil(k/2) simplices and, in
    codimension >= 4, Algorithm 2 enumerates vertex subsets of every dual
    cell: 40 random points in R^6 take about 5 s and 30 in R^7 about 20 s.
    """
    if k <= 5 and k - d <= 3:
        return None
    return (
        f"Points in R^{k} with d = {d} (codimension {k - d}): crustview is built and measured for "
        "k <= 5; Qhull's Delaunay and Algorithm 2's search over each dual cell grow steeply here "
        "(30 random points in R^7 take about 20 s), so expect a long run."
    )


@small_pages
def reconstruct(
    points: np.ndarray,
    d: int,
    *,
    test: str = "cocone",
    theta: float = np.pi / 8,
    joggle: float = DEFAULT_JOGGLE,
    prune_boundary: bool = True,
    mode: str = "robust",
    normals: str = "paper",
    progress: ProgressFn | None = None,
    cancel: object | None = None,
    resample: bool = True,
    contacts: bool = True,
    labelling: bool = True,
) -> Reconstruction:
    """Reconstruct a closed d-manifold from samples in R^k.

    Parameters
    ----------
    points : array_like of shape (n, k)
        The samples.  Duplicates are merged (see :mod:`.prepare`).
    d : int
        Intrinsic dimension, ``1 <= d <= k - 1``.
    test : {"cocone", "cocone-all", "literal"}
        Candidate test used for extraction.  All are always computed and
        stored in ``result.candidates``.  ``"cocone"`` (default) also looks at
        *where* the dual Voronoi cell is (some vertex's cocone);
        ``"cocone-all"`` requires every vertex's cocone (Cocone's rule);
        ``"literal"`` is the paper's orientation-only test.
    theta : float
        Angle threshold of the candidate test, radians (paper: pi/8), at most
        pi/4 (cocone scores above pi/4 are only lower bounds).
    prune_boundary : bool
        Algorithm 3 prunes faces with a single simplex (the paper).  False
        keeps them, for looking at samples with holes (scans); the result is
        then not closed and the report says so.  Paper mode only.
    mode : {"robust", "paper"}
        ``"robust"`` (default): the paper's Algorithm 3, and where it cannot
        give a closed manifold through every sample, the growing extension of
        :mod:`crustview.core.robust.driver` (identical result whenever the paper's
        loop succeeds).  ``"paper"``: Algorithm 3 exactly as printed.
    normals : {"paper", "smoothed"}
        ``"paper"`` (default): Algorithm 1 as printed.  ``"smoothed"``: its
        planes averaged over the samples within two spacings, which survives
        noise (:mod:`crustview.core.robust.smooth_normals`).
    joggle : float
        Relative size (of the sample spacing) of the perturbation applied
        before Qhull; 0 disables it (slow and degenerate on cospherical data).
    progress : callable(stage, fraction), optional
        Called between and inside stages.
    cancel : object with ``is_set()``, optional
        When it becomes set, :class:`~crustview.core.errors.Cancelled` is raised.
    resample : bool
        Rule ``resample-check`` (:mod:`crustview.core.analysis.resample`):
        where the robust extension made a closed surface in R^3 with a handle
        just above the resolution bound, reconstruct 90 % of the samples again
        and make such a handle uncertain if it is not there.  False skips it
        (the check's own run does).
    contacts : bool
        The report's checks of contacts in the robust result of a surface in
        R^3: parts held together only by faces standing across the normals,
        handles only such faces carry, and one closed component holding two
        enclosures.  They only add uncertain features and flags; False skips
        them (``resample-check``'s own run, which reads only its handles'
        loops, does).
    labelling : bool
        The robust extraction of a hypersurface (d = k - 1, or d + 1 the dimension of the sample's
        affine hull: a 3-manifold given in R^5 with a constant coordinate) labels the Delaunay cells
        inside or outside, closed by construction.  False grows it face by face instead, as every
        codimension >= 2 is: the growing path's own rules on a hypersurface (its tests, a comparison).

    Returns
    -------
    Reconstruction

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    >>> rec = reconstruct(np.c_[np.cos(t), 2 * np.sin(t)], d=1)
    >>> rec.topology.closed_manifold, rec.topology.betti
    (True, (1, 1))
    """
    theta = _validate_params(test, theta, mode)
    if normals not in NORMAL_METHODS:
        raise InputError(f"unknown normals {normals!r}; choose one of {', '.join(NORMAL_METHODS)}")
    normals_method = normals  # the name is reused for the arrays below
    report = progress or (lambda stage, frac: None)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    report("prepare", 0.0)
    prep = prepare_points(points, d, joggle=joggle)
    if prep.nearest is not None:
        # the merging measured every sample's nearest-neighbour distance: the later stages, which ask for
        # them of the samples and of the samples rescaled by reextract's power of two, take them from here
        unit = prescale(prep.points)
        remember(prep.points, prep.nearest)
        remember(prep.points / unit, prep.nearest / unit)
    n, k = prep.points.shape
    r = prep.r
    timings["prepare"] = time.perf_counter() - t0
    _next_stage(cancel, n)

    t0 = time.perf_counter()
    report("delaunay", 0.0)
    bounds = bounding_points(r)
    # in codimension 1 the neighbour table pairs the faces' two simplices (see enumerate_faces)
    if r - d == 1:
        simplices, neighbors = delaunay(prep.work, bounds, neighbors=True)
    else:
        simplices, neighbors = delaunay(prep.work, bounds), None
    check_cancel(cancel)  # a cancel during the triangulation stops here, before the listing starts
    # Algorithm 2's face lists need only the simplices: listed on the other core while the circumcentres
    # are computed and during Algorithm 1
    listing = start_in_background(cand.enumerate_faces, simplices, n, d, neighbors=neighbors)
    del neighbors
    try:
        work_all = np.vstack([prep.work, bounds])
        # room for the Voronoi vertices at infinity (at most one per sample), filled in place at the lift
        centres = circumcenters(work_all, simplices, spare=n if r == k else 0)
        timings["delaunay"] = time.perf_counter() - t0
        _next_stage(cancel, n)
    except BaseException:
        listing.exception()  # waits: the listing is not left running past a failed or cancelled run
        raise

    t0 = time.perf_counter()
    report("normals", 0.0)
    try:
        pole_w, normals_w, infinite = greedy_poles(work_all, simplices, centres, n, r - d)
        if normals_method == "smoothed":  # beyond the paper: AN_s averaged over the samples nearby
            normals_w = smoothed_normals(prep.work, normals_w)
        # lift: in-subspace normals plus the complement of the affine hull
        normals = prep.lift_vectors(np.swapaxes(normals_w, 1, 2))  # (n, r-d, k)
        if r < k:
            comp = np.linalg.qr(prep.basis, mode="complete")[0][:, r:]  # (k, k-r)
            normals = np.concatenate([normals, np.broadcast_to(comp.T, (n, k - r, k))], axis=1)
            pole_w = np.concatenate([pole_w, np.full((n, k - r), -1, dtype=np.int64)], axis=1)
        normals, tangents = complete_bases(np.swapaxes(normals, 1, 2))
    except BaseException:
        listing.exception()  # waits: the listing is not left running past a failed run
        raise
    timings["normals"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    report("candidates", 0.0)
    faces, cptr, csimp = listing.result()  # what is left of the listing counts as candidates
    del listing
    _next_stage(cancel, n)
    lit = cand.literal_angles(prep.work, normals_w, faces)
    _next_stage(cancel, n)
    low = np.empty(len(faces))  # the cocone test's verdict, made by the scoring threads
    coc = cand.cocone_angles(
        work_all,
        normals_w,
        centres,
        faces,
        cptr,
        csimp,
        simplices=simplices,
        progress=lambda f: (report("candidates", f), check_cancel(cancel)),
        minimum=low,
    )
    del cptr, csimp  # the dual cells' incidences: the largest temporaries of the run
    candidates = Candidates(
        faces=faces,
        angles=CandidateAngles(lit, coc, cocone=low),
        theta=theta,
        vertex_angles=coc,
    )
    timings["candidates"] = time.perf_counter() - t0
    _next_stage(cancel, n)

    del work_all
    voronoi = prep.lift_appended(centres, infinite)  # in the circumcentres' array: they are not used again
    del centres
    rec = Reconstruction(
        d=d,
        k=k,
        input_points=np.asarray(points, dtype=np.float64),
        input_index=prep.input_index,
        points=prep.points,
        point_input=prep.point_input,
        spacing=prep.spacing,
        joggle=prep.joggle,
        subspace_dim=r,
        bounding_points=prep.lift(bounds),
        delaunay_simplices=simplices,
        voronoi_vertices=voronoi,
        pole_index=pole_w,
        normals=normals,
        tangents=tangents,
        candidates=candidates,
        test=test,
        theta=theta,
        extraction=None,  # type: ignore[arg-type]
        manifold=np.empty((0, d + 1), np.int64),
        topology=None,  # type: ignore[arg-type]
        timings=timings,
        prune_boundary=prune_boundary,
        mode=mode,
        delaunay_backend=backend_label(r),
        normals_method=normals_method,
    )
    del faces, lit, coc, low, simplices, normals, tangents, candidates, voronoi  # held by rec only
    return reextract(
        rec,
        test,
        theta,
        prune_boundary=prune_boundary,
        mode=mode,
        progress=progress,
        cancel=cancel,
        resample=resample,
        contacts=contacts,
        labelling=labelling,
    )


@small_pages
def reextract(
    rec: Reconstruction,
    test: str,
    theta: float,
    *,
    prune_boundary: bool | None = None,
    mode: str | None = None,
    progress: ProgressFn | None = None,
    cancel: object | None = None,
    resample: bool = True,
    contacts: bool = True,
    labelling: bool | None = None,
) -> Reconstruction:
    """Re-run Algorithm 3 and the topology report for another test or threshold.

    Nothing before Algorithm 3 is recomputed: every test's angles are stored.
    ``prune_boundary=None``, ``mode=None`` and ``labelling=None`` keep the settings of ``rec``;
    ``resample``, ``contacts`` and ``labelling`` as in :func:`reconstruct`.

    Returns
    -------
    Reconstruction
        A new object sharing the arrays of ``rec``.
    """
    if mode is None:
        mode = rec.mode
    theta = _validate_params(test, theta, mode)
    report = progress or (lambda stage, frac: None)
    timings = dict(rec.timings)
    t0 = time.perf_counter()
    report("extraction", 0.0)
    tset = None  # T_S's rows, gathered only for the paper's loop (the robust driver selects by the angles)
    frame = None  # the sample's hull, where a hypersurface of it is labelled (below)
    if prune_boundary is None:
        prune_boundary = rec.prune_boundary
    if labelling is None:
        labelling = rec.labelling
    # the exact power-of-two rescaling keeps squares finite at any input scale
    scale = prescale(rec.points)
    measured: list = []  # the robust driver's measurement of the paper's own result, begun early
    with gc_paused():  # see memory.gc_paused: the extraction makes many long-lived small objects
        if mode == "robust":
            cells = None
            work = rec.points / scale
            if labelling and rec.subspace_dim == rec.d + 1:  # hypersurfaces (of their affine hull): labelled
                m = len(rec.delaunay_simplices)
                if rec.subspace_dim < rec.k:  # in the hull's own coordinates, where the Delaunay cells are
                    frame = hull_frame(work, rec.subspace_dim)
                    work = frame.down(work)

                def _cells() -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # made only if the paper's loop fails
                    pts, centres = rec.delaunay_points / scale, rec.voronoi_vertices[:m] / scale
                    if frame is not None:
                        pts, centres = frame.down(pts), frame.down(centres)
                    return pts, rec.delaunay_simplices, centres

                cells = _cells
            ext = extract_robust(
                work,
                rec.candidates.faces,
                rec.candidates.angles[test],
                theta,
                spacing=rec.spacing / scale,
                cells=cells,
                cancel=cancel,
                progress=lambda f: report("extraction", f),
                rows_sorted=True,  # Candidates.faces: sorted rows
                measured=measured,
            )
        else:
            tset = rec.candidates.select(test, theta)
            ext = extract(
                rec.points / scale,
                tset,
                prune_boundary=prune_boundary,
                cancel=cancel,
                progress=lambda f: report("extraction", f),
            )
    manifold = ext.complex_at(ext.n_steps)
    timings["extraction"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    report("topology", 0.0)
    # the robust driver analysed this very complex to decide on it (the same steps, samples and dimension)
    known = getattr(ext, "final_topology", None)
    if known is not None and known[:3] == (ext.n_steps, rec.n, rec.d):
        topo = known[3]
    else:
        topo = analyse(manifold, rec.n, rec.d)
    if known is not None:
        del ext.final_topology  # the report edits topo from here on; the extraction keeps no second reference
    counts = ext.counts_by_rule()
    if mode == "robust":
        _robust_messages(ext, topo)
    elif ext.stopped == "empty":
        topo.messages.insert(
            0,
            f"extraction removed every simplex of T_S ({0 if tset is None else len(tset)} candidates; "
            + ", ".join(f"{r}: {c['steps']} steps removed {c['removed']}" for r, c in counts.items())
            + "): the sample is probably too sparse (undersampled) for this test and angle, or it "
            "has holes (an open scan), which the paper's pruning of boundary faces eats away; "
            "turn boundary pruning off to inspect such a sample",
        )
    elif topo.closed_manifold and topo.unused_samples:
        topo.messages.insert(
            0,
            f"M_S is a closed manifold but {topo.unused_samples} samples are not its vertices, which "
            "the paper requires: the sample is probably undersampled, so the topology may be wrong",
        )
    elif not topo.closed_manifold:
        topo.messages.insert(
            0,
            "extraction could not produce a closed manifold ("
            + ", ".join(f"{r}: {c['steps']} steps removed {c['removed']}" for r, c in counts.items())
            + "); the sample is probably undersampled or noisy here"
            + ("" if prune_boundary else ", and boundary faces were kept on request (prune_boundary off)"),
        )
    timings["topology"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    report("topology", 0.5)
    # in a flat (a hypersurface of the sample's hull), the report's checks run in the flat's coordinates, where
    # the driver measured its features, R^3's own among them for a surface in a 3-flat; all come back to R^k
    feats = result_features(
        replace(rec if frame is None else frame.framed(rec, scale), labelling=labelling),  # resample: as made
        ext,
        manifold,
        topo,
        scale,
        mode=mode,
        test=test,
        theta=theta,
        resample=resample,
        contacts=contacts,
        cancel=cancel,
        report=report,
        pending=measured[0] if measured else None,
    )
    if frame is not None:
        feats = frame.lift_scaled(feats, scale)
        frame.lift_features(ext)  # the extraction's own lists too (the report read them in the frame)
    timings["topology"] += time.perf_counter() - t0
    report("done", 1.0)
    cands = replace(rec.candidates, theta=theta)
    return replace(
        rec,
        candidates=cands,
        test=test,
        theta=theta,
        extraction=ext,
        manifold=manifold,
        topology=topo,
        timings=timings,
        prune_boundary=prune_boundary,
        mode=mode,
        labelling=labelling,
        features=feats,
    )


def _robust_messages(ext, topo) -> None:
    """Sentences for the report of a robust run: which extraction ran, what is left open."""
    topo.messages[:0] = list(ext.notes)
    counts = ext.counts_by_rule()
    extra = {r: c["added"] for r, c in counts.items() if c.get("added")}
    if extra:
        topo.messages.append("steps beyond the paper: " + ", ".join(f"{r} added {c}" for r, c in extra.items()))
    if topo.boundary_faces:
        topo.messages.append(
            f"{topo.boundary_faces} boundary faces remain: holes too large to be undersampling gaps "
            "(an open scan), or gaps the extension could not close; a hole whose rim is shorter than "
            "2 pi local spacings (a missing triangle or two) does not show in a sample, so this result "
            "cannot tell whether the object has such holes too"
        )
    if topo.unused_samples:
        topo.messages.append(f"{topo.unused_samples} samples are not vertices of M_S")
