"""What the user has picked: a sample, a simplex, a (d-1)-face, or a feature of the result."""

from __future__ import annotations

from psygnal import Signal


class Selection:
    """Selection state shared by the view and the information panel.

    One thing is selected at a time: picking a sample, a simplex, a face or
    a feature replaces what was selected before.  ``simplex`` is a row of
    ``Candidates.faces`` (every candidate d-face, whatever the test);
    ``face`` is a sorted tuple of d sample indices; ``feature`` one of the
    result's features (a handle, hole or component: a row of the
    Information panel's list of uncertain ones, clicked).
    """

    #: Emitted after any change.
    changed = Signal()

    def __init__(self) -> None:
        self.sample: int | None = None
        self.simplex: int | None = None
        self.face: tuple[int, ...] | None = None
        self.feature: object | None = None

    def select_sample(self, i: int | None) -> None:
        self.simplex = self.face = self.feature = None
        self.sample = None if i is None else int(i)
        self.changed.emit()

    def select_simplex(self, f: int | None) -> None:
        self.sample = self.face = self.feature = None
        self.simplex = None if f is None else int(f)
        self.changed.emit()

    def select_face(self, face: tuple[int, ...] | None) -> None:
        self.sample = self.simplex = self.feature = None
        self.face = None if face is None else tuple(sorted(int(v) for v in face))
        self.changed.emit()

    def select_feature(self, feature: object | None) -> None:
        """Select one of the result's features (its samples are highlighted)."""
        self.sample = self.simplex = self.face = None
        self.feature = feature
        self.changed.emit()

    def clear(self) -> None:
        self.sample = self.simplex = None
        self.face = self.feature = None
        self.changed.emit()

    @property
    def empty(self) -> bool:
        return self.sample is None and self.simplex is None and self.face is None and self.feature is None
