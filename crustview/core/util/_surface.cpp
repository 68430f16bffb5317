// The edge table of a triangle complex (crustview.core.paper.facets.facet_structure for d = 2) and the
// counts of its topology report (crustview.core.analysis.topology: analyse and is_closed_manifold for
// d = 2), each in one pass per vertex.
//
// For triangles over vertex ids 0..n-1 (any k: only the combinatorics matter)
// it gives the numbers numpy's general-d code computes from its sorted facet
// table: the vertices used, the distinct edges, the edges in one triangle
// (boundary) and in more than two (non-manifold), the components of the edge
// graph; where no edge has more than two triangles, the components of the
// dual graph (triangles joined across their shared edges) that have no
// boundary edge (the rank of the top cycles) and whether the surface can be
// oriented (across its edges of two triangles; boundary edges ask nothing);
// where every edge has exactly two, the vertices whose link is not one circle.  Every number is an integer count, so the two ways agree
// exactly; tests/test_core_topology_compiled.py compares them.
//
// Each vertex v sees its incident triangles (a CSR table by counting); the
// edges (v, w) with w > v are v's to count, grouped by w among those
// triangles.  The link of v is one circle when v's triangles are joined, across
// the edges at v, into one fan.  Orientation: a triangle's sorted row (x < y <
// z) is its reference orientation; two triangles at an edge opposite their
// sorted positions q1, q2 are consistent with equal signs when q1 + q2 is odd
// (they then run through the edge in opposite directions), with opposite signs
// otherwise: a union-find with parities finds a contradiction if there is one.
// No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "_union_find.h"

