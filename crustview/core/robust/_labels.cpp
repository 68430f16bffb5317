// Greedy labelling of a signed graph (crustview.core.robust.labelling).
//
// Every edge ties two nodes either to the same label (sign +1) or to opposite
// labels (sign -1).  The edges come most confident first; each one that joins
// two different sets fixes their relative labels, each one inside a set is
// kept if consistent and counted as violated otherwise.  This is Kruskal's
// maximum spanning forest on a signed graph: every node gets its label from
// the most confident path to the root (the path whose weakest edge is
// strongest), as in the Power Crust's priority labelling of poles.
//
// Union-find with a parity per link, union by size and no path compression,
// so that the tree stays O(log n) deep and the edge at which each node's set
// joined the root's set can be read back (the node's confidence).  No
// third-party code.
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace {

struct View {
    Py_buffer b{};
    bool ok = false;
    ~View() {
        if (ok) PyBuffer_Release(&b);
    }
};

bool get(PyObject* o, View& v, Py_ssize_t itemsize, const char* name) {
    if (PyObject_GetBuffer(o, &v.b, PyBUF_C_CONTIGUOUS) != 0) return false;
    v.ok = true;
    if (v.b.itemsize != itemsize && v.b.len % itemsize != 0) {
        PyErr_Format(PyExc_TypeError, "%s has the wrong item size", name);
        return false;
    }
    return true;
}

PyObject* label(PyObject*, PyObject* args) {
    PyObject *oa, *ob, *os;
    long long n, root;
    if (!PyArg_ParseTuple(args, "LOOOL", &n, &oa, &ob, &os, &root)) return nullptr;
    View va, vb, vs;
    if (!get(oa, va, 8, "a") || !get(ob, vb, 8, "b") || !get(os, vs, 1, "sign")) return nullptr;
    const std::int64_t e = va.b.len / 8;
    if (vb.b.len / 8 != e || vs.b.len != e || n <= 0 || root < 0 || root >= n) {
        PyErr_SetString(PyExc_ValueError, "a, b and sign must have one entry per edge, and 0 <= root < n");
        return nullptr;
    }
    const auto* a = static_cast<const std::int64_t*>(va.b.buf);
    const auto* b = static_cast<const std::int64_t*>(vb.b.buf);
    const auto* s = static_cast<const std::int8_t*>(vs.b.buf);
    for (std::int64_t i = 0; i < e; ++i) {
        if (a[i] < 0 || a[i] >= n || b[i] < 0 || b[i] >= n) {
            PyErr_SetString(PyExc_ValueError, "edge endpoint out of range");
            return nullptr;
        }
    }
    PyObject* out_label = PyByteArray_FromStringAndSize(nullptr, n);
    PyObject* out_when = PyByteArray_FromStringAndSize(nullptr, n * 8);
    PyObject* out_viol = PyByteArray_FromStringAndSize(nullptr, e);
    if (!out_label || !out_when || !out_viol) {
        Py_XDECREF(out_label);
        Py_XDECREF(out_when);
        Py_XDECREF(out_viol);
        return nullptr;
    }
    auto* lab = reinterpret_cast<std::int8_t*>(PyByteArray_AS_STRING(out_label));
    auto* when = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out_when));
    auto* viol = reinterpret_cast<std::int8_t*>(PyByteArray_AS_STRING(out_viol));
    Py_BEGIN_ALLOW_THREADS;
    std::vector<std::int64_t> parent(n), size(n, 1), link(n, -1);
    std::vector<std::int8_t> par(n, 0);  // parity to the parent
    for (std::int64_t i = 0; i < n; ++i) parent[i] = i;
    auto find = [&](std::int64_t x, int& p) {
        p = 0;
        while (parent[x] != x) {
            p ^= par[x];
            x = parent[x];
        }
        return x;
    };
    for (std::int64_t i = 0; i < e; ++i) {
        int pa, pb;
        std::int64_t ra = find(a[i], pa), rb = find(b[i], pb);
        const int want = s[i] < 0 ? 1 : 0;
        viol[i] = 0;
        if (ra == rb) {
            if ((pa ^ pb) != want) viol[i] = 1;
            continue;
        }
        if (size[ra] < size[rb]) {
            std::swap(ra, rb);
            std::swap(pa, pb);
        }
        parent[rb] = ra;
        par[rb] = static_cast<std::int8_t>(pa ^ pb ^ want);
        size[ra] += size[rb];
        link[rb] = i;
    }
    int proot;
    const std::int64_t rr = find(root, proot);
    // root's ancestors, each with the time its child on root's path linked in
    std::vector<std::int64_t> mark(n, -2);
    {
        std::int64_t x = root, t = -1;
        mark[x] = t;
        while (parent[x] != x) {
            t = link[x];
            x = parent[x];
            mark[x] = t;
        }
    }
    for (std::int64_t i = 0; i < n; ++i) {
        int p;
        const std::int64_t r = find(i, p);
        if (r != rr) {
            lab[i] = -1;
            when[i] = -1;
            continue;
        }
        lab[i] = static_cast<std::int8_t>(p ^ proot);
        std::int64_t x = i, t = -1;
        while (mark[x] == -2) {
            t = link[x];
            x = parent[x];
        }
        when[i] = (i == root) ? -1 : (t > mark[x] ? t : mark[x]);
    }
    Py_END_ALLOW_THREADS;
    return Py_BuildValue("NNN", out_label, out_when, out_viol);
}

PyMethodDef methods[] = {
    {"label", label, METH_VARARGS,
     "label(n, a, b, sign, root) -> (label, when, violated)\n\n"
     "Greedy signed-graph labelling over edges given most confident first: a, b\n"
     "int64 endpoints, sign int8 (+1 same label, -1 opposite).  Returns bytearrays:\n"
     "label int8 per node relative to root (0 = root's, 1 = the other, -1 = not\n"
     "connected), when int64 per node (the edge at which its set joined root's, -1\n"
     "for root and unconnected nodes), violated int8 per edge."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_labels", "Greedy signed-graph labelling (robust extraction).", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__labels(void) { return PyModule_Create(&module); }
