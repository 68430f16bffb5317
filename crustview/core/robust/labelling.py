"""Rule ``label-cells``: every Delaunay cell labelled inside or outside, M_S their common faces.

Why a labelling
---------------
For a hypersurface (codimension 1) the object it bounds is a union of Delaunay
k-cells.  If every cell is labelled inside or outside, the faces between an
inside and an outside cell form a complex without boundary, watertight by
construction, and every sample that has cells of both labels in its star is a
vertex of it.  Tight Cocone (Dey and Goswami 2003) labels cells by a walk from
infinity; the Power Crust (Amenta, Choi and Kolluri 2001) labels the polar
balls.  crustview labels every cell with the Power Crust's two rules, applied
to the Delaunay balls themselves:

* **Deep or shallow.**  Two cells that share a face have circumballs that meet
  at an angle alpha: ``cos alpha = (R1^2 + R2^2 - D^2) / (2 R1 R2)`` for radii
  R1, R2 and centres D apart.  Balls that overlap deeply (cos alpha > 0) lie on
  the same side of the surface; balls that only touch (cos alpha near -1, a
  small face between two big balls) lie on opposite sides, because a small
  empty face with a big empty ball on each side is a face of the surface
  (Amenta-Bern: the balls of an epsilon-sample meet the surface only
  shallowly).  The tie's confidence is ``|cos alpha|``.
* **Poles.**  A sample's two poles (the farthest vertex of its Voronoi cell,
  and the farthest on the other side of it) are on opposite sides; the tie's
  confidence is ``-cos`` of the angle between them at the sample.

**Big balls** (Dey and Goswami, *Provable surface reconstruction from noisy
samples*, 2006).  Noise fills a layer of about its own size around the surface
with small Delaunay balls that say nothing about sides.  Every tie is therefore
weighted by how big both balls are, ``g(rho) = 1 - exp(-(rho / BIG_BALL)^2)``
with rho = radius over the local spacing, so ties between big balls are taken
first and the noise layer is decided last, by its neighbours.

**Greedy, most confident first.**  Cells touching the far bounding points are
outside.  The ties are taken in decreasing confidence, each joining two groups
of cells with a fixed relation (a maximum spanning forest of the signed graph,
``_labels.cpp``).  Every cell then has the label of its most confident path to
the outside, and the weakest tie on that path is its *confidence*, which the
repair rules (:mod:`.label_repair`) and the uncertainty report use.
"""

from __future__ import annotations

import numpy as np

from ..delaunay.adjacency import cell_adjacency
from ..util.nearest import nearest_distances
from ..util.vectors import squared_distances

try:  # the compiled kernel; the Python fallback below gives the same labels, slowly
    from . import _labels as _kernel
except ImportError:  # pragma: no cover - only without the extension
    _kernel = None

#: Ball size (radius over the local spacing) at which a Delaunay ball counts as big: g(rho) =
#: 1 - exp(-(rho / BIG_BALL)^2) is 0.22 at one spacing and 0.63 at two.  Two spacings is the
#: smallest gap that an eps < 1 sample resolves (``analysis.features.GAP_MIN``).  The sweep in
#: ``benchmarks/bench_labels.py`` (the labelling path alone on the 17 closed public scans and their
#: noisy copies) finds a plateau: 28 of 51 right at 1, 27 at 2, 25 at 4; 2 is kept for its reason.
BIG_BALL = 2.0


def big_ball(rho: np.ndarray) -> np.ndarray:
    """g(rho): how far a ball of rho local spacings is to be trusted (0 for tiny, 1 for big)."""
    return 1.0 - np.exp(-((rho / BIG_BALL) ** 2))


