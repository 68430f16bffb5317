// Shortest-path trees from several roots on two threads (crustview.core.analysis.loops):
// scipy's dijkstra(graph, indices=roots, return_predecessors=True) where the
// answer does not depend on how ties are broken.
//
// Each root's search is a plain Dijkstra over the CSR arrays scipy itself
// searches (neighbours in the same order; a node's distance replaced only
// by a strictly smaller one, as scipy does; unreached nodes at inf with
// predecessor -9999, scipy's value).  Nodes leave the queue in the order of
// their distances, and only the order among nodes at one distance is the
// queue's own (scipy's Fibonacci heap, here a radix heap).  That order shows
// in the arrays only where two nodes at one distance offer a third the same
// new distance: the first to offer it becomes its predecessor.  Every
// distance is the same either way (a minimum), and so is every other
// predecessor: one set by a node at a smaller distance came first in both
// searches, and a node's own offers are made in the same order.  So a root is
// flagged, and the caller asks scipy for it, exactly when some node receives
// an offer equal to its distance from a node at the same distance as the
// node that made its current one (session 46; before, any two nodes at one
// distance flagged the root, and on a finely tessellated scan every root went
// to scipy).
// The GIL is released; no third-party code.
//
// Also the loop basis's tree-cotree split (crustview.core.analysis.cotree): each edge's two
// triangles and the breadth-first forest of the dual graph, as numpy and scipy give them.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

namespace {

using i64 = std::int64_t;

struct Graph {
    const std::int32_t* indptr;
    const std::int32_t* indices;
    const double* weights;
    i64 n;
};

// A monotone priority queue (a radix heap) on the bits of non-negative doubles, whose order as
// unsigned integers is their order as numbers: keys pushed are never below the last key popped.
class RadixHeap {
  public:
    using Entry = std::pair<std::uint64_t, std::int32_t>;
    bool empty() const { return size_ == 0; }
    void push(double key, std::int32_t v) {
        const std::uint64_t k = bits(key);
        buckets_[bucket(k)].push_back({k, v});
        ++size_;
    }
    // The entries at the smallest key, into out (the key as a double in `key`).
    void pop_all(std::vector<Entry>& out, double& key) {
        if (buckets_[0].empty()) {
            int i = 1;
            while (buckets_[i].empty()) ++i;
            std::uint64_t low = buckets_[i][0].first;
            for (const Entry& e : buckets_[i]) low = std::min(low, e.first);
            last_ = low;
            for (const Entry& e : buckets_[i]) buckets_[bucket(e.first)].push_back(e);
            buckets_[i].clear();
        }
        out.swap(buckets_[0]);
        buckets_[0].clear();
        size_ -= out.size();
        std::memcpy(&key, &last_, sizeof key);
    }

