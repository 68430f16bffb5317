"""The shown M_S compared with another complex: a saved result, a mesh's faces, or M_S of another run.

Qt-free.  :func:`comparison_job` builds a ``job(progress, cancel)`` that the
window runs in its worker thread; its :class:`Comparison` is what the
comparison layer draws (both / only A / only B) and what the Information
panel counts and lists.  The simplex-by-simplex work is
:func:`crustview.core.analysis.complexdiff.diff_complexes`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.analysis.complexdiff import ComplexDiff, diff_complexes
from ..core.errors import Cancelled, InputError
from ..core.result import CANDIDATE_TESTS, Reconstruction

#: What B can be.
KINDS = ("result", "mesh", "run")


@dataclass(frozen=True)
class Comparison:
    """A = the shown (final) M_S, B = the other complex.

    Attributes
    ----------
    label_a, label_b : str
    diff : ComplexDiff
        Its ``points`` are the shown samples when the vertices matched.
    rec : Reconstruction
        The result A was taken from (a comparison is dropped when it changes).
    """

    label_a: str
    label_b: str
    diff: ComplexDiff
    rec: Reconstruction
    #: What B was (the spec of :func:`comparison_job`), so a session can make it again; None if unknown.
    spec: dict | None = None

    def differing(self) -> list[tuple[str, np.ndarray]]:
        """``("A", row)`` for every simplex only in A, then ``("B", row)`` for every one only in B."""
        return [("A", r) for r in self.diff.only_a] + [("B", r) for r in self.diff.only_b]

    def summary(self) -> str:
        """Counts and distance in one or two plain sentences."""
        d, h = self.diff, self.diff.hausdorff
        # the command line's words (`crustview compare`): the value, or the bound where the grids are coarse
        same = d.matched and not len(d.only_a) and not len(d.only_b)
        dist = (
            f"Hausdorff distance {'0 (the same simplices)' if same else h.words()} (A to B {h.a_to_b:.4g}, "
            f"B to A {h.b_to_a:.4g}; sampled, within {h.error_bound:.2g})."
        )
        if not d.matched:
            return "A and B do not share vertices, so only their distance is compared: " + dist
        return f"{len(d.both):,} simplices in both, {len(d.only_a):,} only in A, {len(d.only_b):,} only in B. " + dist


def _check_rec(rec: Reconstruction, d: int, label: str) -> None:
    if d != rec.d:
        raise InputError(f"{label} holds {d}-simplices; the shown M_S is {rec.d}-dimensional")


def load_other(rec: Reconstruction, spec: dict, progress=None, cancel=None) -> tuple[str, np.ndarray, np.ndarray]:
    """B's label, points and simplices from ``spec`` (see :func:`comparison_job`)."""
    kind = spec.get("kind")
    if kind not in KINDS:
        raise InputError(f"compare with what? kind {kind!r} is not one of {', '.join(KINDS)}")
    if kind == "run":
        from ..core import reextract

        test, theta, mode = spec.get("test", rec.test), float(spec.get("theta", rec.theta)), spec.get("mode", rec.mode)
        if test not in CANDIDATE_TESTS:
            raise InputError(f"test {test!r} is not one of {', '.join(CANDIDATE_TESTS)}")
        other = reextract(
            rec, test, theta, prune_boundary=rec.prune_boundary, mode=mode, progress=progress, cancel=cancel
        )
        label = f"M_S with {test}, θ = {math.degrees(theta):.4g}°, {mode}"
        return label, other.points, np.asarray(other.manifold)
    from .. import io

    path = Path(str(spec.get("path", "")))
    if not path.is_file():
        raise InputError(f"'{path}' does not exist" if str(path) not in ("", ".") else "choose a file to compare with")
    if kind == "result":
        params = io.read_run_parameters(path)
        if params is None:
            raise InputError(f"'{path.name}' is not a saved crustview result (an .npz with M_S)")
        _check_rec(rec, int(params["d"]), path.name)
        return f"{path.name} (saved M_S)", io.read_points(path), np.asarray(params["simplices"])
    mesh = io.read_mesh(path)
    if mesh is None:
        raise InputError(f"'{path.name}' has no faces to compare with (a point file?)")
    return f"{path.name} (mesh faces)", mesh.points, mesh.simplices(rec.d)


def comparison_job(rec: Reconstruction, spec: dict):
    """``job(progress, cancel) -> Comparison`` of ``rec``'s M_S (A) with B described by ``spec``.

    Parameters
    ----------
    rec : Reconstruction
    spec : dict
        ``{"kind": "result", "path": ...}`` (a saved ``.npz``),
        ``{"kind": "mesh", "path": ...}`` (its faces), or
        ``{"kind": "run", "test": ..., "theta": radians, "mode": ...}``
        (Algorithm 3 again on the same candidates).
    """
    label_a = f"M_S ({rec.test}, θ = {math.degrees(rec.theta):.4g}°, {rec.mode})"

    def job(progress=None, cancel=None) -> Comparison:
        report = progress or (lambda stage, fraction: None)
        report("reading B", 0.0)
        label_b, pb, sb = load_other(rec, spec, progress, cancel)
        if np.asarray(pb).shape[1] != rec.k:
            raise InputError(f"{label_b} is in R^{np.asarray(pb).shape[1]}, the shown M_S in R^{rec.k}")
        if cancel is not None and cancel.is_set():
            raise Cancelled("comparison cancelled")
        report("comparing", 0.5)
        diff = diff_complexes(rec.points, np.asarray(rec.manifold), pb, sb, rec.d)
        report("comparing", 1.0)
        return Comparison(label_a, label_b, diff, rec, dict(spec))

    return job