namespace {

using i64 = std::int64_t;
using crustview::find;
using crustview::unite;

// Each row's three vertices in increasing order into tri; false where a row repeats a vertex.
bool sorted_rows(i64 f, const i64* rows, std::vector<i64>& tri) {
    tri.resize(static_cast<std::size_t>(3 * f));
    for (i64 t = 0; t < f; ++t) {
        i64 a = rows[3 * t], b = rows[3 * t + 1], c = rows[3 * t + 2];
        if (a == b || a == c || b == c) return false;
        if (a > b) std::swap(a, b);
        if (b > c) std::swap(b, c);
        if (a > b) std::swap(a, b);
        tri[3 * t] = a;
        tri[3 * t + 1] = b;
        tri[3 * t + 2] = c;
    }
    return true;
}

// Union-find whose nodes carry a parity to their parent: sign(node) = sign(root) xor parity(node).
struct ParityForest {
    std::vector<i64> parent;
    std::vector<unsigned char> parity;
    explicit ParityForest(i64 n) : parent(static_cast<std::size_t>(n)), parity(static_cast<std::size_t>(n), 0) {
        for (i64 i = 0; i < n; ++i) parent[i] = i;
    }
    std::pair<i64, unsigned char> find(i64 v) {
        unsigned char p = 0;
        i64 r = v;
        while (parent[r] != r) {
            p ^= parity[r];
            r = parent[r];
        }
        // compress: every node on the way points at the root with its own parity to it
        unsigned char q = p;
        while (parent[v] != v) {
            const i64 next = parent[v];
            const unsigned char pv = parity[v];
            parent[v] = r;
            parity[v] = q;
            q ^= pv;
            v = next;
        }
        return {r, p};
    }
    // Asks sign(a) xor sign(b) == rel; false if that contradicts what is known.
    bool relate(i64 a, i64 b, unsigned char rel) {
        auto [ra, pa] = find(a);
        auto [rb, pb] = find(b);
        if (ra == rb) return (pa ^ pb) == rel;
        if (ra < rb) {
            parent[rb] = ra;
            parity[rb] = pa ^ pb ^ rel;
        } else {
            parent[ra] = rb;
            parity[ra] = pa ^ pb ^ rel;
        }
        return true;
    }
};

struct Report {
    i64 vertices = 0, edges = 0, boundary = 0, nonmanifold = 0, components = 0;
    i64 top_cycles = -1, singular = -1, orientable = -1;
    bool repeated = false;  // a triangle listed twice (the general code counts it once): the caller's numpy code
};

Report report(i64 n, i64 f, const i64* rows) {
    Report out;
    std::vector<i64> tri;
    sorted_rows(f, rows, tri);  // the caller checked that no row repeats a vertex
    std::vector<i64> start(static_cast<std::size_t>(n + 1), 0);
    for (i64 e = 0; e < 3 * f; ++e) ++start[tri[e] + 1];
    for (i64 v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<i64> corner(static_cast<std::size_t>(3 * f));  // t * 3 + position, grouped by vertex
    {
        std::vector<i64> fill(start.begin(), start.end() - 1);
        for (i64 e = 0; e < 3 * f; ++e) corner[fill[tri[e]]++] = e;
    }
    std::vector<i64> vparent(static_cast<std::size_t>(n));
    for (i64 v = 0; v < n; ++v) vparent[v] = v;
    std::vector<i64> dual(static_cast<std::size_t>(f));
    for (i64 t = 0; t < f; ++t) dual[t] = t;
    std::vector<unsigned char> open(static_cast<std::size_t>(f), 0);
    // per edge owned by v: (w, corner of v in that triangle, position of the third vertex)
    struct Entry {
        i64 w, t, q;
    };
    std::vector<Entry> mine;
    std::vector<std::pair<i64, i64>> pairs;  // (t, q) of the two triangles at each manifold edge
    pairs.reserve(static_cast<std::size_t>(3 * f / 2 + 1));
    for (i64 v = 0; v < n; ++v) {
        if (start[v] == start[v + 1]) continue;
        ++out.vertices;
        mine.clear();
        for (i64 k = start[v]; k < start[v + 1]; ++k) {
            const i64 t = corner[k] / 3, p = corner[k] % 3;
            for (int o = 0; o < 3; ++o) {
                if (o == p) continue;
                const i64 w = tri[3 * t + o];
                if (w > v) mine.push_back({w, t, 3 - p - o});  // the third vertex's position
            }
        }
        std::sort(mine.begin(), mine.end(), [](const Entry& x, const Entry& y) {
            return x.w < y.w || (x.w == y.w && x.t < y.t);
        });
        for (std::size_t i = 0; i < mine.size();) {
            std::size_t j = i + 1;
            while (j < mine.size() && mine[j].w == mine[i].w) ++j;
            ++out.edges;
            unite(vparent, v, mine[i].w);
            const std::size_t c = j - i;
            // two rows at one edge are one triangle when their third vertices agree
            for (std::size_t k = i; k < j && !out.repeated; ++k)
                for (std::size_t l = k + 1; l < j; ++l)
                    if (tri[3 * mine[k].t + mine[k].q] == tri[3 * mine[l].t + mine[l].q]) out.repeated = true;
            if (c == 1) {
                ++out.boundary;
                open[mine[i].t] = 1;
            } else if (c > 2) {
                ++out.nonmanifold;
            } else {
                pairs.emplace_back(mine[i].t * 3 + mine[i].q, mine[i + 1].t * 3 + mine[i + 1].q);
            }
            i = j;
        }
    }
    if (out.repeated) return out;
    for (i64 v = 0; v < n; ++v)
        if (start[v] != start[v + 1] && find(vparent, v) == v) ++out.components;
    if (out.nonmanifold > 0) return out;
    for (const auto& [e1, e2] : pairs) unite(dual, e1 / 3, e2 / 3);
    std::vector<unsigned char> open_root(static_cast<std::size_t>(f), 0);
    for (i64 t = 0; t < f; ++t)
        if (open[t]) open_root[find(dual, t)] = 1;
    out.top_cycles = 0;
    for (i64 t = 0; t < f; ++t)
        if (find(dual, t) == t && !open_root[t]) ++out.top_cycles;
    // orientation, with or without boundary: a consistent sign for every triangle across its two-triangle edges
    ParityForest sign(f);
    bool ok = true;
    for (const auto& [e1, e2] : pairs) {
        const unsigned char rel = ((e1 % 3) + (e2 % 3)) % 2 == 1 ? 0 : 1;
        if (!sign.relate(e1 / 3, e2 / 3, rel)) {
            ok = false;
            break;
        }
    }
    out.orientable = ok ? 1 : 0;
    if (out.boundary > 0) return out;
    // a closed pseudo-surface: its links
    out.singular = 0;
    std::vector<i64> local;  // the fans around v: local union-find over v's corners
    std::vector<std::pair<i64, i64>> around;  // (other vertex, local corner)
    for (i64 v = 0; v < n; ++v) {
        const i64 s = start[v], deg = start[v + 1] - s;
        if (deg == 0) continue;
        local.resize(static_cast<std::size_t>(deg));
        for (i64 k = 0; k < deg; ++k) local[k] = k;
        around.clear();
        for (i64 k = 0; k < deg; ++k) {
            const i64 t = corner[s + k] / 3, p = corner[s + k] % 3;
            for (int o = 0; o < 3; ++o)
                if (o != p) around.emplace_back(tri[3 * t + o], k);
        }
        std::sort(around.begin(), around.end());
        i64 distinct = 0;
        for (std::size_t i = 0; i < around.size(); ++i) {
            if (i == 0 || around[i].first != around[i - 1].first) ++distinct;
            else unite(local, around[i - 1].second, around[i].second);
        }
        i64 fans = 0;
        for (i64 k = 0; k < deg; ++k)
            if (find(local, k) == k) ++fans;
        // the link's Euler characteristic (its vertices less its edges) and its connectedness
        if (distinct - deg != 0 || fans != 1) ++out.singular;
    }
    return out;
}

PyObject* surface_report(PyObject*, PyObject* args) {
    Py_buffer rows;
    long long n;
    if (!PyArg_ParseTuple(args, "Ly*", &n, &rows)) return nullptr;
    PyObject* result = nullptr;
    if (n < 0 || rows.len % 24 != 0) {
        PyErr_SetString(PyExc_ValueError, "surface_report: n >= 0 and int64 rows of three");
    } else {
        const i64 f = rows.len / 24;
        const i64* r = static_cast<const i64*>(rows.buf);
        bool ok = true, proper = true;
        for (i64 e = 0; e < 3 * f && ok; ++e) ok = r[e] >= 0 && r[e] < n;
        for (i64 t = 0; t < f && proper; ++t)
            proper = r[3 * t] != r[3 * t + 1] && r[3 * t] != r[3 * t + 2] && r[3 * t + 1] != r[3 * t + 2];
        if (!ok) {
            PyErr_SetString(PyExc_ValueError, "surface_report: a vertex id is outside 0..n-1");
        } else if (!proper) {
            Py_INCREF(Py_None);  // a triangle with a repeated vertex: the caller's general code
            result = Py_None;
        } else {
            Report out;
            bool failed = false;
            Py_BEGIN_ALLOW_THREADS;
            try {
                out = report(n, f, r);
            } catch (...) {  // std::bad_alloc, std::length_error: the tables did not fit
                failed = true;
            }
            Py_END_ALLOW_THREADS;
            if (failed) {
                PyErr_NoMemory();
            } else if (out.repeated) {
                Py_INCREF(Py_None);
                result = Py_None;
            } else {
                result = Py_BuildValue("(LLLLLLLL)", static_cast<long long>(out.vertices),
                                       static_cast<long long>(out.edges), static_cast<long long>(out.boundary),
                                       static_cast<long long>(out.nonmanifold),
                                       static_cast<long long>(out.components), static_cast<long long>(out.top_cycles),
                                       static_cast<long long>(out.singular), static_cast<long long>(out.orientable));
            }
        }
    }
    PyBuffer_Release(&rows);
    return result;
}

// The edges of a triangle complex as numpy's facet table builds them (crustview.core.paper.extraction.
// facet_structure): the distinct edges in lexicographic order, the edge of each sorted row opposite each
// position, and per edge the positions t * 3 + a holding it, increasing.  Vertex v lists the edges (v, w),
// w > v, of its triangles, sorted by (w, position): taken for v = 0, 1, ... that is the lexicographic order.
// false where a triangle repeats a vertex (an edge (v, v) is not v's to list: the caller's numpy code).
bool edge_table(i64 n, i64 f, const i64* rows, std::vector<i64>& edges, std::vector<i64>& facet_of,
                std::vector<i64>& ptr, std::vector<i64>& inc) {
    std::vector<i64> tri;
    if (!sorted_rows(f, rows, tri)) return false;
    // the lower end of each edge owns it: positions 0 and 1 own two edges each, position 0 of (a, b, c)
    // owns (a, b) opposite c and (a, c) opposite b, position 1 owns (b, c) opposite a
    std::vector<i64> start(static_cast<std::size_t>(n + 1), 0);
    for (i64 t = 0; t < f; ++t) {
        start[tri[3 * t] + 1] += 2;
        start[tri[3 * t + 1] + 1] += 1;
    }
    for (i64 v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<std::pair<i64, i64>> own(static_cast<std::size_t>(3 * f));  // (w, position opposite)
    {
        std::vector<i64> fill(start.begin(), start.end() - 1);
        for (i64 t = 0; t < f; ++t) {
            const i64 a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
            own[fill[a]++] = {b, 3 * t + 2};
            own[fill[a]++] = {c, 3 * t + 1};
            own[fill[b]++] = {c, 3 * t};
        }
    }
    facet_of.assign(static_cast<std::size_t>(3 * f), 0);
    inc.resize(static_cast<std::size_t>(3 * f));
    edges.clear();
    ptr.clear();
    ptr.push_back(0);
    i64 k = 0;
    for (i64 v = 0; v < n; ++v) {
        auto lo = own.begin() + start[v], hi = own.begin() + start[v + 1];
        std::sort(lo, hi);
        for (auto it = lo; it != hi; ++it) {
            if (it == lo || it->first != (it - 1)->first) {
                if (it != lo || k > 0) ptr.push_back(k);
                edges.push_back(v);
                edges.push_back(it->first);
            }
            facet_of[it->second] = static_cast<i64>(edges.size() / 2) - 1;
            inc[k++] = it->second;
        }
    }
    if (k > 0) ptr.push_back(k);
    return true;
}

PyObject* bytes_of(const std::vector<i64>& v) {
    return PyBytes_FromStringAndSize(reinterpret_cast<const char*>(v.data()),
                                     static_cast<Py_ssize_t>(v.size() * sizeof(i64)));
}

PyObject* edge_structure(PyObject*, PyObject* args) {
    Py_buffer rows;
    long long n;
    if (!PyArg_ParseTuple(args, "Ly*", &n, &rows)) return nullptr;
    PyObject* result = nullptr;
    if (n < 0 || rows.len % 24 != 0) {
        PyErr_SetString(PyExc_ValueError, "edge_structure: n >= 0 and int64 rows of three");
    } else {
        const i64 f = rows.len / 24;
        const i64* r = static_cast<const i64*>(rows.buf);
        bool ok = true;
        for (i64 e = 0; e < 3 * f && ok; ++e) ok = r[e] >= 0 && r[e] < n;
        if (!ok) {
            PyErr_SetString(PyExc_ValueError, "edge_structure: a vertex id is outside 0..n-1");
        } else {
            std::vector<i64> edges, facet_of, ptr, inc;
            bool proper = false, failed = false;
            Py_BEGIN_ALLOW_THREADS;
            try {
                proper = edge_table(n, f, r, edges, facet_of, ptr, inc);
            } catch (...) {  // std::bad_alloc, std::length_error: the tables did not fit
                failed = true;
            }
            Py_END_ALLOW_THREADS;
            if (failed) {
                PyErr_NoMemory();
            } else if (!proper) {
                Py_INCREF(Py_None);
                result = Py_None;
            } else {
                result = Py_BuildValue("(NNNN)", bytes_of(edges), bytes_of(facet_of), bytes_of(ptr), bytes_of(inc));
            }
        }
    }
    PyBuffer_Release(&rows);
    return result;
}

PyMethodDef methods[] = {
    {"edge_structure", edge_structure, METH_VARARGS,
     "edge_structure(n, rows) -> (edges, facet_of, ptr, positions) as int64 bytes, or None where a triangle "
     "repeats a vertex: the distinct edges (pairs, lexicographic), the edge of each sorted row opposite each "
     "position, and the CSR of the positions t * 3 + a at each edge, increasing."},
    {"surface_report", surface_report, METH_VARARGS,
     "surface_report(n, rows) -> (vertices, edges, boundary, nonmanifold, components, top_cycles, "
     "singular, orientable) of the triangles in rows (int64, three per triangle, ids below n), or None where a "
     "triangle repeats a vertex or is listed twice; top_cycles is -1 "
     "and orientable -1 where an edge has more than two triangles, singular -1 where the surface is not a "
     "closed pseudo-surface."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_surface", "The counts of a triangle complex's topology report.", -1, methods,
};

}  // namespace

PyMODINIT_FUNC PyInit__surface() { return PyModule_Create(&module); }
