"""Algorithm 2 on chunks and threads: same result, and a cancel stops it."""

import numpy as np
import pytest

from crustview.core.delaunay.triangulation import bounding_points, circumcenters, delaunay
from crustview.core.paper import candidates as cand
from crustview.core.paper.normals import greedy_poles
from crustview.core.samples.manifolds import get_manifold
from crustview.core.util import parallel


def _stage_inputs(name: str, n: int):
    from crustview.core.prepare import prepare_points

    m = get_manifold(name)
    prep = prepare_points(m.sample(n, seed=0).points, m.d)
    b = bounding_points(prep.r)
    simp = delaunay(prep.work, b)
    work = np.vstack([prep.work, b])
    centres = circumcenters(work, simp)
    _, normals, _ = greedy_poles(work, simp, centres, len(prep.work), prep.r - m.d)
    faces, ptr, cs = cand.enumerate_faces(simp, len(prep.work), m.d)
    return work, normals, centres, faces, ptr, cs, simp


@pytest.mark.parametrize("name,n", [("torus", 600), ("flat-klein", 400)])
def test_chunks_and_threads_give_the_serial_result(monkeypatch, name, n):
    work, normals, centres, faces, ptr, cs, simp = _stage_inputs(name, n)
    whole = cand.cocone_angles(work, normals, centres, faces, ptr, cs, simplices=simp, workers=1)
    monkeypatch.setattr(cand, "CHUNK_CELL_VERTICES", 200)  # many small chunks
    fracs = []
    threaded = cand.cocone_angles(
        work, normals, centres, faces, ptr, cs, simplices=simp, workers=2, progress=fracs.append
    )
    assert np.array_equal(threaded, whole)
    assert len(fracs) > 10 and fracs == sorted(fracs) and fracs[-1] == 1.0
    lit = cand.literal_angles(work[: len(normals)], normals, faces, workers=1)
    assert np.array_equal(cand.literal_angles(work[: len(normals)], normals, faces, workers=2), lit)


@pytest.mark.parametrize("native", [True, False])
# (5, 4, 300): the compiled sort's other vertices need more than 32 bits (300^4), so it sorts pairs
@pytest.mark.parametrize("k,d,n", [(3, 2, 3000), (4, 2, 500), (4, 1, 500), (5, 2, 150), (5, 4, 300)])
def test_enumerate_faces_matches_a_plain_stable_sort(k, d, n, native, monkeypatch):
    # by the compiled _faces (int32 simplices) or by numpy: the (d+1)-subsets of
    # every simplex whose vertices are samples, grouped, each face's simplices
    # in increasing order
    import itertools

    from crustview.core.delaunay import faces as faces_mod

    if native:
        assert faces_mod._native is not None
    else:
        monkeypatch.setattr(faces_mod, "_native", None)
    rng = np.random.default_rng(7)
    simp = delaunay(rng.normal(size=(n, k)), bounding_points(k))
    assert simp.dtype == np.int32
    faces, ptr, cs = cand.enumerate_faces(simp, n, d)
    combos = list(itertools.combinations(range(k + 1), d + 1))
    srt = np.sort(simp, axis=1)
    inst = srt[:, combos].reshape(-1, d + 1)
    owner = np.repeat(np.arange(len(simp)), len(combos))
    keep = inst[:, -1] < n
    inst, owner = inst[keep], owner[keep]
    order = np.lexsort(inst.T[::-1])
    assert faces.dtype == ptr.dtype == np.int64 and cs.dtype == np.int32
    assert np.array_equal(cs, owner[order])
    assert np.array_equal(faces, np.unique(inst, axis=0))
    assert np.array_equal(np.diff(ptr), np.unique(inst, axis=0, return_counts=True)[1])


def test_the_compiled_face_lists_reject_bad_shapes_clearly():
    from crustview.core.delaunay import _faces

    with pytest.raises(ValueError, match="int32 simplices"):
        _faces.faces(np.zeros(7, dtype=np.int32), 4, 3, 10)
    with pytest.raises(ValueError, match="same shape"):
        _faces.facets(np.zeros(8, dtype=np.int32), np.zeros(4, dtype=np.int32), 4, 10)