  private:
    static std::uint64_t bits(double x) {
        std::uint64_t k;
        std::memcpy(&k, &x, sizeof k);
        return k;
    }
    int bucket(std::uint64_t k) const { return k == last_ ? 0 : 64 - __builtin_clzll(k ^ last_); }
    std::vector<Entry> buckets_[65];
    std::uint64_t last_ = 0;
    std::size_t size_ = 0;
};

// One root's search into dist / pred (length n); returns whether the order among nodes at one distance
// could change a predecessor (an offer equal to a node's distance from the distance of its predecessor).
bool search(const Graph& g, i64 root, double* dist, std::int32_t* pred, std::vector<unsigned char>& done) {
    RadixHeap heap;
    std::vector<RadixHeap::Entry> level;
    const double inf = std::numeric_limits<double>::infinity();
    for (i64 i = 0; i < g.n; ++i) {
        dist[i] = inf;
        pred[i] = -9999;
        done[i] = 0;
    }
    dist[root] = 0.0;
    heap.push(0.0, static_cast<std::int32_t>(root));
    bool tie = false;
    while (!heap.empty()) {
        double key;
        heap.pop_all(level, key);
        for (const RadixHeap::Entry& e : level) {
            const std::int32_t v = e.second;
            if (done[v] || key != dist[v]) continue;  // a stale entry
            done[v] = 1;
            for (std::int32_t j = g.indptr[v]; j < g.indptr[v + 1]; ++j) {
                const std::int32_t w = g.indices[j];
                if (done[w]) continue;
                const double next = key + g.weights[j];
                if (next < dist[w]) {
                    dist[w] = next;
                    pred[w] = v;
                    heap.push(next, w);
                } else if (next == dist[w] && pred[w] >= 0 && pred[w] != v && dist[pred[w]] == key) {
                    tie = true;  // two nodes at this distance offer w the same: the queue's order decides
                }
            }
        }
    }
    return tie;
}

PyObject* shortest_paths(PyObject*, PyObject* args) {
    Py_buffer indptr, indices, weights, roots;
    int threads;
    if (!PyArg_ParseTuple(args, "y*y*y*y*i", &indptr, &indices, &weights, &roots, &threads)) return nullptr;
    PyObject* result = nullptr;
    const i64 n = indptr.len / 4 - 1;
    const i64 m = indices.len / 4;
    const i64 r = roots.len / 8;
    const auto* ptr = static_cast<const std::int32_t*>(indptr.buf);
    const auto* rts = static_cast<const i64*>(roots.buf);
    bool ok = n >= 0 && indptr.len % 4 == 0 && indices.len % 4 == 0 && weights.len == m * 8 && roots.len % 8 == 0;
    ok = ok && ptr[0] == 0 && ptr[n] == m;
    for (i64 i = 0; ok && i < r; ++i) ok = rts[i] >= 0 && rts[i] < n;
    for (i64 j = 0; ok && j < m; ++j) {
        const std::int32_t w = static_cast<const std::int32_t*>(indices.buf)[j];
        ok = w >= 0 && w < n && static_cast<const double*>(weights.buf)[j] >= 0.0;
    }
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "shortest_paths: not a CSR graph with int32 indices and weights >= 0");
    } else {
        // bytearrays: numpy wraps them writable, without a copy
        PyObject* dist = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(r * n * 8));
        PyObject* pred = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(r * n * 4));
        PyObject* ties = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(r));
        if (dist != nullptr && pred != nullptr && ties != nullptr) {
            const Graph g{ptr, static_cast<const std::int32_t*>(indices.buf), static_cast<const double*>(weights.buf), n};
            auto* d = reinterpret_cast<double*>(PyByteArray_AS_STRING(dist));
            auto* p = reinterpret_cast<std::int32_t*>(PyByteArray_AS_STRING(pred));
            auto* t = reinterpret_cast<unsigned char*>(PyByteArray_AS_STRING(ties));
            const int workers = static_cast<int>(std::max<i64>(1, std::min<i64>(threads, r)));
            Py_BEGIN_ALLOW_THREADS;
            auto work = [&](int w) {
                std::vector<unsigned char> done(static_cast<std::size_t>(n));
                for (i64 i = w; i < r; i += workers) t[i] = search(g, rts[i], d + i * n, p + i * n, done) ? 1 : 0;
            };
            std::vector<std::thread> pool;
            for (int w = 1; w < workers; ++w) pool.emplace_back(work, w);
            work(0);
            for (auto& th : pool) th.join();
            Py_END_ALLOW_THREADS;
            result = Py_BuildValue("(NNN)", dist, pred, ties);
        } else {
            Py_XDECREF(dist);
            Py_XDECREF(pred);
            Py_XDECREF(ties);
        }
    }
    PyBuffer_Release(&indptr);
    PyBuffer_Release(&indices);
    PyBuffer_Release(&weights);
    PyBuffer_Release(&roots);
    return result;
}

