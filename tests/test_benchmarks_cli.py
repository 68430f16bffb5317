"""The benchmarks that take case names answer --help and a wrong name with one line, not a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.mark.parametrize("script", ["bench_builtins.py", "bench_core.py", "bench_gudhi.py", "bench_scale.py"])
def test_unknown_case_is_one_line(script: str) -> None:
    proc = subprocess.run(
        [sys.executable, str(BENCH / script), "no-such-case"], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert "unknown" in proc.stderr and "'no-such-case'" in proc.stderr
    assert proc.stdout == ""


def test_help_lists_the_cases() -> None:
    proc = subprocess.run([sys.executable, str(BENCH / "bench_scale.py"), "--help"], capture_output=True, text=True)
    assert proc.returncode == 0
    assert "torus-300k" in proc.stdout and "klein-10k" in proc.stdout
