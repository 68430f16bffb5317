"""Replay of the recorded steps of Algorithm 3 (Qt-free)."""

from __future__ import annotations

import numpy as np
from psygnal import Signal

from ..core.steps import Extraction, Step


class StepPlayer:
    """Position in the recorded extraction, with play/pause.

    The position ``i`` runs from 0 (the candidate complex T_S, nothing done; an empty M_S where the robust
    extension builds it anew) to ``n_steps`` (the final M_S).  At position ``i`` the complex shown is
    ``extraction.alive(i)`` and the *current step* is ``steps[i - 1]``, the
    step that has just been applied (none at position 0).

    A Qt timer calls :meth:`advance` while :attr:`playing`, at most at the
    display rate, with the time since the last call; :attr:`speed` is in
    steps per second.  Steps between two frames are applied without being
    drawn (the complex at any position is one comparison away).  With
    :attr:`rule` set, playback and :meth:`advance` visit only steps of that
    rule.
    """

    #: Emitted with the new position.
    step_changed = Signal(int)
    #: Emitted with True/False when playback starts or stops.
    playing_changed = Signal(bool)
    #: Emitted with the new number of steps when the extraction is replaced.
    extraction_changed = Signal(int)

    def __init__(self, extraction: Extraction | None = None, speed: float = 10.0) -> None:
        self.extraction: Extraction | None = None
        self.position = 0
        self.delivered = False
        self.playing = False
        self.speed = float(speed)
        #: Play only the steps of this rule (None: every step).
        self.rule: str | None = None
        #: Play only these steps (sorted step indices, e.g. one prune cascade's) until playback stops.
        self.only: np.ndarray | None = None
        self._rules: np.ndarray = np.zeros(0, dtype=object)
        self._owed = 0.0
        #: Steps applied by playback since :meth:`play` (for the "drawing 1 in N" readout).
        self.applied = 0
        self.set_extraction(extraction)

    # -- data ------------------------------------------------------------
    @property
    def n_steps(self) -> int:
        return 0 if self.extraction is None else self.extraction.n_steps

    @property
    def current_step(self) -> Step | None:
        """The step that produced the complex at the current position."""
        if self.extraction is None or self.position == 0:
            return None
        return self.extraction.steps[self.position - 1]

    @property
    def shown_step(self) -> Step | None:
        """The step whose simplices the views mark (tau, removed now, added now).

        :attr:`current_step`, except on a result just delivered at its end (:meth:`set_extraction` at
        ``n_steps``), shown clean until the position moves.  The last step's markers over a finished result
        read as part of it (an open scan's opening drawn as a red lid: the cap ``open-cap`` removed).
        """
        return None if self.delivered else self.current_step

    def set_extraction(self, extraction: Extraction | None, position: int = 0) -> None:
        """Replace the recorded extraction and go to ``position``."""
        self.pause()
        self.extraction = extraction
        self._rules = np.array([st.rule for st in extraction.steps] if extraction else [], dtype=object)
        self.position = max(0, min(int(position), self.n_steps))
        #: At the final M_S as delivered, not moved since (see :attr:`shown_step`).
        self.delivered = extraction is not None and self.position == self.n_steps
        self.extraction_changed.emit(self.n_steps)
        self.step_changed.emit(self.position)

    # -- moving ----------------------------------------------------------
    def set_step(self, i: int) -> None:
        """Go to position ``i`` (clamped to ``0..n_steps``)."""
        i = max(0, min(int(i), self.n_steps))
        if i != self.position:
            self.position = i
            self.delivered = False
            self.step_changed.emit(i)
        elif self.delivered:  # asked for the last step itself (End, its row, the slider): its markers too
            self.delivered = False
            self.step_changed.emit(i)

    def first(self) -> None:
        self.set_step(0)

    def last(self) -> None:
        self.set_step(self.n_steps)

    def next(self) -> None:
        self.set_step(self.position + 1)

    def prev(self) -> None:
        self.set_step(self.position - 1)

    def next_of_rule(self, rule: str, count: int = 1) -> int | None:
        """Position just after the ``count``-th next step (from here on) that used ``rule``.

        Returns None when there is no such step; does not move.  With fewer
        than ``count`` such steps left, the last of them.
        """
        if self.extraction is None:
            return None
        later = np.flatnonzero(self._rules[self.position :] == rule)
        if len(later) == 0:
            return None
        return self.position + int(later[min(count, len(later)) - 1]) + 1

    def run_to_rule(self, rule: str) -> bool:
        """Jump to :meth:`next_of_rule`; returns False when there is none."""
        j = self.next_of_rule(rule)
        if j is None:
            return False
        self.set_step(j)
        return True

    def _next_only(self, count: int = 1) -> int | None:
        """Position just after the ``count``-th next step of :attr:`only` (None when none is left)."""
        pos = np.asarray(self.only) + 1
        later = pos[pos > self.position]
        if len(later) == 0:
            return None
        return int(later[min(count, len(later)) - 1])

    # -- playback --------------------------------------------------------
    def play_only(self, steps) -> None:
        """Play ``steps`` (step indices, e.g. a prune cascade's) alone, from just before the first of them."""
        steps = np.unique(np.asarray(steps, dtype=np.int64))
        steps = steps[(steps >= 0) & (steps < self.n_steps)]
        if len(steps) == 0:
            return
        self.pause()
        self.only = steps
        self.set_step(int(steps[0]))
        self.play()

    def play(self) -> None:
        if self.n_steps == 0:
            return
        if self.only is not None:
            if self._next_only() is None:
                self.set_step(int(self.only[0]))
        elif self.position >= self.n_steps or (self.rule and self.next_of_rule(self.rule) is None):
            self.set_step(0)
        self._owed = 0.0
        self.applied = 0
        if not self.playing:
            self.playing = True
            self.playing_changed.emit(True)

    def pause(self) -> None:
        self.only = None  # playing one cascade alone ends with its playback
        if self.playing:
            self.playing = False
            self.playing_changed.emit(False)

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def tick(self, n: int = 1) -> None:
        """Advance ``n`` steps (of :attr:`rule`, when set) while playing; stops at the end."""
        if not self.playing or n <= 0:
            return
        before = self.position
        if self.only is not None:
            j = self._next_only(n)
            if j is None:
                self.pause()
                return
            self.applied += int(np.count_nonzero((self.only + 1 > before) & (self.only + 1 <= j)))
            self.set_step(j)
            if self._next_only() is None:
                self.pause()
            return
        if self.rule:
            j = self.next_of_rule(self.rule, n)
            if j is None:
                self.pause()
                return
            self.set_step(j)
            self.applied += int(np.count_nonzero(self._rules[before:j] == self.rule))
            if self.next_of_rule(self.rule) is None:
                self.pause()
            return
        self.set_step(self.position + n)
        self.applied += self.position - before
        if self.position >= self.n_steps:
            self.pause()

    def advance(self, seconds: float) -> int:
        """Play on by ``seconds`` of wall time at :attr:`speed`; returns the steps applied.

        Fractions of a step are carried to the next call, so the rate is
        exact whatever the frame rate: at 1,000 steps/s and 20 frames/s each
        frame applies 50 steps and draws only the last.
        """
        if not self.playing:
            return 0
        self._owed += max(0.0, float(seconds)) * self.speed
        n = int(self._owed)
        self._owed -= n
        before = self.applied
        self.tick(n)
        return self.applied - before
