"""Every reader against fuzzed bytes: a valid point set or one error line, never anything else.

2,000 cases per reader here, drawn by ``tests/fuzzing.seeded_cases`` from a
fixed seed (so a CI run is repeatable, and a failure names the case's
index); ``scripts/fuzz_readers.py`` runs more with hypothesis's fresh
randomness and shrinks a failure.  See ``tests/fuzzing.py`` for the seeds,
the mutations and the time and memory bounds of each case.
"""

import tempfile
from pathlib import Path

import pytest
from fuzzing import READERS, check_case, seeded_cases

CASES = 2000

pytestmark = pytest.mark.fuzz


@pytest.mark.parametrize("reader", list(READERS))
def test_fuzzed_bytes_give_points_or_one_error_line(reader):
    counts = {"ok": 0, "error": 0}
    with tempfile.TemporaryDirectory() as folder:
        for index, data in enumerate(seeded_cases(reader, CASES)):
            try:
                counts[check_case(reader, data, Path(folder))] += 1
            except BaseException as err:
                raise AssertionError(f"{reader} case {index} ({len(data)} bytes, {data[:80]!r}...): {err}") from err
    print(f"{reader}: {CASES} cases, {counts['ok']} read, {counts['error']} one-line errors")
    assert counts["ok"] + counts["error"] == CASES
    assert counts["error"] > 0  # the mutations do break files
    assert counts["ok"] > 0  # and some mutated files still read
