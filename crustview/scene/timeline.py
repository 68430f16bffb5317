"""Per-step summaries of a recorded extraction (Qt-free): sizes, open faces, rules.

Everything here is computed once per extraction with a handful of numpy
passes, so a timeline over 20,000 steps costs milliseconds, not a replay.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.steps import Extraction
from . import geometry as geo


@dataclass(frozen=True)
class RuleCodes:
    """The rule of every step as a small integer.

    Attributes
    ----------
    names : tuple of str
        The rules that occur, in order of first use.
    codes : ndarray of shape (n_steps,)
        ``names[codes[j]]`` is the rule of step ``j``.
    """

    names: tuple[str, ...]
    codes: np.ndarray


def rule_codes(ext: Extraction) -> RuleCodes:
    """Code the rule of each step of ``ext``."""
    rules = [s.rule for s in ext.steps]
    names = tuple(dict.fromkeys(rules))
    index = {r: i for i, r in enumerate(names)}
    return RuleCodes(names, np.array([index[r] for r in rules], dtype=np.int64))


@dataclass(frozen=True)
class Timeline:
    """Counts at every position 0..n_steps of a replay.

    Attributes
    ----------
    size : ndarray of shape (n_steps + 1,)
        Number of d-simplices alive (|M_S| at that position).
    boundary : ndarray of shape (n_steps + 1,)
        (d-1)-faces in exactly one alive simplex.
    nonmanifold : ndarray of shape (n_steps + 1,)
        (d-1)-faces in more than two alive simplices.
    """

    size: np.ndarray
    boundary: np.ndarray
    nonmanifold: np.ndarray

    @property
    def n_steps(self) -> int:
        return len(self.size) - 1


def lifetimes(ext: Extraction) -> tuple[np.ndarray, np.ndarray]:
    """First and last position at which each simplex is alive.

    ``ext.alive(i)`` is ``first <= i <= last``; a simplex never alive has
    ``first > last``.
    """
    n = ext.n_steps
    first = np.zeros(len(ext.simplices), dtype=np.int64) if ext.added_at is None else np.asarray(ext.added_at)
    last = np.minimum(np.asarray(ext.removed_at, dtype=np.int64), n)
    return first.astype(np.int64), last


def timeline(ext: Extraction, incidence: np.ndarray | None = None) -> Timeline:
    """|M_S|, boundary faces and non-manifold faces after every number of steps.

    ``incidence``: the (d-1)-face of each simplex opposite each vertex, as
    from :func:`~crustview.scene.geometry.facets` (computed when None).

    Each simplex contributes +1 to each of its (d-1)-faces at its first
    position and -1 one position after its last.  Events are summed per
    (face, position), accumulated per face in time order, and every change
    of a face's count across 1 or 2 updates the two face counts.
    """
    n = ext.n_steps
    first, last = lifetimes(ext)
    live = first <= last
    size = np.zeros(n + 2, dtype=np.int64)
    np.add.at(size, first[live], 1)
    np.add.at(size, last[live] + 1, -1)
    size = np.cumsum(size)[: n + 1]
    if not live.any():
        zero = np.zeros(n + 1, dtype=np.int64)
        return Timeline(size, zero, zero.copy())
    inc = geo.facets(ext.simplices)[1] if incidence is None else incidence
    per = inc.shape[1]
    f = inc[live].ravel()
    t_on = np.repeat(first[live], per)
    t_off = np.repeat(last[live] + 1, per)
    keep_off = t_off <= n
    face = np.concatenate([f, f[keep_off]])
    when = np.concatenate([t_on, t_off[keep_off]])
    delta = np.concatenate([np.ones(len(f), dtype=np.int64), -np.ones(int(keep_off.sum()), dtype=np.int64)])
    key = face * (n + 2) + when
    ukey, inv = np.unique(key, return_inverse=True)
    d = np.bincount(inv, weights=delta).astype(np.int64)
    uface, uwhen = ukey // (n + 2), ukey % (n + 2)
    run = np.cumsum(d)
    start = np.flatnonzero(np.r_[True, uface[1:] != uface[:-1]])
    base = np.repeat(run[start] - d[start], np.diff(np.r_[start, len(d)]))
    after = run - base
    before = after - d
    b = (after == 1).astype(np.int64) - (before == 1)
    m = (after > 2).astype(np.int64) - (before > 2)
    boundary = np.cumsum(np.bincount(uwhen, weights=b, minlength=n + 2).astype(np.int64))[: n + 1]
    nonmanifold = np.cumsum(np.bincount(uwhen, weights=m, minlength=n + 2).astype(np.int64))[: n + 1]
    return Timeline(size, boundary, nonmanifold)
