"""Replay of the recorded steps of Algorithm 3 (Qt-free)."""

from __future__ import annotations

from psygnal import Signal

from ..core.result import Extraction, Step


class StepPlayer:
    """Position in the recorded extraction, with play/pause.

    The position ``i`` runs from 0 (the candidate complex T_S, nothing done)
    to ``n_steps`` (the final M_S).  At position ``i`` the complex shown is
    ``extraction.alive(i)`` and the *current step* is ``steps[i - 1]``, the
    step that has just been applied (none at position 0).

    A Qt timer calls :meth:`tick` while :attr:`playing`; :attr:`speed` is in
    steps per second.
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
        self.playing = False
        self.speed = float(speed)
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

    def set_extraction(self, extraction: Extraction | None, position: int = 0) -> None:
        """Replace the recorded extraction and go to ``position``."""
        self.pause()
        self.extraction = extraction
        self.position = max(0, min(int(position), self.n_steps))
        self.extraction_changed.emit(self.n_steps)
        self.step_changed.emit(self.position)

    # -- moving ----------------------------------------------------------
    def set_step(self, i: int) -> None:
        """Go to position ``i`` (clamped to ``0..n_steps``)."""
        i = max(0, min(int(i), self.n_steps))
        if i != self.position:
            self.position = i
            self.step_changed.emit(i)

    def first(self) -> None:
        self.set_step(0)

    def last(self) -> None:
        self.set_step(self.n_steps)

    def next(self) -> None:
        self.set_step(self.position + 1)

    def prev(self) -> None:
        self.set_step(self.position - 1)

    def next_of_rule(self, rule: str) -> int | None:
        """Position just after the next step (from here on) that used ``rule``.

        Returns None when there is no such step; does not move.
        """
        if self.extraction is None:
            return None
        for j in range(self.position, self.n_steps):
            if self.extraction.steps[j].rule == rule:
                return j + 1
        return None

    def run_to_rule(self, rule: str) -> bool:
        """Jump to :meth:`next_of_rule`; returns False when there is none."""
        j = self.next_of_rule(rule)
        if j is None:
            return False
        self.set_step(j)
        return True

    # -- playback --------------------------------------------------------
    def play(self) -> None:
        if self.n_steps == 0:
            return
        if self.position >= self.n_steps:
            self.set_step(0)
        if not self.playing:
            self.playing = True
            self.playing_changed.emit(True)

    def pause(self) -> None:
        if self.playing:
            self.playing = False
            self.playing_changed.emit(False)

    def toggle(self) -> None:
        self.pause() if self.playing else self.play()

    def tick(self, n: int = 1) -> None:
        """Advance ``n`` steps while playing; stops at the end."""
        if not self.playing:
            return
        self.set_step(self.position + n)
        if self.position >= self.n_steps:
            self.pause()
