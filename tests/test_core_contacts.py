"""Rule of the report: two large parts of M_S held together only by faces standing across the normals."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.spatial import ConvexHull

from crustview.core.analysis.contacts import MIN_PART_FACES, STAND_ANGLE, hidden_parts, standing_faces
from crustview.core.analysis.topology import analyse


def test_a_face_stands_across_only_when_far_from_every_vertex_normal() -> None:
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    tri = np.array([[0, 1, 2]])
    up, side = np.array([0.0, 0, 1]), np.array([1.0, 0, 0])
    assert not standing_faces(pts, tri, np.array([up, up, up]))[0]
    assert standing_faces(pts, tri, np.array([side, side, side]))[0]
    # one vertex whose normal line is within the angle is enough (signs do not matter)
    assert not standing_faces(pts, tri, np.array([side, side, -up]))[0]
    tilt = np.array([np.sin(STAND_ANGLE + 0.01), 0, np.cos(STAND_ANGLE + 0.01)])
    assert standing_faces(pts, tri, np.array([tilt, tilt, tilt]))[0]


def _ball(n: int, seed: int) -> np.ndarray:
    """n points on the unit sphere, the first at (1, 0, 0)."""
    x = np.random.default_rng(seed).normal(size=(n, 3))
    x /= np.linalg.norm(x, axis=1)[:, None]
    x[0] = [1.0, 0, 0]
    return x


def _fused(n: int = 200, shift=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two unit spheres' hulls 0.3 apart along x (the second the mirror image of the first, so vertex i
    of one faces vertex i of the other), a triangle cut out of each where they face each other and a
    straight band of 6 triangles between the two holes; radial normals.  Each ball keeps 2 n - 5 faces."""
    a = _ball(n, 1)
    ta = ConvexHull(a).simplices
    ha = ta[(ta == 0).any(axis=1)][0]
    ta = ta[~(ta == ha).all(axis=1)]
    hb = ha + n
    band = []
    for i in range(3):
        j = (i + 1) % 3
        band += [[ha[i], ha[j], hb[i]], [ha[j], hb[j], hb[i]]]
    b = a * [-1.0, 1, 1]
    pts = np.vstack([a, b + [2.3, 0, 0]]) + np.asarray(shift)
    return pts, np.vstack([ta, ta + n, np.array(band)]), np.vstack([a, b])


def test_two_balls_joined_by_a_standing_band_are_reported() -> None:
    pts, tri, normals = _fused()
    t = analyse(tri, len(pts), 2)
    assert t.closed_manifold and t.betti == (1, 0, 1)  # one closed sphere: nothing else says two objects
    found = hidden_parts(pts, tri, normals)
    assert len(found) == 1
    f = found[0]
    assert f.kind == "component" and f.uncertain
    # at the contact, between the two balls, measured between samples off the standing band
    assert 0.9 < f.location[0] < 1.4 and f.size_spacings > 0
    band = np.unique(tri[standing_faces(pts, tri, normals)])
    assert not np.isin(f.vertices, band).any()
    # a feature already there that names this contact (a join: one sample on each side) is not repeated
    assert hidden_parts(pts, tri, normals, known=[f]) == []
    # one that touches only this part (a gap from it to some third object) does not hide it
    other = replace(f, vertices=np.array([f.vertices[0]]))
    assert len(hidden_parts(pts, tri, normals, known=[other])) == 1
    # a sample without a normal on the band: its faces are judged on their other vertices
    nan = normals.copy()
    nan[tri[-1][0]] = np.nan
    assert len(hidden_parts(pts, tri, nan)) == 1


def test_two_fused_pairs_give_two_contacts() -> None:
    p1, t1, n1 = _fused()
    p2, t2, n2 = _fused(shift=(0.0, 5.0, 0.0))
    pts, tri, normals = np.vstack([p1, p2]), np.vstack([t1, t2 + len(p1)]), np.vstack([n1, n2])
    found = hidden_parts(pts, tri, normals)
    assert len(found) == 2
    assert sorted(round(float(f.location[1])) for f in found) == [0, 5]