@pytest.mark.parametrize("native", [True, False])
@pytest.mark.parametrize(
    "backend,k,bounded",
    [("cgal", 3, True), ("qhull", 3, False), ("qhull", 2, True), ("cgal", 4, True), ("cgal", 4, False)],
)
def test_facets_from_the_neighbour_table_equal_the_general_enumeration(backend, k, bounded, native, monkeypatch):
    # codimension 1: faces paired through the backend's neighbour table, by the
    # compiled _faces or by numpy; with no bounding points the hull facets
    # have a single simplex
    from crustview.core.delaunay import faces as faces_mod

    if native:
        assert faces_mod._native is not None  # setup.py builds it; the fast path must be there
    else:
        monkeypatch.setattr(faces_mod, "_native", None)
    rng = np.random.default_rng(12)
    n = 2500 if k < 4 else 600
    pts = rng.normal(size=(n, k))
    b = bounding_points(k) if bounded else np.empty((0, k))
    simp, nbrs = delaunay(pts, b, backend=backend, neighbors=True)
    assert nbrs is not None and nbrs.shape == simp.shape
    general = cand.enumerate_faces(simp, n, k - 1)
    paired = cand.enumerate_faces(simp, n, k - 1, neighbors=nbrs)
    for got, want in zip(paired, general):
        assert got.dtype == want.dtype and np.array_equal(got, want)
    counts = np.diff(general[1])
    assert counts.max() == 2 and (counts.min() == 1) == (not bounded)


def test_an_exception_in_the_consumer_drops_the_chunks_not_started():
    started = []

    def work(i: int) -> int:
        started.append(i)
        return i

    results = []
    with pytest.raises(RuntimeError):
        for r in parallel.run_in_order(work, range(1000), workers=2):
            results.append(r)
            if r == 5:
                raise RuntimeError("cancel")
    assert results == list(range(6))
    assert len(started) < 20