// acc[v] = start[v] ^ acc[pred[v]] (pred < 0: a root or unreached, acc = start), by walks up
// the tree that stop at the first node already done; each node is done once.
PyObject* path_xor(PyObject*, PyObject* args) {
    Py_buffer pred, start;
    int words;
    if (!PyArg_ParseTuple(args, "y*y*i", &pred, &start, &words)) return nullptr;
    PyObject* result = nullptr;
    const i64 n = pred.len / 4;
    if (words < 1 || pred.len % 4 != 0 || start.len != n * words * 8) {
        PyErr_SetString(PyExc_ValueError, "path_xor: int32 pred and (n, words) uint64 start");
    } else {
        const auto* p = static_cast<const std::int32_t*>(pred.buf);
        bool ok = true;
        for (i64 v = 0; ok && v < n; ++v) ok = p[v] < n;
        PyObject* out = ok ? PyBytes_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n * words * 8)) : nullptr;
        if (!ok) PyErr_SetString(PyExc_ValueError, "path_xor: a predecessor is not a node");
        if (out != nullptr) {
            auto* acc = reinterpret_cast<std::uint64_t*>(PyBytes_AS_STRING(out));
            const auto* st = static_cast<const std::uint64_t*>(start.buf);
            bool cycle = false;
            Py_BEGIN_ALLOW_THREADS;
            std::vector<unsigned char> state(static_cast<std::size_t>(n), 0);  // 0 new, 1 on the walk, 2 done
            std::vector<std::int32_t> walk;
            for (i64 v0 = 0; v0 < n && !cycle; ++v0) {
                walk.clear();
                i64 v = v0;
                while (v >= 0 && state[v] == 0) {
                    state[v] = 1;
                    walk.push_back(static_cast<std::int32_t>(v));
                    v = p[v];
                }
                if (v >= 0 && state[v] == 1) cycle = true;  // not a forest
                for (std::size_t i = walk.size(); i-- > 0;) {
                    const i64 u = walk[i];
                    const i64 up = p[u];
                    for (int w = 0; w < words; ++w) {
                        acc[u * words + w] = st[u * words + w] ^ (up >= 0 ? acc[up * words + w] : 0);
                    }
                    state[u] = 2;
                }
            }
            Py_END_ALLOW_THREADS;
            if (cycle) {
                Py_DECREF(out);
                PyErr_SetString(PyExc_ValueError, "path_xor: the predecessors have a cycle");
            } else {
                result = out;
            }
        }
    }
    PyBuffer_Release(&pred);
    PyBuffer_Release(&start);
    return result;
}

// e_tris[e] = (first, last) triangle t, in increasing t, whose edge triple tri_edges[t] holds e; -1 where none
// (numpy's stable sort of the flattened triples by edge, first and last of each run).
PyObject* edge_triangles(PyObject*, PyObject* args) {
    Py_buffer tri_edges;
    long long n_edges;
    if (!PyArg_ParseTuple(args, "y*L", &tri_edges, &n_edges)) return nullptr;
    PyObject* result = nullptr;
    const i64 slots = tri_edges.len / 8;
    const auto* te = static_cast<const i64*>(tri_edges.buf);
    bool ok = n_edges >= 0 && tri_edges.len % 24 == 0;
    for (i64 i = 0; ok && i < slots; ++i) ok = te[i] >= 0 && te[i] < n_edges;
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "edge_triangles: int64 (t, 3) edge ids in [0, n_edges)");
    } else if ((result = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n_edges * 16))) != nullptr) {
        auto* out = reinterpret_cast<i64*>(PyByteArray_AS_STRING(result));
        Py_BEGIN_ALLOW_THREADS;
        std::fill(out, out + 2 * n_edges, i64(-1));
        for (i64 i = 0; i < slots; ++i) {
            i64* row = out + 2 * te[i];
            (row[0] < 0 ? row[0] : row[1]) = i / 3;
        }
        Py_END_ALLOW_THREADS;
    }
    PyBuffer_Release(&tri_edges);
    return result;
}

