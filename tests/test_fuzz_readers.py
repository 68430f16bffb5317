"""Every reader against fuzzed bytes (hypothesis): a valid point set or one error line, never anything else.

2,000 cases per reader here (derandomized, so a CI run is repeatable);
``scripts/fuzz_readers.py`` runs more with fresh randomness.  See
``tests/fuzzing.py`` for the seeds, the mutations and the time and memory
bounds of each case.
"""

import tempfile
from pathlib import Path

import pytest
from fuzzing import READERS, cases, check_case
from hypothesis import HealthCheck, given, settings

CASES = 2000

pytestmark = pytest.mark.fuzz


@pytest.mark.parametrize("reader", list(READERS))
def test_fuzzed_bytes_give_points_or_one_error_line(reader):
    counts = {"ok": 0, "error": 0}
    with tempfile.TemporaryDirectory() as folder:

        @settings(
            max_examples=CASES,
            deadline=None,  # the time bound is check_case's alarm (TIME_LIMIT), not hypothesis's
            derandomize=True,
            database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
        )
        @given(cases(reader))
        def run(data):
            counts[check_case(reader, data, Path(folder))] += 1

        run()
    total = counts["ok"] + counts["error"]
    print(f"{reader}: {total} cases, {counts['ok']} read, {counts['error']} one-line errors")
    assert total >= CASES
    assert counts["error"] > 0  # the mutations do break files
