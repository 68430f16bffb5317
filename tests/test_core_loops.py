"""The loop basis's compiled shortest-path trees (core/analysis/_paths.cpp) against scipy."""

import numpy as np
import pytest


def test_compiled_shortest_path_trees_are_scipys():
    # loops.shortest_path_trees (core/analysis/_paths.cpp) against scipy's dijkstra: random lengths on a
    # mesh's edges with an unreached piece, and a unit grid, whose ties send its roots to scipy
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    from crustview.core.analysis import loops

    rng = np.random.default_rng(0)
    graphs = []
    n = 3000
    e = rng.integers(0, n - 100, size=(9000, 2))  # nodes n - 100 .. n - 1 are unreached
    graphs.append((n, e, rng.random(len(e)) + 1e-3))
    side = 30
    idx = np.arange(side * side).reshape(side, side)
    grid = np.concatenate([np.c_[idx[:, :-1].ravel(), idx[:, 1:].ravel()], np.c_[idx[:-1].ravel(), idx[1:].ravel()]])
    graphs.append((side * side, grid, np.ones(len(grid))))
    for n, e, w in graphs:
        g = coo_matrix((w, (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
        g = g + g.T
        roots = [0, 5, int(e[-1, 0]), 17]
        dist, pred = loops.shortest_path_trees(g, roots)
        want_dist, want_pred = dijkstra(g, indices=roots, return_predecessors=True)
        assert dist.dtype == want_dist.dtype and pred.dtype == want_pred.dtype
        assert np.array_equal(dist, want_dist) and np.array_equal(pred, want_pred)
        ties = loops._paths.shortest_paths(g.indptr, g.indices, g.data, np.asarray(roots, np.int64), 2)[2]
        assert set(ties) == ({1} if n == side * side else {0})  # the grid's roots went to scipy, the others not


def _compiled_trees(g, roots):  # noqa: ANN001, ANN202 - the extension's own arrays, before scipy takes flagged roots
    from crustview.core.analysis import loops

    n = g.shape[0]
    raw = loops._paths.shortest_paths(
        g.indptr.astype(np.int32),
        g.indices.astype(np.int32),
        np.ascontiguousarray(g.data, np.float64),
        np.asarray(roots, np.int64),
        2,
    )
    dist = np.frombuffer(raw[0], np.float64).reshape(len(roots), n)
    pred = np.frombuffer(raw[1], np.int32).reshape(len(roots), n)
    return dist, pred, np.frombuffer(raw[2], np.uint8).astype(bool)


def test_a_root_is_sent_to_scipy_only_where_the_order_at_one_distance_shows():
    # _paths.cpp flags a root only where two nodes at one distance offer a third the same distance (its
    # predecessor is then the queue's choice); every root it keeps gives scipy's arrays exactly. Checked on
    # random graphs with many ties (small integer lengths, zeros, all ones) and on two small ones by hand:
    # a path through the root (two nodes at each distance, no common neighbour: kept), a diamond
    # (0-1, 0-2, 1-3, 2-3 all of length 1: node 3's predecessor is 1 or 2 by the queue's order: flagged)
    # and the same kite with 2-3 of length 2 (1 and 2 still tie, but offer 3 different distances: kept)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    def graph(n, e, w):  # noqa: ANN001, ANN202
        e = np.asarray(e)
        g = coo_matrix((np.asarray(w, float), (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
        return (g + g.T).tocsr()

    path = graph(7, [(i, i + 1) for i in range(6)], np.ones(6))
    diamond = graph(4, [(0, 1), (0, 2), (1, 3), (2, 3)], np.ones(4))
    assert not _compiled_trees(path, [3])[2][0]  # nodes 2 and 4 at 1, 1 and 5 at 2: no shared offer
    kite = graph(4, [(0, 1), (0, 2), (1, 3), (2, 3)], [1, 1, 1, 2])  # 1 and 2 tie, but offer 3 two distances
    assert _compiled_trees(diamond, [0])[2][0] and not _compiled_trees(kite, [0])[2][0]
    rng = np.random.default_rng(5)
    kept = 0
    for trial in range(160):
        n = int(rng.integers(5, 300))
        e = rng.integers(0, n, size=(int(rng.integers(n, 4 * n)), 2))
        e = e[e[:, 0] != e[:, 1]]
        w = (rng.integers(1, 4, len(e)), rng.integers(0, 3, len(e)), rng.random(len(e)), np.ones(len(e)))[trial % 4]
        g = graph(n, e, w)
        roots = rng.integers(0, n, size=5)
        dist, pred, flagged = _compiled_trees(g, roots)
        want_dist, want_pred = dijkstra(g, indices=roots, return_predecessors=True)
        for i in np.flatnonzero(~flagged):
            assert np.array_equal(dist[i], want_dist[i]) and np.array_equal(pred[i], want_pred[i])
        kept += int((~flagged).sum())
    assert kept > 100  # roots with tied distances that no longer go to scipy (was: none with a tie)


def test_compiled_path_masks_are_the_pointer_doubling_ones(monkeypatch):
    # loops._path_masks by one walk per vertex (_paths.path_xor) against its numpy pointer doubling, on
    # random forests with unreached vertices (scipy's -9999) and masks of one and three words
    from crustview.core.analysis import loops

    assert loops._paths is not None  # the kernel compared below is built
    rng = np.random.default_rng(1)
    for n, words in ((1, 1), (50, 1), (5000, 3)):
        pred = np.array([rng.integers(-1, v) if v else -9999 for v in range(n)], dtype=np.int32)  # parents first
        pred[pred == -1] = -9999
        perm = rng.permutation(n)  # the same forest under other names: children before parents too
        inv = np.argsort(perm)
        pred = np.where(pred[perm] >= 0, inv[np.maximum(pred[perm], 0)], -9999).astype(np.int32)
        kids = np.flatnonzero(pred >= 0)
        pick = rng.choice(kids, size=min(len(kids), 40), replace=False)
        marked = np.stack([pick, pred[pick]], axis=1)
        marked[::2] = marked[::2, ::-1]  # either end first
        mask = rng.integers(0, 2**63, size=(len(marked), words), dtype=np.uint64)
        compiled = loops._path_masks(pred, marked, mask)
        monkeypatch.setattr(loops, "_paths", None)
        reference = loops._path_masks(pred, marked, mask)
        monkeypatch.undo()
        assert compiled.dtype == reference.dtype and np.array_equal(compiled, reference)


def _rank_gf2(rows: list[np.ndarray]) -> int:
    """Rank over Z/2 of bit rows (uint8 0/1 arrays), by plain row reduction on a dense bit matrix."""
    if not rows:
        return 0
    m = np.array(rows, dtype=np.uint8) % 2
    rank = 0
    for col in range(m.shape[1]):
        hit = np.flatnonzero(m[rank:, col]) + rank
        if len(hit) == 0:
            continue
        m[[rank, hit[0]]] = m[[hit[0], rank]]
        below = np.flatnonzero(m[:, col])
        below = below[below != rank]
        m[below] ^= m[rank]
        rank += 1
        if rank == len(m):
            break
    return rank


def test_the_loop_basis_takes_each_candidate_exactly_when_it_raises_the_rank():
    # loops._independent (Python integers, pivot at the highest bit) against the definition: a candidate,
    # in the given order, is taken when the rank over Z/2 of the taken ones and it exceeds the taken
    # ones' rank; masks of one and three 64-bit words (bits across word boundaries), many dependent
    # candidates (sums of earlier ones), zero rows, and the stop at the wanted rank
    from crustview.core.analysis import loops

    rng = np.random.default_rng(3)
    for words, count, rank in ((1, 40, 64), (3, 200, 30), (3, 200, 192)):
        bits = 64 * words
        base = rng.integers(0, 2, size=(12, bits), dtype=np.uint8)
        rows = [base[i] for i in range(12)]
        for _ in range(count - 12):
            pick = rng.random() < 0.7
            rows.append(
                base[rng.random(12) < 0.5].sum(axis=0) % 2 if pick else rng.integers(0, 2, bits).astype(np.uint8)
            )
        rows.append(np.zeros(bits, np.uint8))
        packed = np.array([np.packbits(r, bitorder="little").view("<u8") for r in rows])
        order = rng.permutation(len(rows))
        got = loops._independent(packed, order, rank)
        want, taken = [], []
        for i in order.tolist():
            if len(want) == rank:
                break
            if _rank_gf2(taken + [rows[i]]) > len(taken):
                taken.append(rows[i])
                want.append(i)
        assert got == want


def _torus_mesh(a: int = 24, b: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """A triangulated torus (a x b grid, each square split in two): b1 = 2."""
    u, v = np.meshgrid(np.arange(a), np.arange(b), indexing="ij")
    t, p = 2 * np.pi * u.ravel() / a, 2 * np.pi * v.ravel() / b
    pts = np.c_[(2 + 0.7 * np.cos(p)) * np.cos(t), (2 + 0.7 * np.cos(p)) * np.sin(t), 0.7 * np.sin(p)]
    idx = np.arange(a * b).reshape(a, b)
    i0, i1 = idx, np.roll(idx, -1, axis=0)
    j0, j1 = i0, np.roll(i0, -1, axis=1)
    k1 = np.roll(i1, -1, axis=1)
    tris = np.concatenate([np.c_[i0.ravel(), i1.ravel(), k1.ravel()], np.c_[j0.ravel(), k1.ravel(), j1.ravel()]])
    return pts, tris


def test_cocycles_only_gives_the_full_search_s_cocycles():
    """short_basis(..., cocycles_only=True) fills the same cocycles as the full search (they come from the
    tree-cotree split before it) and returns no loop; the full search finds the torus's two."""
    from crustview.core.analysis import loops

    pts, tris = _torus_mesh()
    edges, tri_edges = loops.triangle_edges(tris)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    full: dict = {}
    basis = loops.short_basis(pts, tris, edges, tri_edges, count, len(pts), cocycles=full)
    only: dict = {}
    assert loops.short_basis(pts, tris, edges, tri_edges, count, len(pts), cocycles=only, cocycles_only=True) == []
    assert len(basis) == 2 and set(only) == set(full) == {"mask", "edge_ids", "graph"}
    assert np.array_equal(only["mask"], full["mask"]) and only["mask"].any()
    assert (only["graph"] != full["graph"]).nnz == 0
    assert np.array_equal(only["edge_ids"](tris[:, 0], tris[:, 1]), full["edge_ids"](tris[:, 0], tris[:, 1]))


def test_handles_only_gives_the_same_handles():
    """features(..., handles_only=True) lists exactly the handle features of the full report, and nothing else,
    on a torus with a hole cut in it (so the full report also has a hole)."""
    from crustview.core.analysis.features import features

    pts, tris = _torus_mesh()
    tris = tris[3:]  # a hole of three triangles
    full = features(pts, tris, 2, tighten_loops=False)
    only = features(pts, tris, 2, tighten_loops=False, handles_only=True)
    assert {f.kind for f in full} >= {"hole", "handle"} and {f.kind for f in only} == {"handle"}
    want = [f for f in full if f.kind == "handle"]
    assert len(only) == len(want) == 2
    for f, g in zip(only, want, strict=True):
        assert f.size_spacings == g.size_spacings and np.array_equal(f.vertices, g.vertices)


def test_spread_roots_are_the_norm_based_ones():
    """_spread's in-place distances give numpy's norm bit for bit, so the same roots as the plain
    farthest-point sampling with np.linalg.norm (_spread_numpy, the loop as it was), at any scale and
    dimension; on paper: of a square's corners, the opposite one comes after the first."""
    from crustview.core.analysis.loops import _spread, _spread_numpy

    def reference(points, vs, k):
        return _spread_numpy(points[vs], vs, k)

    square = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    assert _spread(square, np.arange(4), 2) == [0, 2]
    rng = np.random.default_rng(7)
    for dim in (2, 3, 4, 7, 8, 9, 10):
        for scale in (1e-6, 1.0, 1e6):
            q = rng.normal(size=(4000, dim)) * scale
            vs = np.sort(rng.choice(4000, 3000, replace=False))
            assert _spread(q, vs, 12) == reference(q, vs, 12)
    dup = np.zeros((5, 3))  # every vertex the same: one root
    assert _spread(dup, np.arange(5), 12) == [0]


def test_spread_distances_are_numpy_s_norms_bit_for_bit():
    """The distance rows _spread takes its maxima of equal the norm-based ones, value for value, so no near
    tie can go the other way (below 8 coordinates; from 8 on _spread is the norm-based loop itself)."""
    from crustview.core.analysis.loops import _distances_to

    rng = np.random.default_rng(11)
    for dim in (1, 2, 3, 5, 7):
        for scale in (1e-6, 1.0, 1e6):
            q = rng.normal(size=(2000, dim)) * scale
            cols = np.ascontiguousarray(q.T)
            for j in (0, 17, 1999):
                assert np.array_equal(_distances_to(cols, j), np.linalg.norm(q - q[j], axis=1))


def test_compiled_edge_triangles_and_dual_forest_are_numpys_and_scipys(monkeypatch):
    # cotree.edge_triangles and cotree.bfs_forest (core/analysis/_paths.cpp) against the stable sort and
    # scipy's breadth-first search, component by component from its smallest node: on a noisy torus's
    # M_S (its dual graph through every inner edge, and through a random half, many components) and on
    # random graphs with isolated nodes, repeated edges and edges given in both directions
    from crustview.core import reconstruct
    from crustview.core.analysis import cotree
    from crustview.core.analysis.loops import triangle_edges
    from crustview.core.samples.manifolds import get_manifold

    assert cotree._paths is not None  # the kernel compared below is built
    rng = np.random.default_rng(3)
    rec = reconstruct(get_manifold("torus").sample(800, seed=2, noise=0.005).points, 2)
    edges, tri_edges = triangle_edges(rec.manifold)
    cases = []
    for keep in (np.ones(len(edges), bool), rng.random(len(edges)) < 0.5):
        compiled = cotree.edge_triangles(tri_edges, len(edges))
        assert (compiled >= 0).all()  # a closed surface: two triangles at every edge
        e = np.flatnonzero(keep)
        cases.append((len(tri_edges), compiled[e, 0], compiled[e, 1]))
    # three triangles at an edge, an edge of none: first and last triangle, -1 where none
    odd = np.array([[0, 1, 2], [2, 3, 4], [2, 5, 6], [7, 8, 0]])
    cases_e = [(tri_edges, len(edges)), (odd, 10)]
    for te, m in cases_e:
        got = cotree.edge_triangles(te, m)
        monkeypatch.setattr(cotree, "_paths", None)
        want = cotree.edge_triangles(te, m)
        monkeypatch.undo()
        assert got.dtype == want.dtype and np.array_equal(got, want)
    assert cotree.edge_triangles(odd, 10)[2].tolist() == [0, 2] and cotree.edge_triangles(odd, 10)[9].tolist() == [
        -1,
        -1,
    ]
    for n in (1, 40, 2000):
        a = rng.integers(0, n, size=n)
        b = rng.integers(0, n, size=n)
        a, b = np.r_[a, b[:5]], np.r_[b, a[:5]]  # some edges twice, the other way round
        cases.append((n + 7, a, b))  # the last seven nodes isolated
    for n, a, b in cases:
        got = cotree.bfs_forest(n, a, b)
        monkeypatch.setattr(cotree, "_paths", None)
        want = cotree.bfs_forest(n, a, b)
        monkeypatch.undo()
        for x, y in zip(got, want):
            assert x.dtype == y.dtype == np.int64 and np.array_equal(x, y)
    # a path 2 - 0 - 1 and a lone node 3: roots are each component's smallest node
    parent, depth = cotree.bfs_forest(4, np.array([0, 0]), np.array([1, 2]))
    assert parent.tolist() == [-1, 0, 0, -1] and depth.tolist() == [0, 1, 1, 0]


def test_the_loop_basis_is_the_same_on_both_cores_and_in_line(monkeypatch):
    # short_basis with its trees beside the tree-cotree split and the roots' loops on a pool (above
    # PARALLEL_MIN vertices) against the same search in line: the same loops, lengths and cocycles
    from pathlib import Path

    from crustview.core import reconstruct
    from crustview.core.analysis import loops
    from crustview.core.samples.manifolds import get_manifold
    from crustview.io import read_mesh

    fertility = read_mesh(Path(__file__).resolve().parents[1] / "resources" / "fertility.off").points  # genus 4
    for points in (get_manifold("torus").sample(1500, seed=4).points, fertility):
        rec = reconstruct(points, 2)
        tris = rec.manifold
        edges, tri_edges = loops.triangle_edges(tris)
        count = np.bincount(tri_edges.ravel(), minlength=len(edges))
        got = {}
        for parallel_min in (0, 10**9):
            monkeypatch.setattr(loops, "PARALLEL_MIN", parallel_min)
            cocycles: dict = {}
            basis = loops.short_basis(rec.points, tris, edges, tri_edges, count, rec.n, cocycles=cocycles)
            got[parallel_min] = (basis, cocycles["mask"])
        (b1, m1), (b2, m2) = got.values()
        assert len(b1) == len(b2) == rec.topology.betti[1] and np.array_equal(m1, m2)
        for (loop1, len1), (loop2, len2) in zip(b1, b2):
            assert np.array_equal(loop1, loop2) and len1 == len2


def test_each_triangle_s_up_edge_is_the_first_edge_it_shares_with_its_dual_parent():
    # cotree.up_edges against its definition (the first of a triangle's three edge slots that its dual
    # parent also has) on triangle soups with repeated rows, where a triangle shares all three edges with
    # its twin, and without them; and the loop basis of a soup with a repeated triangle (a review's case)
    from crustview.core.analysis import cotree
    from crustview.core.analysis.loops import short_basis, triangle_edges

    rng = np.random.default_rng(5)
    for trial in range(300):
        n = int(rng.integers(4, 12))
        tris = np.sort(rng.integers(0, n, size=(int(rng.integers(2, 25)), 3)), axis=1)
        tris = tris[(tris[:, 0] < tris[:, 1]) & (tris[:, 1] < tris[:, 2])]
        if trial % 2:
            tris = np.concatenate([tris, tris[: len(tris) // 3]])  # repeated rows
        if len(tris) < 2:
            continue
        edges, tri_edges = triangle_edges(tris)
        e_tris = cotree.edge_triangles(tri_edges, len(edges))
        count = np.bincount(tri_edges.ravel(), minlength=len(edges))
        de = np.flatnonzero(count == 2)
        pair = (e_tris[de, 0], e_tris[de, 1])
        parent, _ = cotree.bfs_forest(len(tris), *pair)
        got = cotree.up_edges(tris, edges, tri_edges, parent, de, pair)
        for t in range(len(tris)):
            if parent[t] < 0:
                assert got[t] == -1
            else:
                want = next(e for e in tri_edges[t] if e in set(tri_edges[parent[t]].tolist()))
                assert got[t] == want, (trial, t)
    tris = np.array([[0, 1, 2], [0, 1, 2], [0, 1, 3], [0, 1, 4], [0, 3, 4], [1, 3, 4]])
    points = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, 0, 1], [0.5, 0, -1]], float)
    edges, tri_edges = triangle_edges(tris)
    count = np.bincount(tri_edges.ravel(), minlength=len(edges))
    basis = short_basis(points, tris, edges, tri_edges, count, len(points))
    # the old edge-triple comparison's basis: one loop, round the edge 0-1 through sample 3 (1 + 2 sqrt(1.25))
    assert [loop.tolist() for loop, _ in basis] == [[0, 1, 3, 0]]
    assert basis[0][1] == pytest.approx(1 + 2 * np.sqrt(1.25))