def test_parts_count_from_min_part_faces() -> None:
    pts, tri, normals = _fused()
    a_only = tri[(tri < 200).all(axis=1)]
    assert hidden_parts(pts[:200], a_only, normals[:200]) == []  # one ball: no standing band, nothing
    # balls of 80 points keep 155 faces each, MIN_PART_FACES: reported; of 79 points, 153: fragments
    assert 2 * 80 - 5 == MIN_PART_FACES
    for n, found in ((80, 1), (79, 0)):
        pts, tri, normals = _fused(n)
        assert len(tri) >= 2 * MIN_PART_FACES and standing_faces(pts, tri, normals)[-6:].all()
        assert len(hidden_parts(pts, tri, normals)) == found, n


def test_a_sphere_and_a_torus_fused_by_the_labelling_are_flagged() -> None:
    """bench_objects.py's sphere and torus one spacing apart at 0.1 h noise (seed 2): the labelling puts
    the gap's cells inside and no rule runs; the result, one closed genus-1 surface, was reported sure."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from bench_objects import pair

    from crustview.core import reconstruct

    pts, truth = pair("sphere-torus", 1.0, 0.1, 2)
    rec = reconstruct(pts, 2)
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 2, 1) != truth
    contact = [f for f in rec.uncertain_features if f.kind == "component" and "stand across" in f.reason]
    assert len(contact) == 1
    # at the contact: between the sphere (x <= 1) and the torus beyond it
    assert 0.9 < contact[0].location[0] < 1.2
    # the same points turned into a 3-flat of R^4: labelled in the flat's coordinates, and the report's checks
    # run there too (session 37; before, the flat's surface was sure), the contact placed back in R^4
    turn = np.linalg.qr(np.random.default_rng(1).normal(size=(4, 4)))[0]
    flat = reconstruct(np.c_[pts, np.zeros(len(pts))] @ turn + 1.0, 2)
    assert flat.k == 4 and flat.subspace_dim == 3 and flat.topology.betti == rec.topology.betti
    there = [f for f in flat.uncertain_features if f.kind == "component" and "stand across" in f.reason]
    assert len(there) == 1
    assert np.allclose((there[0].location - 1.0) @ turn.T, np.r_[contact[0].location, 0.0], atol=1e-6)


def _double_contact(n: int = 300) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Two unit spheres' hulls (mirror images, 0.3 apart) joined by two straight bands of standing
    faces at two facing places: one closed surface of genus 1 whose handle is the two contacts."""
    x = _ball(n, 1)
    x[0], x[1] = [np.cos(0.5), np.sin(0.5), 0], [np.cos(-0.5), np.sin(-0.5), 0]
    t = ConvexHull(x).simplices
    holes = [t[(t == v).any(axis=1)][0] for v in (0, 1)]
    assert not set(holes[0]) & set(holes[1])
    t = t[~np.any([(t == h).all(axis=1) for h in holes], axis=0)]
    band = []
    for h in holes:
        for i in range(3):
            j = (i + 1) % 3
            band += [[h[i], h[j], h[i] + n], [h[j], h[j] + n, h[i] + n]]
    pts = np.vstack([x, x * [-1.0, 1, 1] + [2.3, 0, 0]])
    return pts, np.vstack([t, t + n, np.array(band)]), np.vstack([x, x * [-1.0, 1, 1]])


def test_a_handle_carried_only_by_standing_bands_is_found() -> None:
    from crustview.core.analysis.contacts import bridged_handles
    from crustview.core.analysis.features import features

    pts, tri, normals = _double_contact()
    top = analyse(tri, len(pts), 2)
    assert top.closed_manifold and top.betti == (1, 2, 1)
    handles = [f for f in features(pts, tri, 2) if f.kind == "handle"]
    assert len(handles) == 2
    through = bridged_handles(pts, tri, normals, handles)
    # the loop around one band (its rim is on the balls) is carried by the rest; the loop through both is not
    assert len(through) == 1
    loop = handles[next(iter(through))].vertices
    assert (loop < 300).any() and (loop >= 300).any()
    # a handle feature whose walk is not on M_S (a dispute marks the other result's loop) is passed over
    off = replace(handles[0], vertices=np.array([0, 150, 450]))
    assert bridged_handles(pts, tri, normals, [off, *handles]) == {1 + next(iter(through))}


