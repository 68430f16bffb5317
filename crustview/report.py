"""The JSON report of a reconstruction (``crustview reconstruct --report``).

:func:`report_dict` gives its content as plain Python objects and
:func:`write_report` writes it; both are re-exported by :mod:`crustview.io`.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from crustview.atomic import atomic_open
from crustview.core.errors import InputError

if TYPE_CHECKING:
    from crustview.core.analysis.compare import MeshComparison
    from crustview.core.analysis.features import Feature
    from crustview.core.analysis.quality import SamplingQuality
    from crustview.core.result import Reconstruction


def _reason(err: BaseException) -> str:
    text = (err.strerror if isinstance(err, OSError) and err.strerror else str(err)) or type(err).__name__
    return " ".join(text.split()).rstrip(".")


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_jsonable(v) for v in obj]
    return obj


#: Number of prune cascades listed in a report (largest first).
REPORT_CASCADES = 20


def holes_of_candidates(rec: Reconstruction) -> int:
    """Number of (d-1)-faces of T_S that lie in a single d-simplex of T_S (the holes of T_S).

    ``rec.extraction.holes`` when the extraction recorded them, otherwise
    counted on T_S for ``rec.test`` and ``rec.theta``.
    """
    if rec.extraction.holes is not None:
        return len(rec.extraction.holes)
    from crustview.core.paper.facets import facet_structure

    tset = rec.candidates.select(rec.test, rec.theta)
    if len(tset) == 0:
        return 0
    ptr = facet_structure(np.asarray(tset, dtype=np.int64))[2]
    return int(np.count_nonzero(np.diff(ptr) == 1))


def _cascades(rec: Reconstruction) -> dict[str, Any]:
    cascades = rec.extraction.cascades()
    return {
        "n_cascades": len(cascades),
        "cascades": [
            {
                "origin": c.origin,
                "tau": [int(rec.point_input[v]) for v in c.tau],
                "rule": c.rule,
                "hole": c.hole,
                "steps": len(c.steps),
                "removed": c.removed,
            }
            for c in cascades[:REPORT_CASCADES]
        ],
    }


def left_out_samples(rec: Reconstruction) -> list[int]:
    """The input rows of the samples that are no vertex of M_S (ascending; empty when every sample is one).

    Rows of the input file (``rec.point_input``: the first row of each merged
    duplicate), so that a user can find them in the data.
    """
    used = np.zeros(rec.n, bool)
    if len(rec.manifold):
        used[np.asarray(rec.manifold).ravel()] = True
    return sorted(int(rec.point_input[i]) for i in np.flatnonzero(~used))


def _feature(f: Feature, quality: SamplingQuality | None) -> dict[str, Any]:
    """A feature's JSON form with the estimated epsilon over its samples (``epsilon``, ``epsilon_max``)."""
    from crustview.core.analysis.quality import feature_epsilon

    out = f.as_dict()
    if quality is not None:
        out.update(feature_epsilon(quality.epsilon, f.vertices))
    return out