@pytest.mark.parametrize("native", [True, False])
def test_facets_of_two_tetrahedra_by_hand(native, monkeypatch):
    # two tetrahedra glued along (1, 2, 3); cell 0 sees cell 1 opposite its
    # vertex 0, cell 1 sees cell 0 opposite its vertex 4 (column 3)
    from crustview.core.delaunay import faces as faces_mod

    if not native:
        monkeypatch.setattr(faces_mod, "_native", None)
    simp = np.array([[0, 1, 2, 3], [1, 2, 3, 4]], dtype=np.int32)
    nbrs = np.array([[1, -1, -1, -1], [-1, -1, -1, 0]], dtype=np.int32)
    faces, ptr, owners = cand.enumerate_faces(simp, 5, 2, neighbors=nbrs)
    assert faces.tolist() == [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3], [1, 2, 4], [1, 3, 4], [2, 3, 4]]
    assert [owners[a:b].tolist() for a, b in zip(ptr[:-1], ptr[1:])] == [[0], [0], [0], [0, 1], [1], [1], [1]]
    # with vertex 4 a bounding point only cell 0's facets are sample faces
    faces, ptr, owners = cand.enumerate_faces(simp, 4, 2, neighbors=nbrs)
    assert faces.tolist() == [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
    assert ptr.tolist() == [0, 1, 2, 3, 5] and owners.tolist() == [0, 0, 0, 0, 1]


def test_codimension_1_segment_scores_compiled_equal_numpy_bit_for_bit(monkeypatch):
    # the compiled _segments does numpy's arithmetic operation for operation: the ends' minima and
    # certificates, and the exact minimum over each segment from them, so the whole cocone scores are equal
    work, normals, centres, faces, ptr, cs, simp = _stage_inputs("torus", 1500)
    assert cand._native_segments is not None  # setup.py builds it
    cells = cs.reshape(-1, 2)  # codimension 1 with bounding points: every dual cell is a segment
    assert np.array_equal(ptr, np.arange(0, 2 * len(faces) + 1, 2))
    sin_lim = np.sin(cand.SCORE_LIMIT)

    def both(c, f, e):
        plain = cand._segment_ends(work, normals, c, f, e)
        return (
            cand._segment_sin2_native(work, normals, c, f, e, sin_lim),
            np.stack([cand.segment_sin2(b, lean, sin_lim) for b, lean in plain], axis=1),
            np.stack([lean for _, lean in plain], axis=1),
        )

    fused, apart, lean = both(centres, faces, cells)
    assert np.array_equal(fused, apart)
    # every branch taken many times: crossing (0), the nearer end (best), and certified (lean ** 2)
    assert (lean <= 0).sum() > 100 and ((lean > 0) & (lean < sin_lim)).sum() > 100 and (lean >= sin_lim).sum() > 100
    # a non-finite Voronoi vertex gives NaN in both, as numpy's minimum does (std::min would drop it)
    bad = centres.copy()
    bad[cells[:5, 1]] = np.nan
    fused, apart, _ = both(bad, faces[:5], cells[:5])
    assert np.isnan(apart).all() and np.array_equal(fused, apart, equal_nan=True)
    # a Voronoi vertex on the sample itself: |x| = 0 is guarded the same way
    hit = centres.copy()
    hit[cells[0, 0]] = work[faces[0, 0]]
    fused, apart, _ = both(hit, faces[:1], cells[:1])
    assert np.array_equal(fused, apart)
    whole = cand.cocone_angles(work, normals, centres, faces, ptr, cs, simplices=simp)
    monkeypatch.setattr(cand, "_native_segments", None)
    assert np.array_equal(cand.cocone_angles(work, normals, centres, faces, ptr, cs, simplices=simp), whole)
    from crustview.core.delaunay import _segments

    with pytest.raises(ValueError, match="outside"):
        _segments.sin2(
            work,
            normals[:, :, 0],
            centres,
            np.full((1, 3), 10**9, dtype=np.int64),
            np.zeros((1, 2), dtype=np.int64),
            3,
            3,
            float(sin_lim),
        )


@pytest.mark.parametrize("name,n", [("flat-klein", 400), ("clifford-torus", 300)])
def test_codimension_2_vertex_pass_compiled_equals_numpy_bit_for_bit(monkeypatch, name, n):
    # the compiled _cellpass does numpy's arithmetic operation for operation, and the exact step after it
    # sees the same arrays: the whole cocone scores are equal (on two threads too: the test above)
    work, normals, centres, faces, ptr, cs, simp = _stage_inputs(name, n)
    assert cand._native_cellpass is not None  # setup.py builds it
    # a Voronoi vertex on a sample itself: |x| = 0 is guarded the same way (the first 300 faces)
    hit = centres.copy()
    hit[cs[ptr[0]]] = work[faces[0, 0]]
    cases = [(centres, faces, ptr), (hit, faces[:300], ptr[:301])]
    native = [cand.cocone_angles(work, normals, c, f, p, cs, simplices=simp, workers=1) for c, f, p in cases]
    monkeypatch.setattr(cand, "_native_cellpass", None)
    plain = [cand.cocone_angles(work, normals, c, f, p, cs, simplices=simp, workers=1) for c, f, p in cases]
    assert all(np.array_equal(a, b) for a, b in zip(native, plain))
    # the cells' edges listed by numpy instead of the compiled cell_edges: the same scores again
    from crustview.core.paper import dualcells

    monkeypatch.setattr(dualcells, "_native", None)
    assert all(
        np.array_equal(a, cand.cocone_angles(work, normals, c, f, p, cs, simplices=simp, workers=1))
        for a, (c, f, p) in zip(plain, cases)
    )
    from crustview.core.delaunay import _cellpass

    with pytest.raises(ValueError, match="outside"):
        _cellpass.cellpass(
            work, normals, centres, np.full((1, 3), 10**9, dtype=np.int64), np.zeros((1, 4), np.int64), 4, 2, 3, 4
        )
    sq = np.zeros(faces.shape)
    with pytest.raises(ValueError, match="outside"):
        _cellpass.cellpass_rows(work, normals, centres, faces, ptr, cs, np.array([len(faces)]), sq, 4, 2, 3, 4, 0.5)


def test_dual_cell_edges_compiled_equal_numpy_on_paper_and_on_the_klein_bottle():
    from crustview.core.paper.dualcells import cell_structure, native_edges

    # by hand: the triangle (0, 1, 2) in R^4 with three simplices around it; s0 = 01234 and s1 = 01245
    # share 0124, s1 and s2 = 01235 share 0125, s0 and s2 share 0123.  Listed by the vertex kept (3, 4, 5),
    # then by the position dropped among the two others, then by cell vertex.
    face = np.array([[0, 1, 2]])
    simp = np.array([[0, 1, 2, 3, 4], [4, 0, 1, 2, 5], [0, 1, 2, 5, 3]], dtype=np.int32)
    cells = np.array([[0, 1, 2]])
    want = [[0, 0, 2], [0, 0, 1], [0, 1, 2]]
    assert cell_structure(face, simp[cells], 6, 2)[0].tolist() == want
    assert native_edges(face, simp, cells).tolist() == want
    # every cell of a sampled Klein bottle (codimension 2), by cell size
    work, normals, centres, faces, ptr, cs, simp = _stage_inputs("flat-klein", 400)
    sizes = np.diff(ptr)
    for nv in np.unique(sizes):
        rows = np.flatnonzero(sizes == nv)
        ids = cs[ptr[rows][:, None] + np.arange(nv)]
        edges = native_edges(faces[rows], simp, ids)
        assert np.array_equal(edges, cell_structure(faces[rows], simp[ids], len(work), 2)[0])
        assert len(edges) == nv * len(rows)  # a polygon of nv vertices has nv edges


@pytest.mark.parametrize("name,n", [("torus", 600), ("flat-klein", 400), ("torus-r5", 120)])
def test_literal_test_on_triangles_compiled_equals_numpy_bit_for_bit(monkeypatch, name, n):
    # codimension 1, 2 and 3: the compiled _literal does numpy's arithmetic operation for operation
    from crustview.core.paper import literal

    work, normals, centres, faces, ptr, cs, simp = _stage_inputs(name, n)
    assert literal._native is not None and faces.shape[1] == 3  # setup.py builds it
    native = cand.literal_angles(work[: len(normals)], normals, faces)
    monkeypatch.setattr(literal, "_native", None)
    assert np.array_equal(cand.literal_angles(work[: len(normals)], normals, faces), native)
    from crustview.core.delaunay import _literal

    with pytest.raises(ValueError, match="outside"):
        _literal.literal(work, normals, np.full((1, 3), 10**9, dtype=np.int64), work.shape[1], normals.shape[2])


@pytest.mark.parametrize("k,d,n", [(3, 2, 2000), (4, 2, 400), (4, 1, 300), (5, 4, 300)])
def test_face_lists_on_two_threads_equal_one_thread(k, d, n):
    # from 2**20 records the compiled _faces sorts on two threads: the same arrays (here forced from 2 records)
    from crustview.core.delaunay import _faces

    rng = np.random.default_rng(3)
    simp = delaunay(rng.normal(size=(n, k)), bounding_points(k))
    w = simp.shape[1]
    before = _faces.second_threads()
    one = _faces.faces(simp, w, d + 1, n, 2**62)
    assert _faces.second_threads() == before  # one thread
    two = _faces.faces(simp, w, d + 1, n, 2)
    assert _faces.second_threads() >= before + 2  # the instances and the sort each on two threads
    assert one == two and one == _faces.faces(simp, w, d + 1, n)
    if d == k - 1:
        simp2, nbrs = delaunay(rng.normal(size=(n, k)), bounding_points(k), neighbors=True)
        before = _faces.second_threads()
        one = _faces.facets(simp2, nbrs, w, n, 2**62)
        assert _faces.second_threads() == before
        two = _faces.facets(simp2, nbrs, w, n, 2)
        assert _faces.second_threads() > before
        assert one == two and one == _faces.facets(simp2, nbrs, w, n)


def test_compiled_face_lists_and_cell_edges_refuse_bad_input_with_one_line():
    # a negative vertex id would index the counting sort's buckets: a ValueError, not a crash
    from crustview.core.delaunay import _cellpass, _faces

    with pytest.raises(ValueError, match="negative"):
        _faces.faces(np.array([[-1, 0, 1, 2]], np.int32), 4, 3, 3)
    with pytest.raises(ValueError, match="outside"):  # a cell naming simplex 7 of a table of one
        _cellpass.cell_edges(np.zeros((1, 3), np.int64), np.zeros((1, 5), np.int32), np.full((1, 1), 7), 3, 5, 1)
    with pytest.raises(ValueError, match="without its face"):  # a simplex that does not hold the face
        simp = np.array([[3, 4, 5, 6, 7]], np.int32)
        _cellpass.cell_edges(np.array([[0, 1, 2]]), simp, np.zeros((1, 1), np.int64), 3, 5, 1)


def test_faces_grouped_by_cell_size_compiled_equal_numpy_and_a_hand_case(monkeypatch):
    # by hand: cell sizes 3, 2, 3, 5, 2 -> sizes 2 (faces 1, 4), 3 (faces 0, 2), 5 (face 3)
    ptr = np.array([0, 3, 5, 8, 13, 15], np.int64)
    want = [(2, [1, 4]), (3, [0, 2]), (5, [3])]
    rng = np.random.default_rng(4)
    cases = [ptr, np.concatenate([[0], np.cumsum(rng.integers(3, 60, 20_000))]).astype(np.int64)]
    got = [cand.size_groups(p) for p in cases]
    assert [(v, r.tolist()) for v, r in got[0]] == want
    monkeypatch.setattr(cand, "_native_cellpass", None)
    for p, compiled in zip(cases, got, strict=True):
        plain = cand.size_groups(p)
        assert [v for v, _ in plain] == [v for v, _ in compiled]
        assert all(np.array_equal(a, b) for (_, a), (_, b) in zip(plain, compiled, strict=True))


def test_compiled_size_groups_refuse_decreasing_pointers_with_one_line():
    from crustview.core.delaunay import _cellpass

    with pytest.raises(ValueError, match="must not decrease"):
        _cellpass.size_groups(np.array([0, 3, 2], np.int64))


@pytest.mark.parametrize("native", [True, False])
@pytest.mark.parametrize("name,n", [("torus", 600), ("flat-klein", 400), ("circle-r4", 60)])
def test_the_scoring_threads_minimum_is_the_cocone_tests_verdict(monkeypatch, name, n, native):
    # codimension 1 (chunks), 2 (the compiled pass) and 3; the minimum made beside the angles, in many
    # small chunks on two threads, equals the column-by-column reduction of the finished angles
    from crustview.core.result import CandidateAngles

    work, normals, centres, faces, ptr, cs, simp = _stage_inputs(name, n)
    if not native:
        monkeypatch.setattr(cand, "_native_cellpass", None)
        monkeypatch.setattr(cand, "_native_segments", None)
    monkeypatch.setattr(cand, "CHUNK_CELL_VERTICES", 200)
    low = np.full(len(faces), np.nan)
    coc = cand.cocone_angles(work, normals, centres, faces, ptr, cs, simplices=simp, workers=2, minimum=low)
    want = CandidateAngles(np.zeros(len(faces)), coc)["cocone"]
    assert low.tobytes() == want.tobytes() and np.all(low <= coc.max(axis=1))
    assert CandidateAngles(np.zeros(len(faces)), coc, cocone=low)["cocone"] is low
