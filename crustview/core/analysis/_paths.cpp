// Shortest-path trees from several roots on two threads (crustview.core.analysis.loops):
// scipy's dijkstra(graph, indices=roots, return_predecessors=True) where the
// answer does not depend on how ties are broken.
//
// Each root's search is a plain Dijkstra over the CSR arrays scipy itself
// searches (neighbours in the same order; a node's distance replaced only
// by a strictly smaller one, as scipy does; unreached nodes at inf with
// predecessor -9999, scipy's value).  When every reached node's distance
// is distinct, the order in which nodes leave the queue is fixed by the
// distances alone, and with it every distance and predecessor: any correct
// priority queue gives scipy's arrays.  When two nodes leave at the same
// distance, the root is flagged, and the caller asks scipy for that root.
// The GIL is released; no third-party code.

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

// One root's search into dist / pred (length n); returns whether two nodes left the queue at one distance.
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
        int fresh = 0;  // nodes leaving the queue at this key
        for (const RadixHeap::Entry& e : level) {
            const std::int32_t v = e.second;
            if (done[v] || key != dist[v]) continue;  // a stale entry
            done[v] = 1;
            if (++fresh > 1) tie = true;
            for (std::int32_t j = g.indptr[v]; j < g.indptr[v + 1]; ++j) {
                const std::int32_t w = g.indices[j];
                if (done[w]) continue;
                const double next = key + g.weights[j];
                if (next < dist[w]) {
                    dist[w] = next;
                    pred[w] = v;
                    heap.push(next, w);
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

PyMethodDef methods[] = {
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
    PyModuleDef_HEAD_INIT, "_paths", "Shortest-path trees from several roots, on two threads.", -1, methods,
};

}  // namespace

PyMODINIT_FUNC PyInit__paths() { return PyModule_Create(&module); }
