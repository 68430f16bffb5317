"""A generated sample reconstructed and judged against its known Betti numbers (bench_objects, bench_shapes,
bench_curves)."""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import numpy as np

from crustview.core import reconstruct

#: Share of the samples that must be vertices at 0.3 h (as ``bench_scans.py``; issue 18's done-when).
USED_NOISY = 0.99


@dataclass
class Judged:
    """What one run gave: right or not, flagged or not, and the row's numbers."""

    right: bool
    flagged: bool
    betti: tuple[int, ...]
    uncertain: tuple[int, int, int]  # handles, holes, components in doubt
    used: int
    seconds: float

    @property
    def quiet_wrong(self) -> bool:
        """A wrong topology without an uncertain feature: issue 18's target is none.

        An open result without one counts too: its report lists every hole as sure (the window's amber for any
        open result says only "an open scan?"), so only ``uncertain_features`` flags a result.
        """
        return not self.right and not self.flagged

    @property
    def right_flagged(self) -> bool:
        """A right result that carries an uncertain feature (issue 18: at most one in ten)."""
        return self.right and sum(self.uncertain) > 0

    def add_to(self, row: list[int]) -> None:
        """Count this run in a tally row [right, total, wrong without a flag, right with one]."""
        row[0] += self.right
        row[1] += 1
        row[2] += self.quiet_wrong
        row[3] += self.right_flagged


def judge(points: np.ndarray, betti: tuple[int, ...], noise: float, d: int = 2) -> Judged:
    """Reconstruct ``points`` (a d-manifold, a surface by default) and judge it: closed, ``betti``, every
    sample (99 % at 0.3 h)."""
    t0 = time.perf_counter()
    rec = reconstruct(points, d)
    seconds = time.perf_counter() - t0
    t = rec.topology
    need = USED_NOISY if noise >= 0.3 else 1.0
    used = len(points) - t.unused_samples
    ok = bool(t.closed_manifold and tuple(t.betti) == tuple(betti) and used >= need * len(points) - 1e-9)
    u = rec.uncertain_features
    unc = tuple(sum(f.kind == k for f in u) for k in ("handle", "hole", "component"))
    # an empty M_S is no answer (FAILED) and names no features since session 32: flagged as it was before
    flagged = bool(u) or t.n_simplices == 0
    return Judged(ok, flagged, tuple(t.betti), unc, used, seconds)  # type: ignore[arg-type]


def seeds(doc: str | None, argv: list[str], default: int, what: str) -> int:
    """The ``--seeds N`` of a sweep's command line (the sweep's docstring's first line is its ``--help`` text)."""
    ap = argparse.ArgumentParser(description=(doc or "").split("\n")[0])
    ap.add_argument("--seeds", type=int, default=default, help=what)
    return ap.parse_args(argv).seeds
