"""Which samples the per-sample glyph layers draw when all of them would be too many.

Normal planes and "all poles" are one glyph per sample: a million glyphs
cost seconds per frame in software OpenGL and cover each other anyway.  Above
:data:`GLYPH_LIMIT` samples these layers draw an even subset (every s-th
sample, so density stays uniform over the shape) and say so: the layer's
``count`` is what is drawn, ``total`` what the layer holds, and ``note`` one
sentence for the layer panel and the view.
"""

from __future__ import annotations

import math

import numpy as np

#: Most glyphs a per-sample layer draws.
GLYPH_LIMIT = 100_000


def even_subset(n: int, limit: int | None = None) -> np.ndarray:
    """Every ``ceil(n / limit)``-th index of ``range(n)`` (all of them when ``n <= limit``).

    ``limit`` defaults to :data:`GLYPH_LIMIT` (read at call time).
    """
    limit = GLYPH_LIMIT if limit is None else limit
    return np.arange(0, n, max(1, math.ceil(n / max(limit, 1))), dtype=np.int64)


def subset_note(what: str, drawn: int, total: int) -> str:
    """The sentence a layer shows when it draws ``drawn`` of its ``total`` elements ('' if all)."""
    if drawn >= total:
        return ""
    return (
        f"{what}: drawn {drawn:,} of {total:,} (every {math.ceil(total / max(drawn, 1))}th sample), "
        "too many to draw whole"
    )
