"""A replayable step log over face tuples, assembled into an :class:`~crustview.core.steps.Extraction`.

The labelling rules (:mod:`.cells`) change M_S by whole sets of faces.
:class:`StepLog` takes each step as the faces it adds and removes, gives
every face a row of :attr:`Extraction.simplices` (the rows of T_S first, as in
paper mode, then every other face in the order it first appears; a face
added again after its removal gets a new row), and fills ``added_at`` and
``removed_at`` so that the viewer replays the run like any other.
"""

from __future__ import annotations

import numpy as np

from ..steps import Extraction, Step
from ..util.rows import row_keys

Face = tuple[int, ...]


class StepLog:
    """Steps of a robust run as added and removed faces.

    Parameters
    ----------
    candidates : ndarray of shape (t, d + 1)
        T_S, sorted rows: the first rows of the result.
    n_points : int
    """

    def __init__(self, candidates: np.ndarray, n_points: int) -> None:
        self.n = int(n_points)
        self.ts = np.asarray(candidates, dtype=np.int64)
        self.dp1 = self.ts.shape[1]
        keys = _keys(self.ts, self.n)
        self._order = np.argsort(keys, kind="stable")
        self._sorted = keys[self._order]
        self.rows: list[np.ndarray] = []  # faces beyond T_S, in blocks
        self.n_rows = len(self.ts)
        self.removed_at: dict[int, int] = {}
        self.alive: dict[Face, int] = {}
        self.used_ts = np.zeros(len(self.ts), bool)
        self.steps: list[Step] = []
        self._added: list[tuple[np.ndarray, int]] = []

    def _rows_for(self, faces: np.ndarray) -> np.ndarray:
        """Rows for faces being added: their T_S row if unused so far, else new rows."""
        faces = np.sort(np.asarray(faces, dtype=np.int64).reshape(-1, self.dp1), axis=1)
        rows = np.full(len(faces), -1, np.int64)
        if len(self.ts) and len(faces):
            k = _keys(faces, self.n)
            j = np.minimum(np.searchsorted(self._sorted, k), len(self._sorted) - 1)
            hit = self._sorted[j] == k
            cand = self._order[j]
            ok = hit & ~self.used_ts[cand]
            # two equal faces in one step cannot both take the row
            _, first = np.unique(cand[ok], return_index=True)
            take = np.zeros(len(faces), bool)
            take[np.flatnonzero(ok)[first]] = True
            rows[take] = cand[take]
            self.used_ts[cand[take]] = True
        new = rows < 0
        if new.any():
            rows[new] = self.n_rows + np.arange(int(new.sum()))
            self.n_rows += int(new.sum())
            self.rows.append(faces[new])
        return rows

    def step(self, rule: str, tau: Face, added: np.ndarray, removed: np.ndarray, angle: float, why: str) -> None:
        """Record one step: ``added`` and ``removed`` are faces (rows of vertex ids)."""
        idx = len(self.steps)
        rem_rows = []
        for f in np.sort(np.asarray(removed, dtype=np.int64).reshape(-1, self.dp1), axis=1).tolist():
            r = self.alive.pop(tuple(f), None)
            if r is not None:
                self.removed_at[r] = idx
                rem_rows.append(r)
        add = np.sort(np.asarray(added, dtype=np.int64).reshape(-1, self.dp1), axis=1)
        rows = self._rows_for(add)
        self.alive.update(zip(map(tuple, add.tolist()), rows.tolist()))
        self._added.append((rows, idx + 1))
        self.steps.append(
            Step(idx, rule, tuple(int(x) for x in tau), (), tuple(rem_rows), angle, why, added=tuple(rows.tolist()))
        )

    def faces(self) -> np.ndarray:
        """The alive faces now (sorted rows)."""
        if not self.alive:
            return np.zeros((0, self.dp1), np.int64)
        return np.array(list(self.alive.keys()), dtype=np.int64)

    def extraction(self, stopped: str, notes: list[str] | None = None) -> Extraction:
        """The run as an Extraction (``mode = "robust"``)."""
        n_steps = len(self.steps)
        simplices = np.vstack([self.ts, *self.rows]) if self.rows else self.ts.copy()
        simplices = simplices.reshape(-1, self.dp1)
        added_at = np.full(len(simplices), n_steps + 1, np.int64)
        for rows, at in self._added:
            added_at[rows] = np.minimum(added_at[rows], at)
        removed_at = np.full(len(simplices), n_steps, np.int64)
        if self.removed_at:
            r = np.fromiter(self.removed_at.keys(), np.int64)
            removed_at[r] = np.fromiter(self.removed_at.values(), np.int64)
        in_ts = np.arange(len(simplices)) < len(self.ts)
        ext = Extraction(
            simplices, self.steps, removed_at, stopped, added_at=added_at, mode="robust", in_candidates=in_ts
        )
        ext.notes.extend(notes or [])
        return ext


def _keys(rows: np.ndarray, base: int) -> np.ndarray:
    """One comparable key per sorted row."""
    k = row_keys(rows, base)
    if k is None:
        k = np.array([r.tobytes() for r in np.ascontiguousarray(rows)])
    return k
