"""Handles of d-complexes, d >= 3 (:mod:`crustview.core.analysis.tunnels`): classes and loops checked on paper."""

from __future__ import annotations

import math

import numpy as np
import pytest

from crustview.core.analysis.features import LOOP_MIN, LOOP_SUPPORTED, features
from crustview.core.analysis.topology import analyse
from crustview.core.analysis.tunnels import edge_classes, skeleton, tunnels


def _ring(m: int, shift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A necklace of m tetrahedra around the unit circle: v_i in z = 0, w_i in z = 1, tet i = v_i v_i+1 w_i w_i+1.

    Consecutive tets share an edge and no three meet, so the union is a ring: b1 = 1, and its shortest loop
    runs around one of the two circles, m chords of length 2 sin(pi / m).
    """
    t = 2 * np.pi * np.arange(m) / m
    v = np.c_[np.cos(t) + shift, np.sin(t), np.zeros(m)]
    w = np.c_[np.cos(t) + shift, np.sin(t), np.ones(m)]
    i = np.arange(m)
    j = (i + 1) % m
    return np.vstack([v, w]), np.c_[i, j, m + i, m + j]


def _classes_of(points: np.ndarray, simplices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    edges, tri_edges = skeleton(simplices)
    mask, b1, _ = edge_classes(len(points), edges, tri_edges)
    return edges, tri_edges, mask, b1


def test_a_ring_of_tetrahedra_has_one_handle_of_m_chords():
    pts, tets = _ring(8)
    edges, tri_edges, mask, b1 = _classes_of(pts, tets)
    assert b1 == 1
    # every triangle bounds: its edges' classes add up to zero
    assert not (mask[tri_edges[:, 0]] ^ mask[tri_edges[:, 1]] ^ mask[tri_edges[:, 2]]).any()
    chords = 8 * 2 * math.sin(math.pi / 8)
    coarse = tunnels(pts, tets, np.ones(len(pts)))
    assert len(coarse) == 1 and coarse[0].kind == "handle"
    assert coarse[0].size_spacings == pytest.approx(chords)
    assert chords < LOOP_MIN and coarse[0].uncertain and "fewer samples" in coarse[0].reason
    # the loop goes once around: its vertices' angles cover the circle
    ang = np.unique(np.round(np.arctan2(pts[coarse[0].vertices, 1], pts[coarse[0].vertices, 0]), 6))
    assert len(ang) == 8
    fine = tunnels(pts, tets, np.full(len(pts), 0.4))
    assert fine[0].size_spacings == pytest.approx(chords / 0.4)
    assert fine[0].size_spacings >= LOOP_SUPPORTED and not fine[0].uncertain


def test_a_coned_ring_has_no_handle():
    """Tets from a centre point to the ring's lower triangles fill the loop's disc: b1 = 0."""
    pts, tets = _ring(8)
    c = len(pts)
    pts = np.vstack([pts, [[0.0, 0.0, 0.5]]])
    i = np.arange(8)
    tets = np.vstack([tets, np.c_[np.full(8, c), i, (i + 1) % 8, 8 + i]])
    assert _classes_of(pts, tets)[3] == 0
    assert tunnels(pts, tets, np.ones(len(pts))) == []


def test_two_rings_have_two_handles_and_the_features_list_them():
    p1, t1 = _ring(6)
    p2, t2 = _ring(10, shift=5.0)
    pts, tets = np.vstack([p1, p2]), np.vstack([t1, t2 + len(p1)])
    assert _classes_of(pts, tets)[3] == 2
    found = [f for f in features(pts, tets, 3, spacing=np.ones(len(pts))) if f.kind == "handle"]
    sizes = sorted(f.size_spacings for f in found)
    assert sizes == pytest.approx([6 * 2 * math.sin(math.pi / 6), 10 * 2 * math.sin(math.pi / 10)])


def _grid(m: int, flip: bool) -> np.ndarray:
    """An m x m grid of squares, two triangles each, glued into a torus (or, with ``flip``, a Klein bottle)."""

    def vid(i: int, j: int) -> int:
        if i == m:  # across the seam of the first coordinate: the second reversed on a Klein bottle
            i, j = 0, (m - j) % m if flip else j
        return i * m + j % m

    tris = []
    for i in range(m):
        for j in range(m):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            tris += [(a, b, c), (a, c, d)]
    return np.array(tris, np.int64)


# the 6-vertex real projective plane (the hemi-icosahedron)
_RP2 = np.array(
    [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 1], [1, 2, 4], [2, 3, 5], [3, 4, 1], [4, 5, 2], [5, 1, 3]]
)


@pytest.mark.parametrize(
    "tris, b1",
    [(_grid(5, False), 2), (_grid(5, True), 2), (_RP2, 1)],
    ids=["torus", "klein-bottle", "projective-plane"],
)
def test_the_classes_count_b1_of_any_2_complex(tris, b1):
    """Z/2 homology: b1 of the torus and the Klein bottle is 2, of the projective plane 1; the topology
    analysis (its own elimination) agrees."""
    n = int(tris.max()) + 1
    assert analyse(tris, n, 2).betti[1] == b1
    edges, tri_edges = skeleton(tris)
    mask, got, born = edge_classes(n, edges, tri_edges)
    assert got == b1 and len(born) == b1
    assert not (mask[tri_edges[:, 0]] ^ mask[tri_edges[:, 1]] ^ mask[tri_edges[:, 2]]).any()
    # the classes span b1 dimensions: the edges' masks have rank b1 over Z/2
    rows = {int.from_bytes(r.tobytes(), "little") for r in mask}
    basis: dict[int, int] = {}
    for x in rows:
        while x and (x.bit_length() - 1) in basis:
            x ^= basis[x.bit_length() - 1]
        if x:
            basis[x.bit_length() - 1] = x
    assert len(basis) == b1


@pytest.mark.parametrize("seed", [0, 1, 3, 4, 5, 6])
def test_the_classes_of_random_tetrahedra_agree_with_the_topology_analysis(seed):
    """Random halves of a Delaunay triangulation of 200 points: holes, tunnels and relations among the free
    coordinates (triangles whose three edges were known before they were used: 1 to 6 in these draws), which the
    tiny cases above never make.
    Every triangle bounds, every basis loop is a closed walk along the complex's edges, and the loops are
    b1 independent classes."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(seed)
    pts = rng.random((200, 3))
    tets = Delaunay(pts).simplices
    tets = tets[rng.random(len(tets)) < 0.5]
    n = len(pts)
    edges, tri_edges, mask, b1 = _classes_of(pts, tets)
    assert b1 == analyse(tets, n, 3).betti[1] > 0
    assert not (mask[tri_edges[:, 0]] ^ mask[tri_edges[:, 1]] ^ mask[tri_edges[:, 2]]).any()
    loops = tunnels(pts, tets, np.full(n, 0.05))
    assert len(loops) == b1
    have = {tuple(e) for e in edges.tolist()}
    basis: dict[int, int] = {}
    for f in loops:
        w = f.vertices[np.r_[True, f.vertices[1:] != f.vertices[:-1]]]
        steps = [tuple(sorted(p)) for p in zip(w, np.roll(w, -1), strict=True) if p[0] != p[1]]
        assert steps and all(s in have for s in steps) and np.isfinite(f.size_spacings)
        ids = [int(np.flatnonzero((edges == s).all(axis=1))[0]) for s in steps]
        x = int.from_bytes(np.bitwise_xor.reduce(mask[ids], axis=0).tobytes(), "little")
        while x and (x.bit_length() - 1) in basis:
            x ^= basis[x.bit_length() - 1]
        assert x, "a basis loop in the span of the others (or null-homologous)"
        basis[x.bit_length() - 1] = x


def test_a_long_class_beside_another_component_is_still_found():
    """A thick torus T^2 x I in R^4 (a long circle of 60 steps, a short one of 3) and a necklace far away:
    b1 = 3.  The spread roots' own candidates miss the long circle; the forest's loops complete the basis,
    and no loop runs into the other component (before the review: 2 of 3 loops, or one of infinite size)."""
    import itertools

    m1, m2 = 60, 3

    def vid(i: int, j: int, k: int) -> int:
        return ((i % m1) * m2 + (j % m2)) * 2 + k

    pts = np.zeros((m1 * m2 * 2, 4))
    tets = []
    for i, j, k in itertools.product(range(m1), range(m2), range(2)):
        th, ph = 2 * np.pi * i / m1, 2 * np.pi * j / m2
        pts[vid(i, j, k)] = [
            30 * np.cos(th),
            30 * np.sin(th),
            (0.5 + 0.3 * k) * np.cos(ph),
            (0.5 + 0.3 * k) * np.sin(ph),
        ]
    for i, j in itertools.product(range(m1), range(m2)):
        for order in itertools.permutations(range(3)):  # Kuhn's triangulation of each cube
            c, path = [0, 0, 0], [vid(i, j, 0)]
            for ax in order:
                c[ax] += 1
                path.append(vid(i + c[0], j + c[1], c[2]))
            tets.append(path)
    ring_pts, ring_tets = _ring(8, shift=100.0)
    pts = np.vstack([pts, np.c_[ring_pts, np.zeros(len(ring_pts))]])
    tets = np.vstack([np.array(tets), ring_tets + m1 * m2 * 2])
    assert analyse(tets, len(pts), 3).betti[1] == 3
    found = tunnels(pts, tets, np.full(len(pts), 0.3))
    assert len(found) == 3 and all(np.isfinite(f.size_spacings) and len(f.vertices) > 3 for f in found)
    # the long circle: 60 steps around a circle of radius 30 (or more), sure
    assert max(f.size_spacings for f in found) >= 60 * 2 * 30 * math.sin(math.pi / 60) / 0.3 - 1e-6


def test_more_classes_than_the_search_takes_make_one_unsupported_feature(monkeypatch):
    """Above MAX_LOOPS independent loops none is searched: one handle feature says how many, uncertain."""
    import crustview.core.analysis.tunnels as tunnels_module

    p1, t1 = _ring(6)
    p2, t2 = _ring(10, shift=5.0)
    pts, tets = np.vstack([p1, p2]), np.vstack([t1, t2 + len(p1)])
    monkeypatch.setattr(tunnels_module, "MAX_LOOPS", 1)
    (only,) = tunnels(pts, tets, np.ones(len(pts)))
    assert only.kind == "handle" and only.uncertain and only.size_spacings == 0.0
    assert only.reason.startswith("2 independent loops: too many handles")