def test_a_bridged_handle_of_an_open_surface_is_found_on_its_capped_form() -> None:
    """The two spheres joined by two bands, with a hole cut on the far side of the first one (an open
    scan): the handle through both bands is found as on the closed surface (session 28: the check looked at
    closed surfaces only, and a decimated hand at 0.3 h kept a false handle across two fingers, sure)."""
    from crustview.core.analysis.contacts import bridged_handles
    from crustview.core.analysis.features import features

    pts, tri, normals = _double_contact()
    far = int(np.argmin(pts[:300, 0]))  # the first sphere's point farthest from the contacts
    tri = tri[~(tri == far).any(axis=1)]  # its star removed: one hole
    top = analyse(tri, len(pts), 2)
    assert not top.closed_manifold and top.boundary_faces > 0 and top.nonmanifold_faces == 0
    feats = features(pts, tri, 2)
    handles = [f for f in feats if f.kind == "handle"]
    assert len(handles) == 2 and sum(f.kind == "hole" for f in feats) == 1
    through = bridged_handles(pts, tri, normals, handles)
    assert len(through) == 1
    loop = handles[next(iter(through))].vertices
    assert (loop < 300).any() and (loop >= 300).any()


def test_a_surface_without_handles_has_no_bridged_handle() -> None:
    """Handle features on a genus-0 M_S (another answer's, or a disputed one) and standing faces: the
    surface has no handle class, so nothing is bridged (the decimated feline at half its faces raised
    KeyError here once open surfaces were checked)."""
    from crustview.core.analysis.contacts import bridged_handles
    from crustview.core.analysis.features import Feature

    pts, tri, _ = _double_contact()
    one = tri[(tri < 300).all(axis=1)]  # the first sphere alone: closed, genus 0
    normals = np.tile([0.0, 0.0, 1.0], (len(pts), 1))  # every face near the equator stands across these
    assert standing_faces(pts, one, normals, STAND_ANGLE / 2).any()
    other = Feature("handle", np.zeros(3), 30.0, False, np.array([0, 1, 2, 3]), "")
    assert bridged_handles(pts, one, normals, [other]) == set()
    far = int(np.argmin(pts[:300, 0]))
    holed = one[~(one == far).any(axis=1)]  # and with a hole
    assert bridged_handles(pts, holed, normals, [other]) == set()


def test_real_handles_are_not_bridges() -> None:
    """A built-in torus with 0.1 % noise: its two loops stay sure."""
    from crustview.core import reconstruct
    from crustview.core.samples.manifolds import get_manifold

    s = get_manifold("torus").sample(1500, seed=3).points
    rec = reconstruct(s + np.random.default_rng(3).normal(scale=0.003, size=s.shape), 2)
    handles = [f for f in rec.features if f.kind == "handle"]
    assert rec.topology.betti == (1, 2, 1) and len(handles) == 2
    assert not any("rule contact" in f.reason for f in rec.features)


def test_a_result_of_the_paper_s_own_algorithm_gets_no_rule_beyond_it() -> None:
    """The contact and resample checks judge the extension's steps: a result Algorithm 3 gave alone is the paper's.

    A torus turned in rings three times farther apart than the vertices along them (``bench_shapes.py``):
    Algorithm 3 closes it through every sample, but its faces are more than theta from the vertex normals
    along the whole tube, so the contact rule once flagged its real handle (the extension had not run:
    every rule's count was listed, zero or not).
    """
    import sys
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.core.uncertainty import _beyond

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from bench_shapes import lathe, profile_torus

    verts, _ = lathe(profile_torus(), 96, 3.0, closed_loop=True)
    rec = reconstruct(verts, 2)
    counts = rec.extraction.counts_by_rule()
    assert rec.topology.closed_manifold and rec.topology.betti == (1, 2, 1) and rec.topology.unused_samples == 0
    assert not _beyond(counts)
    assert rec.uncertain_features == []
    assert _beyond({**counts, "label-cells": {"steps": 1, "removed": 0, "added": 10}})
