"""The robust extension's last phase: closing small holes, dropping strays, taking in left-out samples.

Works on the complex that :mod:`crustview.core.robust.grow` produced, as an
:class:`~.complex.EditableComplex` (a dictionary of (d-1)-faces, so that
simplices outside the Delaunay triangulation can be added where no Delaunay
face fits), with one mixin per rule of the step log:

* ``fill-hole`` (:mod:`.fill_hole`): a hole with at most
  :data:`~.fill_hole.FILL_MAX_FACES` faces and a span of at most
  :data:`~.fill_hole.FILL_MAX_SPAN` sample spacings is an undersampling gap
  and is closed; larger holes are real boundary and stay open, except a
  *slit*, one long rim loop only a few spacings wide.
* ``drop-stray`` (:mod:`.drop_stray`): a component far smaller than the
  largest is removed, and its samples go to ``insert-sample``.
* ``insert-sample`` (:mod:`.insert_sample`): a sample that is no vertex of
  M_S and lies within :data:`~.insert_sample.INSERT_MAX` spacings of it is
  made a vertex by a stellar subdivision of the nearest face, which keeps a
  manifold a manifold in every dimension.
"""

from __future__ import annotations

from .complex import EditableComplex
from .drop_stray import DropStray
from .fill_chain import ChainFill
from .fill_cone import ConeFill
from .fill_hole import FillHole
from .insert_sample import SampleInsertion

#: Rounds of hole filling, sample insertion, unpinching and stray dropping (each can leave
#: work for the others; real scans settle in two or three).
PATCH_ROUNDS = 5


class Patcher(FillHole, ConeFill, ChainFill, DropStray, SampleInsertion, EditableComplex):
    """M_S as an :class:`~.complex.EditableComplex`, with the rules of the last phase as methods."""

    def settle(self) -> list[int]:
        """Close small holes, insert left-out samples, unpinch and drop strays until nothing changes.

        Returns the samples still left out.
        """
        self.drop_small_components()
        left: list[int] = []
        for _ in range(PATCH_ROUNDS):  # closing, inserting, unpinching and dropping can each leave work for the others
            for _ in range(4):  # eroding one hole can reach another: repeat while something closes
                before = len(self.bset)
                for hole in self.holes():
                    self.fill(hole)
                if len(self.bset) in (0, before):
                    break
            left = self.insert_unused()
            # unpinching frees samples and opens holes; the last filling can close off a stray bubble
            changed = self.unpinch_all()
            changed = self.drop_small_components() or changed
            if not changed:
                break
        else:
            left = self.insert_unused()
        return left
