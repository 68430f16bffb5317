"""Rule ``drop-stray``: removing stray components (the robust extension's last phase).

A component far smaller than the largest (a seed that closed three or four
samples into a tiny loop or bubble) is removed, and its samples go to
``insert-sample`` (:mod:`.insert_sample`).  The method here is mixed into
:class:`~.patcher.Patcher`, whose :class:`~.complex.EditableComplex` it edits.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..paper.facets import facet_structure

#: Components with fewer simplices than this, and under STRAY_SHARE of the largest, are stray.
STRAY_MAX = 128
STRAY_SHARE = 0.05


class DropStray:
    """``drop-stray`` for :class:`~.patcher.Patcher` (see the module docstring)."""

    # -- stray components ------------------------------------------------------
    def drop_small_components(self) -> int:
        """Remove components far smaller than the largest; returns how many.

        A component with fewer than :data:`STRAY_MAX` simplices and under
        :data:`STRAY_SHARE` of the largest one is a stray piece that a seed
        grew in an undersampled spot (three samples closed into a tiny loop,
        four into a tetrahedron).  Its samples go back to ``insert-sample``.
        """
        ids = np.flatnonzero(np.fromiter(self.alive, dtype=bool, count=len(self.alive)))
        if len(ids) == 0:
            return 0
        simp = self.rows(ids)
        _, _, ptr, inc = facet_structure(simp)
        cnt = np.diff(ptr)
        two = np.flatnonzero(cnt == 2)
        a, b = inc[ptr[two]], inc[ptr[two] + 1]
        graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(len(ids), len(ids)))
        n_comp, label = connected_components(graph, directed=False)
        if n_comp < 2:
            return 0
        sizes = np.bincount(label)
        largest = int(sizes.max())
        dropped = 0
        # labels number the components in the order of their first simplex
        for lab in np.flatnonzero((sizes < STRAY_MAX) & (sizes < STRAY_SHARE * largest)).tolist():
            comp = ids[label == lab].tolist()
            for i in comp:
                self._delete(i)
            self.log.append(
                (
                    "drop-stray",
                    self.simp[comp[0]],
                    (),
                    tuple(comp),
                    float("nan"),
                    f"a stray component of {len(comp)} simplices (the largest has {largest}) "
                    "was removed; its samples are inserted into the rest",
                )
            )
            dropped += 1
        return dropped
