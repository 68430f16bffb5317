"""Longer fuzzing of crustview's readers than the test suite's 2,000 derandomized cases per reader.

    .venv/bin/python scripts/fuzz_readers.py                 # 20,000 fresh cases for every reader
    .venv/bin/python scripts/fuzz_readers.py -n 100000 ply-binary pcd

Each case is checked as in ``tests/test_fuzz_readers.py`` (``tests/fuzzing.py``:
a valid point set or one error line, a time and a memory bound).  The first
failing case of a reader is shrunk by hypothesis and printed, and its bytes
are saved to ``fuzz-failure-READER.bin``; the exit status is 1 when any
reader failed.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from fuzzing import READERS, cases, check_case  # noqa: E402
from hypothesis import HealthCheck, given, settings  # noqa: E402


def fuzz(reader: str, n: int) -> tuple[dict, BaseException | None]:
    counts = {"ok": 0, "error": 0}
    failure: list[bytes] = []
    with tempfile.TemporaryDirectory() as folder:

        @settings(
            max_examples=n,
            deadline=None,
            database=None,
            suppress_health_check=list(HealthCheck),
        )
        @given(cases(reader))
        def run(data):
            try:
                counts[check_case(reader, data, Path(folder))] += 1
            except BaseException:
                failure[:] = [data]
                raise

        try:
            run()
        except BaseException as err:  # noqa: BLE001 - reported, with the shrunk case
            if failure:
                Path(f"fuzz-failure-{reader}.bin").write_bytes(failure[0])
            return counts, err
    return counts, None


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("readers", nargs="*", help="readers to fuzz (default: all)")
    parser.add_argument("-n", type=int, default=20000, help="cases per reader (default: 20,000)")
    args = parser.parse_args()
    failed = 0
    for reader in args.readers or list(READERS):
        start = time.perf_counter()
        counts, err = fuzz(reader, args.n)
        total = counts["ok"] + counts["error"]
        line = f"{reader:<11} {total:>7} cases ({counts['ok']} read, {counts['error']} errors) in "
        line += f"{time.perf_counter() - start:.0f} s"
        if err is not None:
            failed += 1
            line += f": FAILED {type(err).__name__}: {' '.join(str(err).split())[:300]}"
        print(line, flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
