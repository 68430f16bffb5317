"""Framing the data clear of the text over the view: the legend, the caption, the colour bars.

The legend and its notes stand in the upper-left corner and are drawn over
the geometry (:mod:`.overlay`), so a camera that fills the view with the data
puts the top of a tall scan under them.  :func:`fit_clear` moves and scales
the data's image into the largest part of the view those blocks leave free:
it shifts the camera's window centre (a pure translation of the image, so
rotating still turns the data about its own centre) and dollies the camera.
"""

from __future__ import annotations

import numpy as np

#: Pixels kept between the data and the view's edges or a block of text.
MARGIN = 6.0
#: Smallest free rectangle (its smaller side, as a share of the view's) the data is moved into.
SMALLEST_FREE = 0.45
#: Most points projected to measure the data's image.
MEASURED = 20_000

Rect = tuple[float, float, float, float]  # x0, y0, x1, y1 in display pixels (origin bottom-left)


def text_block(actors, renderer) -> Rect | None:
    """The display rectangle covered by 2-D text actors (None when there are none)."""
    boxes = []
    for a in actors:
        if not a.GetVisibility() or not a.GetInput():
            continue
        size = [0.0] * 4
        a.GetBoundingBox(renderer, size)
        x, y = a.GetPositionCoordinate().GetComputedDisplayValue(renderer)
        boxes.append((x + size[0], y + size[2], x + size[1], y + size[3]))
    if not boxes:
        return None
    b = np.array(boxes)
    return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


def largest_free_rect(width: float, height: float, blocks: list[Rect]) -> Rect:
    """The rectangle of the view that meets no block and has the largest smaller side.

    Candidates are bounded by the view's edges and the blocks' edges.
    """
    xs0 = sorted({0.0} | {b[2] for b in blocks if b[2] < width})
    xs1 = sorted({width} | {b[0] for b in blocks if b[0] > 0})
    ys0 = sorted({0.0} | {b[3] for b in blocks if b[3] < height})
    ys1 = sorted({height} | {b[1] for b in blocks if b[1] > 0})
    best, best_side = (0.0, 0.0, width, height), -1.0
    for x0 in xs0:
        for x1 in xs1:
            if x1 <= x0:
                continue
            for y0 in ys0:
                for y1 in ys1:
                    if y1 <= y0:
                        continue
                    if any(x0 < b[2] and b[0] < x1 and y0 < b[3] and b[1] < y1 for b in blocks):
                        continue
                    side = min(x1 - x0, y1 - y0)
                    if side > best_side:
                        best, best_side = (x0, y0, x1, y1), side
    return best


def display_points(renderer, pts: np.ndarray) -> np.ndarray:
    """Display coordinates (pixels, origin bottom-left) of world points, shape (m, 2)."""
    w, h = renderer.GetSize()
    cam = renderer.GetActiveCamera()
    m = cam.GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1, 1)
    mat = np.array([[m.GetElement(i, j) for j in range(4)] for i in range(4)])
    hom = np.c_[pts, np.ones(len(pts))] @ mat.T
    ndc = hom[:, :2] / hom[:, 3:4]
    return np.c_[(ndc[:, 0] + 1) * w / 2, (ndc[:, 1] + 1) * h / 2]


def fit_clear(renderer, pts: np.ndarray, blocks: list[Rect], rounds: int = 3) -> float:
    """Scale and shift the image of ``pts`` into the largest rectangle free of ``blocks``.

    The camera must already look at the data (its focal point at the data's
    centre).  Only makes the image smaller, never larger.  Returns the scale
    applied (1.0: nothing was in the way).
    """
    w, h = renderer.GetSize()
    cam = renderer.GetActiveCamera()
    if len(pts) == 0 or w < 50 or h < 50:
        return 1.0
    if len(pts) > MEASURED:
        pts = pts[np.linspace(0, len(pts) - 1, MEASURED).astype(np.int64)]
    x0, y0, x1, y1 = largest_free_rect(w, h, blocks)
    if min(x1 - x0, y1 - y0) < SMALLEST_FREE * min(w, h):
        return 1.0  # so much text that the data would shrink to a stamp: better partly under it
    x0, y0, x1, y1 = x0 + MARGIN, y0 + MARGIN, x1 - MARGIN, y1 - MARGIN
    total = 1.0
    for _ in range(rounds):
        xy = display_points(renderer, pts)
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        if lo[0] >= x0 - 1 and hi[0] <= x1 + 1 and lo[1] >= y0 - 1 and hi[1] <= y1 + 1:
            break
        size = np.maximum(hi - lo, 1.0)
        s = min(1.0, (x1 - x0) / size[0], (y1 - y0) / size[1])
        if s < 1.0:
            total *= s
            if cam.GetParallelProjection():
                cam.SetParallelScale(cam.GetParallelScale() / s)
            else:
                cam.Dolly(s)  # moves towards the focal point by a factor: < 1 moves away
        renderer.ResetCameraClippingRange()
        xy = display_points(renderer, pts)
        centre = (xy.min(axis=0) + xy.max(axis=0)) / 2
        dx, dy = (x0 + x1) / 2 - centre[0], (y0 + y1) / 2 - centre[1]
        wx, wy = cam.GetWindowCenter()
        cam.SetWindowCenter(wx - 2 * dx / w, wy - 2 * dy / h)
    renderer.ResetCameraClippingRange()
    return total
