"""The compiled counts of a triangle complex (``util/_surface.cpp``) against the general-d report."""

import itertools

import numpy as np
import pytest
from test_core_extraction import OCTA, grid_surface

from crustview.core.analysis import ranks, topology
from crustview.core.analysis.topology import _analyse_general, _surface_report, analyse, is_closed_manifold


def test_the_compiled_kernel_is_built():
    """The install builds it (scripts/install.sh)."""
    assert topology._surface is not None


RP2 = np.array(
    [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5], [0, 5, 1], [1, 2, 4], [2, 3, 5], [3, 4, 1], [4, 5, 2], [5, 1, 3]]
)
#: The five-vertex Moebius band: triangles (i, i+1, i+2) mod 5; edges (i, i+1) inner, (i, i+2) its one rim.
MOEBIUS = np.array([[i, (i + 1) % 5, (i + 2) % 5] for i in range(5)])
#: An annulus of eight triangles: a ring 0-3 below, 4-7 above, no twist.
ANNULUS = np.array([t for i in range(4) for t in ([i, (i + 1) % 4, i + 4], [(i + 1) % 4, (i + 1) % 4 + 4, i + 4])])


def _general_closed(tris: np.ndarray, monkeypatch: pytest.MonkeyPatch) -> bool:
    with monkeypatch.context() as m:
        m.setattr(topology, "_surface", None)
        return is_closed_manifold(tris, 2)


def _pinched() -> np.ndarray:
    other = OCTA + 5
    other[other == 5] = 0  # two octahedra sharing one vertex
    return np.vstack([OCTA, other])


def _complexes(rng: np.random.Generator) -> list[tuple[str, np.ndarray, int]]:
    torus, klein = grid_surface(6, 7), grid_surface(6, 7, klein=True)
    cases = [
        ("octahedron", OCTA, 6),
        ("projective plane", RP2, 6),
        ("torus", torus, 42),
        ("klein bottle", klein, 42),
        ("pinched octahedra", _pinched(), 11),
        ("disc", np.array([[0, 1, 2], [0, 2, 3]]), 6),
        ("moebius band", MOEBIUS, 5),
        ("annulus", ANNULUS, 8),
        ("shuffled rows and columns", rng.permuted(torus[rng.permutation(len(torus))], axis=1), 50),
        ("torus, klein bottle and octahedron apart", np.vstack([torus, klein + 42, OCTA + 84]), 95),
        # two tori glued along a grid circle would be non-manifold; glued at a vertex: pinched, two cycles
        ("tori at a vertex", np.vstack([torus, np.where(torus == 0, 0, torus + 41)]), 83),
    ]
    for i in range(12):  # punched surfaces: holes, closed and open parts, isolated triangles
        tris = np.vstack([torus, klein + 42, OCTA + 84, RP2 + 90])
        keep = rng.random(len(tris)) > rng.choice([0.02, 0.1, 0.4, 0.8])
        cases.append((f"punched {i}", tris[keep], 100))
    # a wedge of three triangles at an edge: non-manifold, left to the general code
    cases.append(("fin on an octahedron", np.vstack([OCTA, [[0, 2, 7]]]), 8))
    # a triangle listed twice (once reversed) on its own, and beside a torus: the general code counts it once
    cases.append(("a triangle twice", np.array([[0, 1, 2], [2, 1, 0]]), 3))
    cases.append(("a triangle twice beside a torus", np.vstack([torus, [[42, 43, 44], [42, 43, 44]]]), 45))
    return cases


def test_the_compiled_report_is_the_general_one(monkeypatch):
    rng = np.random.default_rng(3)
    for name, tris, n in _complexes(rng):
        tris = np.asarray(tris, np.int64)
        want = _analyse_general(tris, n, 2)
        got = _surface_report(tris, n)
        twice = len(np.unique(np.sort(tris, axis=1), axis=0)) < len(tris)
        if want.nonmanifold_faces or twice:
            assert got is None, name  # rank d_2 needs the elimination; a repeated row is counted once
        else:
            assert got == want, name
        assert analyse(tris, n, 2) == want, name
        assert is_closed_manifold(tris, 2) == _general_closed(tris, monkeypatch) == want.closed_manifold, name