// Breadth-first forest of the undirected graph on n nodes with edges (a[i], b[i]): from the smallest
// unvisited node of each component, neighbours taken in increasing order (scipy's breadth_first_order
// on the canonical CSR matrix of the graph).  parent -1 at roots; depth in hops to the root.
PyObject* bfs_forest(PyObject*, PyObject* args) {
    Py_buffer abuf, bbuf;
    long long n;
    if (!PyArg_ParseTuple(args, "Ly*y*", &n, &abuf, &bbuf)) return nullptr;
    PyObject* result = nullptr;
    const i64 m = abuf.len / 8;
    const auto* a = static_cast<const i64*>(abuf.buf);
    const auto* b = static_cast<const i64*>(bbuf.buf);
    bool ok = n >= 0 && abuf.len % 8 == 0 && bbuf.len == abuf.len;
    for (i64 i = 0; ok && i < m; ++i) ok = a[i] >= 0 && a[i] < n && b[i] >= 0 && b[i] < n;
    PyObject* parent = nullptr;
    PyObject* depth = nullptr;
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "bfs_forest: int64 edge ends in [0, n)");
    } else {
        parent = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n * 8));
        depth = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n * 8));
    }
    if (parent != nullptr && depth != nullptr) {
        auto* par = reinterpret_cast<i64*>(PyByteArray_AS_STRING(parent));
        auto* dep = reinterpret_cast<i64*>(PyByteArray_AS_STRING(depth));
        Py_BEGIN_ALLOW_THREADS;
        std::vector<i64> start(static_cast<std::size_t>(n + 1), 0);
        for (i64 i = 0; i < m; ++i) {
            ++start[a[i] + 1];
            ++start[b[i] + 1];
        }
        for (i64 v = 0; v < n; ++v) start[v + 1] += start[v];
        std::vector<i64> adj(static_cast<std::size_t>(2 * m));
        std::vector<i64> fill(start.begin(), start.end() - 1);
        for (i64 i = 0; i < m; ++i) {
            adj[fill[a[i]]++] = b[i];
            adj[fill[b[i]]++] = a[i];
        }
        for (i64 v = 0; v < n; ++v) std::sort(adj.begin() + start[v], adj.begin() + start[v + 1]);
        std::vector<unsigned char> seen(static_cast<std::size_t>(n), 0);
        std::vector<i64> queue;
        queue.reserve(static_cast<std::size_t>(n));
        for (i64 r = 0; r < n; ++r) {
            if (seen[r]) continue;
            seen[r] = 1;
            par[r] = -1;
            dep[r] = 0;
            queue.clear();
            queue.push_back(r);
            for (std::size_t q = 0; q < queue.size(); ++q) {
                const i64 v = queue[q];
                for (i64 j = start[v]; j < start[v + 1]; ++j) {
                    const i64 w = adj[j];
                    if (seen[w]) continue;
                    seen[w] = 1;
                    par[w] = v;
                    dep[w] = dep[v] + 1;
                    queue.push_back(w);
                }
            }
        }
        Py_END_ALLOW_THREADS;
        result = Py_BuildValue("(NN)", parent, depth);
    } else {
        Py_XDECREF(parent);
        Py_XDECREF(depth);
    }
    PyBuffer_Release(&abuf);
    PyBuffer_Release(&bbuf);
    return result;
}

PyMethodDef methods[] = {
    {"bfs_forest", bfs_forest, METH_VARARGS,
     "bfs_forest(n, a, b) -> (parent, depth): breadth-first forest of the undirected graph with int64 edges "
     "(a[i], b[i]) on n nodes, from each component's smallest node, neighbours in increasing order; int64 "
     "bytearrays, parent -1 at roots, depth in hops."},
    {"edge_triangles", edge_triangles, METH_VARARGS,
     "edge_triangles(tri_edges, n_edges) -> e_tris: per edge its first and last triangle (int64 bytearray, "
     "(n_edges, 2), -1 where none) from the int64 (t, 3) edge ids of the triangles."},
    {"path_xor", path_xor, METH_VARARGS,
     "path_xor(pred, start, words) -> acc: per node the XOR of start (uint64, words per node) over its tree path "
     "to the root, the root's own entry included (int32 pred, negative at roots)."},
    {"shortest_paths", shortest_paths, METH_VARARGS,
     "shortest_paths(indptr, indices, weights, roots, threads) -> (dist, pred, ties): one shortest-path tree per "
     "root (int32 CSR arrays, float64 weights, int64 roots); dist float64 and pred int32 bytearrays, (roots, n) "
     "row by row, and one byte per root, 1 where two nodes were reached at the same distance."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_paths", "Shortest-path trees from several roots, on two threads; the dual forest of the loop basis.", -1, methods,
};

}  // namespace

PyMODINIT_FUNC PyInit__paths() { return PyModule_Create(&module); }
