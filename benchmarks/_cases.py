"""Command line of the benchmarks that take case names: ``--help`` and one clear line for a wrong name."""

from __future__ import annotations

import argparse
from collections.abc import Iterable


def case_names(doc: str | None, known: Iterable[str], argv: list[str], what: str = "case") -> list[str]:
    """The case names given on the command line (every known one when none is), checked.

    Parameters
    ----------
    doc : str or None
        The benchmark's module docstring (its first line is the ``--help`` description).
    known : iterable of str
        The names the benchmark knows, in its own order.
    argv : list of str
        The arguments after the program name.
    what : str
        What a name names ("case", "manifold"), for the help text.

    Returns
    -------
    list of str
        The names to run, in the order given.  An unknown name exits with
        argparse's one-line error (status 2) listing the known ones.
    """
    known = list(known)
    first = (doc or "").strip().splitlines()[0] if doc else None
    ap = argparse.ArgumentParser(description=first, epilog=f"{what}s: {' '.join(known)}")
    ap.add_argument("names", nargs="*", metavar=what, help=f"{what}s to run (default: all)")
    names = ap.parse_args(argv).names
    bad = [n for n in names if n not in known]
    if bad:
        ap.error(f"unknown {what} {' '.join(bad)!r}; known: {' '.join(known)}")
    return names or known
