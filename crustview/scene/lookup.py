"""Selecting by typed index: a sample, a (d-1)-face or a d-simplex, as the inspector names them (Qt-free)."""

from __future__ import annotations

import re

import numpy as np

from . import geometry as geo


def select_by_text(model, text: str) -> tuple[str, np.ndarray] | str:
    """Select what ``text`` names in ``model.selection``.

    ``"12"`` or ``"sample 12"``: sample 12; ``"r 7"``, ``"r7"``, ``"row 7"``, ``"rows 7"`` or
    ``"(input row 7)"``: the sample of the input's row 7 (rows from 0, as the inspector's "input row" counts
    them; samples are numbered in spatial order, and repeated rows share one sample; a built-in's rows are
    its drawn points); ``"s 40"``/``"simplex 40"``: T_S
    simplex 40 (the number the steps use); ``d + 1`` numbers (``"12 40 41"``,
    ``"(12, 40, 41)"``): the simplex on those samples; ``d`` numbers: that
    (d-1)-face.  Returns ``(kind, samples)`` with the sample indices to frame,
    or one sentence saying why nothing was selected.
    """
    rec = model.rec
    if rec is None:
        return "nothing is shown yet"
    words = text.strip().lower().strip("()[] ")
    nums = [int(v) for v in re.findall(r"-?\d+", words)]
    by_row = re.match(r"^(input\s*)?(r|rows?)(\b|\d)", words) is not None
    if not nums:
        return (
            f"type a sample number (0 … {rec.n - 1}), 'r N' for the input's row N, or the {rec.d + 1} samples "
            "of a simplex"
        )
    if any(v < 0 for v in nums):
        return "indices are 0 or more"
    sel = model.selection
    ext = rec.extraction
    if by_row:
        rows = len(rec.input_index)
        if len(nums) != 1:
            return "give one row number after 'r'"
        r = nums[0]
        if r >= rows:
            return f"the input has {rows:,} rows (0 … {rows - 1})"
        i = int(rec.input_index[r])
        sel.select_sample(i)
        return "sample", np.array([i])
    if len(nums) == 1 and re.match(r"^(s|simplex|t_s|ts)\b", words):
        e = nums[0]
        if e >= len(ext.simplices):
            return f"T_S has simplices 0 … {len(ext.simplices) - 1}"
        row = model.candidate_row(e)
        if row < 0:
            return f"T_S simplex {e} is not a Delaunay face of this test"
        sel.select_simplex(row)
        return "simplex", np.asarray(ext.simplices[e])
    if len(nums) == 1:
        i = nums[0]
        if i >= rec.n:
            return f"there are {rec.n:,} samples (0 … {rec.n - 1})"
        sel.select_sample(i)
        return "sample", np.array([i])
    if max(nums) >= rec.n:
        return f"there are {rec.n:,} samples (0 … {rec.n - 1})"
    if len(nums) == rec.d + 1:
        row = int(geo.find_rows(rec.candidates.faces, np.array(nums)[None])[0])
        if row < 0:
            return f"{tuple(nums)} is not a Delaunay {rec.d}-simplex of these samples"
        sel.select_simplex(row)
        return "simplex", np.array(nums)
    if len(nums) == rec.d:
        sel.select_face(tuple(sorted(nums)))
        return "face", np.array(nums)
    return f"a simplex has {rec.d + 1} samples and a face {rec.d}; got {len(nums)} numbers"
