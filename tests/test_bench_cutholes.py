"""bench_cutholes.py cuts the share of samples nearest its centre, and lists only closed single objects."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from bench_cutholes import closed_single, cut  # noqa: E402


def test_the_cut_takes_the_samples_nearest_the_centre() -> None:
    """Eleven samples on a line at 0, 1, ..., 10: a fifth of them around sample 0 are 0, 1 and 2 (distances up
    to the fifth quantile, 2); around sample 5, the samples 4, 5 and 6 (distances 0, 1, 1; the quantile is 1)."""
    pts = np.c_[np.arange(11.0), np.zeros(11), np.zeros(11)]
    assert cut(pts, 0, 0.2)[:, 0].tolist() == [3, 4, 5, 6, 7, 8, 9, 10]
    assert cut(pts, 5, 0.2)[:, 0].tolist() == [0, 1, 2, 3, 7, 8, 9, 10]


def test_only_closed_single_objects_are_cut(tmp_path: Path) -> None:
    truth = {
        "a.off": {"closed": True, "components": 1},
        "b.off": {"closed": True, "components": 26},
        "c.off": {"closed": False, "components": 1},
    }
    (tmp_path / "truth.json").write_text(json.dumps(truth))
    assert closed_single(tmp_path) == [tmp_path / "a.off"]