def report_dict(
    rec: Reconstruction,
    comparison: MeshComparison | None = None,
    quality: dict[str, Any] | SamplingQuality | None = None,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """The content of :func:`write_report` as plain Python objects.

    Parameters
    ----------
    rec : Reconstruction
    comparison : MeshComparison, optional
        M_S against a mesh's faces (key ``ground_truth``).
    quality : SamplingQuality or dict, optional
        :func:`crustview.core.analysis.quality.sampling_quality` of ``rec`` (or its
        :func:`~crustview.core.analysis.quality.summary`) when already computed; otherwise it is
        computed here (a summary alone lacks the per-sample values the listed features need: then those
        are computed too).  Its ``seconds`` are left out, so that the report of a run is the same every time
        it is made.  Every entry of ``uncertain_features`` and ``removed_features`` gets the estimated
        epsilon over its samples (``epsilon``, the median; ``epsilon_max``, the coarsest:
        :func:`~crustview.core.analysis.quality.feature_epsilon`).
    extra : dict, optional
        More keys, added last: e.g. ``input`` (what the file held besides
        coordinates, and the angles between its normals and AN_s) and
        ``dimension_estimate`` (how ``-d auto`` chose d, or, with ``given_d``, the
        estimate that contradicts a ``-d`` given by hand).
    """
    from crustview.core.analysis.quality import SamplingQuality, sampling_quality, summary

    listed = [f for f in rec.features if f.uncertain or f.removed]
    per_sample = quality if isinstance(quality, SamplingQuality) else None
    if per_sample is None and (quality is None or listed):  # each listed feature says its estimated epsilon
        per_sample = sampling_quality(rec)
    quality = summary(rec, per_sample) if not isinstance(quality, dict) else quality
    quality = {key: value for key, value in quality.items() if key != "seconds"}
    more = {} if comparison is None else {"ground_truth": comparison.as_dict()}
    level, sentence = result_verdict(rec, comparison)
    if rec.mode == "paper":
        more.update(_cascades(rec))
    more.update(extra or {})
    return _jsonable(
        {
            "d": rec.d,
            "k": rec.k,
            "n": rec.n,
            "n_input": len(rec.input_points),
            "test": rec.test,
            "theta": rec.theta,
            "theta_degrees": math.degrees(rec.theta),
            "mode": rec.mode,
            "normals": rec.normals_method,
            "prune_boundary": rec.prune_boundary,
            "labelling": rec.labelling,
            "n_candidates": int(rec.candidates.mask(rec.test, rec.theta).sum()),
            "holes_of_T_S": holes_of_candidates(rec),
            "stopped": rec.extraction.stopped,
            "notes": list(rec.extraction.notes),
            "topology": rec.topology.as_dict(),
            "verdict": {"level": level, "text": sentence},
            "left_out_samples": left_out_samples(rec),
            "uncertain_features": [_feature(f, per_sample) for f in rec.uncertain_features],
            # every handle the rule cut-handle removed (the ones below any eps < 1 sample's resolution too),
            # every separation join-parts joined, every cap open-cap kept closed
            "removed_features": [_feature(f, per_sample) for f in rec.features if f.removed],
            "features": {
                kind: sum(f.kind == kind and not f.removed and not f.disputed for f in rec.features)
                for kind in ("handle", "hole", "component")
            },
            "rules": rec.extraction.counts_by_rule(),
            "sampling_quality": quality,
            "timings": dict(rec.timings),
            "delaunay_backend": rec.delaunay_backend,
            **more,
        }
    )


def result_verdict(rec: Reconstruction, comparison: MeshComparison | None = None) -> tuple[str, str]:
    """How sure the result is, in one word and a sentence, as the window says it.

    ``"sure"``, ``"uncertain"``, ``"wrong"`` (the mesh's own faces contradict it: ``comparison``) or
    ``"failed"`` (:func:`crustview.scene.describe.verdict_word`).
    """
    from types import SimpleNamespace

    from crustview.scene.describe import verdict_word

    truth = None if comparison is None else SimpleNamespace(comparison=comparison, manifold=None)
    return verdict_word(rec, truth)


def write_report(
    path: str | os.PathLike,
    rec: Reconstruction,
    comparison: MeshComparison | None = None,
    extra: dict[str, Any] | None = None,
) -> None:
    """Write a JSON summary of a reconstruction.

    Keys: ``d k n n_input test theta theta_degrees mode prune_boundary labelling
    n_candidates stopped``; ``holes_of_T_S`` (the number of (d-1)-faces of
    T_S in a single simplex before extraction); ``notes`` (how the
    extraction went, e.g. why the robust extension took over);
    ``topology`` (:meth:`TopologyReport.as_dict`); ``verdict`` (``level``: ``"sure"``, ``"uncertain"``,
    ``"wrong"`` or ``"failed"``, and ``text``, as the window says it: :func:`result_verdict`); ``rules``
    (:meth:`Extraction.counts_by_rule`); ``sampling_quality``
    (:func:`crustview.core.analysis.quality.summary` without its ``seconds``:
    estimated epsilon and the samples beyond the paper's bounds);
    ``uncertain_features`` and ``removed_features`` (each with ``kind``, ``location``,
    ``size_spacings``, ``reason`` and the estimated ``epsilon`` over its samples, median and
    ``epsilon_max``); ``left_out_samples`` (input rows); ``timings`` (seconds per stage);
    ``delaunay_backend`` (the Delaunay code that ran, e.g. CGAL through crustview's extension, or Qhull).
    Paper runs also have ``n_cascades`` and ``cascades``: the
    :data:`REPORT_CASCADES` largest prune cascades, each with its
    ``origin`` step, its face ``tau`` (input rows), the origin's ``rule``, ``hole``
    (the origin face was a hole of T_S), the number of ``steps`` and of
    simplices ``removed``.  With a ``comparison``, also ``ground_truth``
    (:meth:`~crustview.core.analysis.compare.MeshComparison.as_dict`: recovered and
    extra faces, both topologies, the sampled Hausdorff distance).  ``extra``
    adds keys as in :func:`report_dict`.  The file is written atomically
    (:mod:`crustview.atomic`): a failed write leaves the previous report.

    Raises
    ------
    InputError
        When the file cannot be written.
    """
    path = Path(path)
    try:
        content = report_dict(rec, comparison, extra=extra)
        with atomic_open(path, "w", encoding="utf-8") as fh:
            json.dump(content, fh, indent=2)
            fh.write("\n")
    except OSError as err:
        raise InputError(f"Cannot write '{path}': {_reason(err)}.") from None