class Labelling:
    """Inside/outside labels of the Delaunay cells, and how each was decided.

    Parameters
    ----------
    points : ndarray of shape (n, k)
        The samples.
    delaunay_points : ndarray of shape (n + b, k)
        Samples followed by the far bounding points.
    simplices : ndarray of shape (m, k + 1)
        Delaunay k-simplices over ``delaunay_points``.
    centres : ndarray of shape (m, k)
        Their circumcentres (the Voronoi vertices).

    Attributes
    ----------
    inside : ndarray of shape (m,) of bool
    confidence : ndarray of shape (m,)
        The weakest tie on the cell's most confident path to the outside (1 for
        the outside cells themselves).
    outside : ndarray of shape (m,) of bool
        Cells with a bounding point (fixed outside).
    a, b, faces : the shared faces (:func:`cell_adjacency`).
    cos_alpha : ndarray of shape (p,)
        cos of the angle at which the two balls of each shared face meet.
    violated : int
        Ties the greedy labelling could not keep.
    """

    def __init__(
        self, points: np.ndarray, delaunay_points: np.ndarray, simplices: np.ndarray, centres: np.ndarray
    ) -> None:
        n = len(points)
        m = len(simplices)
        self.n, self.m = n, m
        self.simplices = simplices
        # numpy's norm of centres - delaunay_points[simplices[:, 0]], bit for bit (util/vectors.py)
        radius = np.sqrt(squared_distances(centres, None, delaunay_points, simplices[:, 0]))
        h = nearest_distances(points)
        h = np.where(h > 0, h, np.median(h))
        self.spacing = h
        self.points = points
        self.outside = (simplices >= n).any(axis=1)
        hv = np.where(simplices < n, h[np.minimum(simplices, n - 1)], 0.0)
        cnt = (simplices < n).sum(axis=1)
        ht = hv.sum(axis=1) / np.maximum(cnt, 1)
        self.rho = np.where(cnt > 0, radius / np.where(ht > 0, ht, 1.0), np.inf)
        a, b, faces = cell_adjacency(simplices)
        self.a, self.b, self.faces = a, b, faces
        d2 = squared_distances(centres, a, centres, b)
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = (radius[a] ** 2 + radius[b] ** 2 - d2) / (2 * radius[a] * radius[b])
        self.cos_alpha = np.clip(np.nan_to_num(cos, nan=1.0), -1.0, 1.0)
        g = big_ball(self.rho)
        # node 0 is the outside (every cell with a bounding point), cell i is node i + 1
        node = np.where(self.outside, 0, 1 + np.arange(m))
        ea, eb, sign, conf = [node[a]], [node[b]], [np.where(self.cos_alpha >= 0, 1, -1)], []
        conf.append(np.abs(self.cos_alpha) * np.minimum(g[a], g[b]))
        pa, pb, pc = self._pole_pairs(points, centres, radius, g)
        ea.append(node[pa])
        eb.append(node[pb])
        sign.append(-np.ones(len(pa), np.int64))
        conf.append(pc)
        ea, eb, sign, conf = (np.concatenate(x) for x in (ea, eb, sign, conf))
        keep = ea != eb
        ea, eb, sign, conf = ea[keep], eb[keep], sign[keep].astype(np.int8), conf[keep]
        order = descending_order(conf)
        lab, when, viol = _label(m + 1, ea[order], eb[order], sign[order])
        conf_sorted = conf[order]
        node_conf = np.where(when >= 0, conf_sorted[np.maximum(when, 0)], 1.0)
        self.inside = (lab[node] == 1) & ~self.outside
        self.confidence = node_conf[node]
        self.confidence[self.outside] = 1.0
        self.violated = int(viol.sum())

    def _pole_pairs(
        self, points: np.ndarray, centres: np.ndarray, radius: np.ndarray, g: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each sample's two pole cells (farthest, and farthest on the other side) and the tie's confidence."""
        plus, minus = pole_cells(self.simplices, self.n, radius, centres, points)
        smp = np.flatnonzero((plus >= 0) & (minus >= 0))
        u = centres[plus[smp]] - points[smp]
        v = centres[minus[smp]] - points[smp]
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = (u * v).sum(axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        cos = np.nan_to_num(cos, nan=0.0)
        conf = np.maximum(-cos, 0.0) * np.minimum(g[plus[smp]], g[minus[smp]])
        return plus[smp], minus[smp], conf

    def cut(self) -> np.ndarray:
        """Boolean mask over :attr:`faces`: the faces between an inside and an outside cell."""
        return self.inside[self.a] != self.inside[self.b]

    def surface(self) -> tuple[np.ndarray, np.ndarray]:
        """The faces of M_S (sorted rows) and each one's inside cell."""
        c = self.cut()
        inner = np.where(self.inside[self.a[c]], self.a[c], self.b[c])
        return self.faces[c], inner


def pole_cells(
    simplices: np.ndarray, n: int, radius: np.ndarray, centres: np.ndarray, points: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per sample, its two pole cells: the farthest Voronoi vertex, and the farthest on the other side.

    The first is the incident cell of largest radius (:func:`_farthest`); the second the same among
    the incident cells whose centre lies on the other side of the sample (negative dot product with
    the way to the first).  -1 where a sample has none.  The compiled kernel
    (``_labels.pole_cells``) gives the same cells as :func:`pole_cells_python`.
    """
    if _kernel is not None:
        s = np.ascontiguousarray(simplices, dtype=np.int64)
        k = points.shape[1]
        plus, minus = _kernel.pole_cells(
            int(n),
            int(s.shape[1]),
            int(k),
            s,
            np.ascontiguousarray(radius, dtype=np.float64),
            np.ascontiguousarray(centres, dtype=np.float64),
            np.ascontiguousarray(points, dtype=np.float64),
        )
        return np.frombuffer(plus, np.int64).copy(), np.frombuffer(minus, np.int64).copy()
    return pole_cells_python(simplices, n, radius, centres, points)


def pole_cells_python(
    simplices: np.ndarray, n: int, radius: np.ndarray, centres: np.ndarray, points: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`pole_cells` in numpy (the reference the kernel is tested against)."""
    w = simplices.shape[1]
    cell = np.repeat(np.arange(len(simplices), dtype=np.int64), w)
    vert = simplices.ravel()
    ok = vert < n
    cell, vert = cell[ok], vert[ok]
    r = radius[cell]
    plus = _farthest(vert, cell, r, n)
    has = plus >= 0
    to_plus = np.zeros_like(points)
    to_plus[has] = centres[plus[has]] - points[has]
    dot = ((centres[cell] - points[vert]) * to_plus[vert]).sum(axis=1)
    other = dot < 0
    minus = _farthest(vert[other], cell[other], r[other], n)
    return plus, minus


def _farthest(vert: np.ndarray, cell: np.ndarray, r: np.ndarray, n: int) -> np.ndarray:
    """Per sample, a cell of largest radius among its incidences (-1 for none); the last such on ties.

    Two unbuffered reductions (``np.maximum.at``) instead of a sort by sample: the
    largest radius of each sample, then the last incidence that reaches it
    (nefertiti's 1.3 million incidences: 0.24 s sorted, 0.01 s so; the same
    cells).  NaN radii (a flat cell's centre) are passed over (``np.fmax``); a
    sample with no other radius gets -1.
    """
    out = np.full(n, -1, np.int64)
    if len(vert) == 0:
        return out
    top = np.full(n, -np.inf)
    np.fmax.at(top, vert, r)
    hit = np.flatnonzero(r == top[vert])
    last = np.full(n, -1, np.int64)
    np.maximum.at(last, vert[hit], hit)
    has = last >= 0
    out[has] = cell[last[has]]
    return out


def descending_order(values: np.ndarray) -> np.ndarray:
    """``np.argsort(-values, kind="stable")``: by the kernel's radix sort where built and no value is NaN.

    The labelling's ties come most confident first, equal confidences in their order (0.07 s of numpy's
    stable sort for nefertiti's 650,000 ties, about 0.03 s by radix).
    """
    v = np.ascontiguousarray(values, dtype=np.float64)
    if _kernel is not None and hasattr(_kernel, "descending_order") and v.ndim == 1 and not np.isnan(v).any():
        return np.frombuffer(_kernel.descending_order(v), np.int64)
    return np.argsort(-v, kind="stable")


def _label(n: int, a: np.ndarray, b: np.ndarray, sign: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's labelling (node 0 is the root), or the same in Python without it."""
    a = np.ascontiguousarray(a, dtype=np.int64)
    b = np.ascontiguousarray(b, dtype=np.int64)
    sign = np.ascontiguousarray(sign, dtype=np.int8)
    if _kernel is not None:
        lab, when, viol = _kernel.label(int(n), a, b, sign, 0)
        return (
            np.frombuffer(lab, np.int8).copy(),
            np.frombuffer(when, np.int64).copy(),
            np.frombuffer(viol, np.int8).copy(),
        )
    return label_python(n, a, b, sign)


def label_python(n: int, a: np.ndarray, b: np.ndarray, sign: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's algorithm in plain Python (reference and fallback; same results)."""
    parent = list(range(n))
    size = [1] * n
    link = [-1] * n
    par = [0] * n
    viol = np.zeros(len(a), np.int8)

    def find(x: int) -> tuple[int, int]:
        p = 0
        while parent[x] != x:
            p ^= par[x]
            x = parent[x]
        return x, p

    for i, (x, y, s) in enumerate(zip(a.tolist(), b.tolist(), sign.tolist())):
        ra, pa = find(x)
        rb, pb = find(y)
        want = 1 if s < 0 else 0
        if ra == rb:
            viol[i] = (pa ^ pb) != want
            continue
        if size[ra] < size[rb]:
            ra, rb, pa, pb = rb, ra, pb, pa
        parent[rb] = ra
        par[rb] = pa ^ pb ^ want
        size[ra] += size[rb]
        link[rb] = i
    rr, proot = find(0)
    mark = {}
    x, t = 0, -1
    mark[x] = t
    while parent[x] != x:
        t = link[x]
        x = parent[x]
        mark[x] = t
    lab = np.full(n, -1, np.int8)
    when = np.full(n, -1, np.int64)
    for i in range(n):
        r, p = find(i)
        if r != rr:
            continue
        lab[i] = p ^ proot
        x, t = i, -1
        while x not in mark:
            t = link[x]
            x = parent[x]
        when[i] = -1 if i == 0 else max(t, mark[x])
    return lab, when, viol


def oriented(faces: np.ndarray, inner: np.ndarray, simplices: np.ndarray, points: np.ndarray) -> np.ndarray:
    """+1/-1 per face of M_S: the sign of its sorted vertex order seen from its inside cell.

    Faces between the same two sides get one consistent sign convention, so M_S is oriented
    (its normals point out of the inside cells).
    """
    apex = _apex(faces, simplices[inner])
    base = points[faces[:, 0]]
    mat = np.stack([points[faces[:, j]] - base for j in range(1, faces.shape[1])] + [points[apex] - base], axis=1)
    return np.where(np.linalg.det(mat) > 0, -1, 1).astype(np.int64)


def _apex(faces: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The vertex of each cell that is not in its face."""
    inface = (cells[:, :, None] == faces[:, None, :]).any(axis=2)
    return cells[np.arange(len(cells)), np.argmin(inface, axis=1)]