def test_known_answers_from_the_compiled_counts():
    # worked by hand: V - E + F and the orientation of each
    for tris, n, betti, euler, orient in (
        (OCTA, 6, (1, 0, 1), 2, True),
        (RP2, 6, (1, 1, 1), 1, False),
        (grid_surface(4, 5), 20, (1, 2, 1), 0, True),
        (grid_surface(4, 5, klein=True), 20, (1, 2, 1), 0, False),
    ):
        rep = _surface_report(np.asarray(tris, np.int64), n)
        assert rep.closed_manifold and rep.betti == betti and rep.euler == euler and rep.orientable is orient
    pinched = _surface_report(_pinched(), 11)
    assert not pinched.closed_manifold and pinched.singular_vertices == 1 and pinched.betti == (1, 0, 2)
    disc = _surface_report(np.array([[0, 1, 2], [0, 2, 3]]), 6)
    assert disc.boundary_faces == 4 and disc.unused_samples == 2 and disc.betti == (1, 0, 0)
    assert disc.orientable is True and disc.messages[-1] == "2 of 6 samples are not vertices of the complex"
    # with a boundary: V - E + F = 5 - 10 + 5 and 8 - 16 + 8, one rim and two; only the band's half twist
    # makes two triangles at an inner edge disagree
    for tris, n, rims, orient in ((MOEBIUS, 5, 5, False), (ANNULUS, 8, 8, True)):
        for rep in (_surface_report(tris, n), _analyse_general(tris, n, 2)):
            assert rep.betti == (1, 1, 0) and rep.euler == 0 and rep.boundary_faces == rims
            assert rep.orientable is orient
    fin = _analyse_general(np.vstack([MOEBIUS, [[0, 1, 7]]]), 8, 2)  # an edge in three triangles
    assert fin.nonmanifold_faces == 1 and fin.orientable is None


def test_a_triangle_repeating_a_vertex_goes_to_the_general_code():
    tris = np.vstack([OCTA, [[1, 1, 2]]])
    assert _surface_report(tris, 6) is None
    assert analyse(tris, 6, 2) == _analyse_general(tris, 6, 2)


