// Connected components of an undirected graph given by its edges
// (crustview.core.analysis.topology.graph_components), with scipy's labels;
// and the elder rule's merges for 0-dimensional persistence (merges).
//
// scipy.sparse.csgraph.connected_components(directed=False) numbers the
// components in the order of their smallest node (it starts a search from
// nodes 0, 1, ... that no earlier search reached); a union-find over the
// edges followed by one pass over the nodes in order gives the same labels,
// without building the sparse matrix.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cstdint>
#include <vector>

#include "../util/_union_find.h"

namespace {

using i64 = std::int64_t;
using crustview::find;

PyObject* components(PyObject*, PyObject* args) {
    Py_buffer a, b;
    long long n;
    if (!PyArg_ParseTuple(args, "Ly*y*", &n, &a, &b)) return nullptr;
    PyObject* result = nullptr;
    const Py_ssize_t m = a.len / 8;
    if (n < 0 || n > INT32_MAX || a.len != b.len || a.len % 8 != 0) {
        PyErr_SetString(PyExc_ValueError, "components: n must fit int32 and both edge ends be int64 of one length");
    } else {
        const i64* u = static_cast<const i64*>(a.buf);
        const i64* v = static_cast<const i64*>(b.buf);
        bool ok = true;
        for (Py_ssize_t e = 0; e < m && ok; ++e) ok = u[e] >= 0 && u[e] < n && v[e] >= 0 && v[e] < n;
        if (!ok) {
            PyErr_SetString(PyExc_ValueError, "components: an edge end is not a node");
        } else {
            std::vector<i64> parent(static_cast<std::size_t>(n));
            Py_BEGIN_ALLOW_THREADS;
            for (i64 i = 0; i < n; ++i) parent[i] = i;
            for (Py_ssize_t e = 0; e < m; ++e) {
                i64 x = find(parent, u[e]), y = find(parent, v[e]);
                if (x == y) continue;
                if (x < y) parent[y] = x;  // the smaller node stays the root
                else parent[x] = y;
            }
            Py_END_ALLOW_THREADS;
            PyObject* out = PyBytes_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n) * 4);
            if (out != nullptr) {
                auto* label = reinterpret_cast<std::int32_t*>(PyBytes_AS_STRING(out));
                std::int32_t next = 0;
                Py_BEGIN_ALLOW_THREADS;
                // roots are their component's smallest node, so a root is met before its other nodes
                for (i64 i = 0; i < n; ++i) {
                    const i64 r = find(parent, i);
                    label[i] = r == i ? next++ : label[r];
                }
                Py_END_ALLOW_THREADS;
                result = Py_BuildValue("(iN)", static_cast<int>(next), out);
            }
        }
    }
    PyBuffer_Release(&a);
    PyBuffer_Release(&b);
    return result;
}

// 0-dimensional persistence by the elder rule: nodes with birth values, edges taken in the caller's order
// (a filtration read from its end: crustview.core.analysis.alpha).  An edge between two components makes
// the younger one (the smaller birth value: born later in that order) part of the elder.  Returns, per
// merge, the edge's index, the younger component's root (the node whose birth value is its birth) and the
// elder's root.
PyObject* merges(PyObject*, PyObject* args) {
    Py_buffer bo, a, b;
    if (!PyArg_ParseTuple(args, "y*y*y*", &bo, &a, &b)) return nullptr;
    PyObject* result = nullptr;
    const Py_ssize_t n = bo.len / 8, m = a.len / 8;
    if (bo.len % 8 != 0 || a.len != b.len || a.len % 8 != 0) {
        PyErr_SetString(PyExc_ValueError, "merges: float64 births and two int64 edge-end buffers of one length");
    } else {
        const double* born = static_cast<const double*>(bo.buf);
        const i64* u = static_cast<const i64*>(a.buf);
        const i64* v = static_cast<const i64*>(b.buf);
        bool ok = true;
        for (Py_ssize_t e = 0; e < m && ok; ++e) ok = u[e] >= 0 && u[e] < n && v[e] >= 0 && v[e] < n;
        if (!ok) {
            PyErr_SetString(PyExc_ValueError, "merges: an edge end is not a node");
        } else {
            std::vector<i64> parent(static_cast<std::size_t>(n));
            std::vector<i64> out;
            Py_BEGIN_ALLOW_THREADS;
            for (i64 i = 0; i < n; ++i) parent[i] = i;
            for (Py_ssize_t e = 0; e < m; ++e) {
                const i64 x = find(parent, u[e]), y = find(parent, v[e]);
                if (x == y) continue;
                const bool x_young = born[x] < born[y];
                const i64 young = x_young ? x : y, old = x_young ? y : x;
                parent[young] = old;  // a root is its component's eldest node
                out.push_back(static_cast<i64>(e));
                out.push_back(young);
                out.push_back(old);
            }
            Py_END_ALLOW_THREADS;
            result = PyBytes_FromStringAndSize(reinterpret_cast<const char*>(out.data()),
                                               static_cast<Py_ssize_t>(out.size() * sizeof(i64)));
        }
    }
    PyBuffer_Release(&bo);
    PyBuffer_Release(&a);
    PyBuffer_Release(&b);
    return result;
}

PyMethodDef methods[] = {
    {"components", components, METH_VARARGS,
     "components(n, u, v) -> (count, labels): the connected components of the graph on n nodes with edges "
     "(u[i], v[i]) (int64 buffers); labels (int32 bytes) number them in the order of their smallest node."},
    {"merges", merges, METH_VARARGS,
     "merges(born, u, v) -> bytes: the elder rule's merges over the edges (u[i], v[i]) in order, for nodes "
     "with float64 birth values: int64 triples (edge index, root of the younger component, root of the elder)."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_components", "Connected components of a graph, with scipy's labels.", -1, methods,
};

}  // namespace

PyMODINIT_FUNC PyInit__components() { return PyModule_Create(&module); }