def test_a_delaunay_surface_and_its_parts(torus_run, monkeypatch):
    rec, _ = torus_run
    m_s = np.asarray(rec.manifold, np.int64)
    rng = np.random.default_rng(0)
    for tris in (m_s, m_s[rng.random(len(m_s)) > 0.01], m_s[: len(m_s) // 2], m_s[::-1]):
        assert _surface_report(tris, rec.n) == _analyse_general(tris, rec.n, 2)
        assert is_closed_manifold(tris, 2) == _general_closed(tris, monkeypatch)
    # every triangle of the tetrahedra at some samples: non-manifold edges
    tets = rec.delaunay_simplices[(rec.delaunay_simplices < rec.n).all(axis=1)][:200]
    soup = np.unique(
        np.sort(np.vstack([tets[:, list(c)] for c in itertools.combinations(range(4), 3)]), axis=1), axis=0
    )
    assert _surface_report(soup, rec.n) is None
    assert analyse(soup, rec.n, 2) == _analyse_general(soup, rec.n, 2)


def test_the_compiled_edge_table_is_numpys_facet_structure(torus_run, monkeypatch):
    from crustview.core.paper import facets

    rec, _ = torus_run
    rng = np.random.default_rng(5)
    t_s = np.asarray(rec.candidates.select(rec.test, rec.theta), np.int64)  # edges in 1-6 triangles
    cases = [t.astype(np.int64) for _, t, _ in _complexes(rng)]
    cases += [t_s, t_s[rng.permutation(len(t_s))], rng.permuted(t_s, axis=1), OCTA[:1]]
    for tris in cases:
        for positions in (False, True):
            got = facets.facet_structure(tris, positions)
            with monkeypatch.context() as m:
                m.setattr(facets, "_surface", None)
                want = facets.facet_structure(tris, positions)
            for g, w in zip(got, want, strict=True):
                assert g.dtype == w.dtype and np.array_equal(g, w)
    assert facets._edge_structure(np.array([[0, 0, 1]])) is None  # a repeated vertex: numpy's table
    assert np.diff(facets.facet_structure(t_s)[2]).max() > 2  # T_S has edges in three triangles and more


def test_the_compiled_triangle_edges_are_numpys(torus_run, monkeypatch):
    from crustview.core.analysis import cotree

    rec, _ = torus_run
    rng = np.random.default_rng(11)
    m_s = np.asarray(rec.manifold)
    cases = [t for _, t, _ in _complexes(rng)] + [m_s, m_s.astype(np.int32), rng.permuted(m_s, axis=1)[::-1]]
    for tris in cases:
        got = cotree.triangle_edges(tris)
        with monkeypatch.context() as m:
            m.setattr(cotree, "_surface", None)
            want = cotree.triangle_edges(tris)
        assert cotree._compiled_edges(tris) is not None
        for g, w in zip(got, want, strict=True):
            assert g.dtype == w.dtype and np.array_equal(g, w)
    repeated = np.array([[0, 1, 1], [0, 1, 2]])
    assert cotree._compiled_edges(repeated) is None
    assert [e.tolist() for e in cotree.triangle_edges(repeated)] == [
        [[0, 1], [0, 2], [1, 1], [1, 2]],
        [[0, 2, 0], [0, 3, 1]],
    ]


def test_huge_vertex_ids_take_numpys_tables():
    # a few triangles over ids near 2^40: the kernels would index a table that long, numpy sorts six entries
    from crustview.core.analysis import cotree
    from crustview.core.paper import facets

    big = (OCTA[:2] + (1 << 40)).astype(np.int64)
    assert topology._surface_counts(big) is None and facets._edge_structure(big) is None
    assert cotree._compiled_edges(big) is None
    assert analyse(big, 6, 2).boundary_faces == 4 and len(cotree.triangle_edges(big)[0]) == 5
    assert len(facets.facet_structure(big)[0]) == 5


def test_tables_too_large_for_memory_raise_memoryerror_instead_of_aborting():
    # the kernels' vectors throw std::bad_alloc / std::length_error; the process must get a MemoryError
    import subprocess
    import sys

    code = (
        "import resource, numpy as np\n"
        "from crustview.core.util import _surface as S\n"
        "from crustview.core.analysis import _gf2\n"
        "resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))\n"
        "for call in (lambda: S.surface_report(1 << 40, np.array([[0, 1, 2]], np.int64)),\n"
        "             lambda: S.edge_structure(1 << 40, np.array([[0, 1, 2]], np.int64)),\n"
        "             lambda: _gf2.rank(np.array([[0, 1]], np.int64), 1 << 40, 2)):\n"
        "    try:\n"
        "        call()\n"
        "    except MemoryError:\n"
        "        print('MemoryError')\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["MemoryError"] * 3


# ---------------------------------------------------------------- the boundary ranks over GF(2) (_gf2.cpp)
def test_the_compiled_rank_is_built():
    """The install builds it (scripts/install.sh)."""
    assert ranks._gf2 is not None


def _dense_rank_gf2(cols: list[list[int]], rows: int) -> int:
    """Gaussian elimination on a dense 0/1 matrix: a third way, sharing nothing with the other two."""
    m = np.zeros((rows, len(cols)), dtype=np.uint8)
    for j, col in enumerate(cols):
        for r in col:
            m[r, j] ^= 1
    rank = 0
    for c in range(m.shape[1]):
        below = np.flatnonzero(m[rank:, c]) + rank
        if len(below) == 0:
            continue
        m[[rank, below[0]]] = m[[below[0], rank]]
        others = np.flatnonzero(m[:, c])
        others = others[others != rank]
        m[others] ^= m[rank]
        rank += 1
        if rank == rows:
            break
    return rank


def test_boundary_ranks_worked_out_by_hand():
    """The boundary of a tetrahedron (S^2): 4 triangles on 6 edges, rank 3 (their sum is the one cycle);
    K4's 6 edges on 4 vertices, rank 3.  The boundary of a 4-simplex (S^3): 5 tetrahedra, rank 4;
    10 triangles on 10 edges, rank 10 - rank d1 (4) - b1 (0) = 6.  The six-vertex projective plane:
    10 triangles on 15 edges, rank 9 (b2 = 1 over Z/2)."""
    tet = np.array(list(itertools.combinations(range(4), 3)))
    simplex4 = np.array(list(itertools.combinations(range(5), 4)))
    cases = [(tet, 2, 3), (tet, 1, 3), (simplex4, 3, 4), (simplex4, 2, 6), (RP2, 2, 9)]
    for simplices, j, want in cases:
        faces = topology.all_faces(simplices)
        assert topology.boundary_rank_gf2(faces[j], faces[j - 1]) == want, (len(simplices), j)
        assert ranks.boundary_rank_gf2_python(faces[j], faces[j - 1]) == want, (len(simplices), j)


def test_the_compiled_rank_matches_python_and_a_dense_elimination_on_random_columns():
    """Columns of 2-4 rows, some named twice (they cancel), some all cancelled, narrow and wide."""
    rng = np.random.default_rng(5)
    for trial in range(40):
        rows = int(rng.integers(1, 60))
        width = int(rng.integers(2, 5))
        n_cols = int(rng.integers(1, 90))
        cols = rng.integers(0, rows, size=(n_cols, width))
        if trial % 4 == 0:
            cols[:, 1] = cols[:, 0]  # a row twice in every column
        want = _dense_rank_gf2(cols.tolist(), rows)
        got = ranks._gf2.rank(np.ascontiguousarray(cols, dtype=np.int64), rows, width)
        assert got == want == ranks._reduce_python(cols), (trial, got, want)


def test_the_compiled_rank_refuses_entries_outside_the_rows():
    with pytest.raises(ValueError, match="not a row"):
        ranks._gf2.rank(np.array([[0, 3]], dtype=np.int64), 3, 2)
    with pytest.raises(ValueError, match="width"):
        ranks._gf2.rank(np.array([0, 1, 2], dtype=np.int64), 3, 2)


def test_a_3_manifolds_report_is_the_same_with_and_without_the_compiled_rank(s3_run, monkeypatch):
    """S^3 in R^4 (the general code: d = 3) and the same complex with a tetrahedron removed (open)."""
    rec, _ = s3_run
    tets = np.asarray(rec.manifold)
    for simplices in (tets, tets[1:]):
        compiled = topology._analyse_general(simplices, len(rec.points), 3)
        with monkeypatch.context() as m:
            m.setattr(ranks, "_gf2", None)
            python = topology._analyse_general(simplices, len(rec.points), 3)
        assert compiled == python
    assert topology._analyse_general(tets, len(rec.points), 3).betti == (1, 0, 0, 1)
