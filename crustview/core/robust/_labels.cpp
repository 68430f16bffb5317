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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <thread>
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
    if (v.b.itemsize != itemsize) {
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

// The pieces of one vertex's star (crustview.core.robust.label_repair.LabelEditor.star_pieces): the
// cells that have v, joined through the faces at v whose two cells have the same label.  The same
// union-find as the Python reference, step for step: the faces in increasing id, parent[root(a)] =
// root(b), path halving; piece ids are the ranks of the roots, as numpy's unique(return_inverse).
struct Stars {
    const std::int64_t *sp, *sc, *cp, *cf, *faces, *a, *b;
    const std::uint8_t* inside;
    std::int64_t width, n_star;
    std::vector<std::int64_t> fs, parent, roots, uniq;

    // the union-find over a star's k cells: every cell its own piece
    void reset(std::int64_t k) {
        parent.resize(static_cast<std::size_t>(k));
        for (std::int64_t i = 0; i < k; ++i) parent[i] = i;
    }

    std::int64_t root(std::int64_t i) {
        while (parent[i] != i) {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        return i;
    }

    // writes the piece of each star cell into comp (star order); returns the number of pieces
    std::int64_t pieces(std::int64_t v, std::int64_t* comp) {
        const std::int64_t lo = sp[v], hi = sp[v + 1], k = hi - lo;
        fs.clear();
        for (std::int64_t i = lo; i < hi; ++i) {
            const std::int64_t c = sc[i];
            for (std::int64_t j = cp[c]; j < cp[c + 1]; ++j) fs.push_back(cf[j]);
        }
        std::sort(fs.begin(), fs.end());
        fs.erase(std::unique(fs.begin(), fs.end()), fs.end());
        auto pos = [&](std::int64_t c) -> std::int64_t {  // a star has a few dozen cells
            for (std::int64_t i = 0; i < k; ++i)
                if (sc[lo + i] == c) return i;
            return -1;
        };
        reset(k);
        for (const std::int64_t f : fs) {
            bool at_v = false;
            for (std::int64_t c = 0; c < width; ++c) at_v = at_v || faces[f * width + c] == v;
            if (!at_v || (inside[a[f]] != 0) != (inside[b[f]] != 0)) continue;
            const std::int64_t pa = pos(a[f]), pb = pos(b[f]);
            if (pa < 0 || pb < 0) continue;
            const std::int64_t ra = root(pa), rb = root(pb);
            if (ra != rb) parent[ra] = rb;
        }
        roots.resize(static_cast<std::size_t>(k));
        for (std::int64_t i = 0; i < k; ++i) roots[i] = root(i);
        uniq = roots;
        std::sort(uniq.begin(), uniq.end());
        uniq.erase(std::unique(uniq.begin(), uniq.end()), uniq.end());
        if (comp != nullptr)
            for (std::int64_t i = 0; i < k; ++i)
                comp[i] = std::lower_bound(uniq.begin(), uniq.end(), roots[i]) - uniq.begin();
        return static_cast<std::int64_t>(uniq.size());
    }

    // the number of pieces of v's star (what pieces() returns, without numbering them): each star cell's
    // faces at v joined to the cell across them when both have the same label; no face list to sort,
    // and the star's cells found by binary search (each star's cells are sorted: LabelEditor sorts them)
    std::int64_t count(std::int64_t v) {
        const std::int64_t lo = sp[v], hi = sp[v + 1], k = hi - lo;
        if (k == 0) return 0;
        auto pos = [&](std::int64_t c) -> std::int64_t {  // the caller sorts each star (LabelEditor)
            const std::int64_t* it = std::lower_bound(sc + lo, sc + hi, c);
            return it != sc + hi && *it == c ? it - (sc + lo) : -1;
        };
        reset(k);
        std::int64_t pieces = k;
        for (std::int64_t i = 0; i < k; ++i) {
            const std::int64_t c = sc[lo + i];
            const bool in_c = inside[c] != 0;
            for (std::int64_t j = cp[c]; j < cp[c + 1]; ++j) {
                const std::int64_t f = cf[j];
                const std::int64_t o = a[f] == c ? b[f] : a[f];
                if (o < c || (inside[o] != 0) != in_c) continue;  // each face once, same labels only
                bool at_v = false;
                for (std::int64_t x = 0; x < width; ++x) at_v = at_v || faces[f * width + x] == v;
                if (!at_v) continue;
                const std::int64_t po = pos(o);
                if (po < 0) continue;
                const std::int64_t ra = root(i), rb = root(po);
                if (ra != rb) {
                    parent[ra] = rb;
                    --pieces;
                }
            }
        }
        return pieces;
    }
};

// parses (width, star_ptr, star_cells, cell_ptr, cell_faces, faces, a, b, inside) from args[first:]
bool get_stars(PyObject* args, Py_ssize_t first, Stars& st, View* views) {
    const char* names[] = {"star_ptr", "star_cells", "cell_ptr", "cell_faces", "faces", "a", "b", "inside"};
    if (PyTuple_GET_SIZE(args) != first + 9) {
        PyErr_SetString(PyExc_TypeError, "star pieces: wrong number of arguments");
        return false;
    }
    st.width = PyLong_AsLongLong(PyTuple_GET_ITEM(args, first));
    if (st.width == -1 && PyErr_Occurred()) return false;
    for (int i = 0; i < 8; ++i)
        if (!get(PyTuple_GET_ITEM(args, first + 1 + i), views[i], i == 7 ? 1 : 8, names[i])) return false;
    st.sp = static_cast<const std::int64_t*>(views[0].b.buf);
    st.sc = static_cast<const std::int64_t*>(views[1].b.buf);
    st.cp = static_cast<const std::int64_t*>(views[2].b.buf);
    st.cf = static_cast<const std::int64_t*>(views[3].b.buf);
    st.faces = static_cast<const std::int64_t*>(views[4].b.buf);
    st.a = static_cast<const std::int64_t*>(views[5].b.buf);
    st.b = static_cast<const std::int64_t*>(views[6].b.buf);
    st.inside = static_cast<const std::uint8_t*>(views[7].b.buf);
    st.n_star = views[0].b.len / 8 - 1;
    const std::int64_t n_cells = views[2].b.len / 8 - 1, n_faces = views[5].b.len / 8;
    if (st.width <= 0 || st.n_star < 0 || views[4].b.len / 8 != n_faces * st.width || views[6].b.len / 8 != n_faces ||
        views[7].b.len != n_cells) {
        PyErr_SetString(PyExc_ValueError, "star pieces: inconsistent arrays");
        return false;
    }
    return true;
}

PyObject* star_pieces(PyObject*, PyObject* args) {
    if (PyTuple_GET_SIZE(args) < 1) {
        PyErr_SetString(PyExc_TypeError, "star_pieces: v missing");
        return nullptr;
    }
    const long long v = PyLong_AsLongLong(PyTuple_GET_ITEM(args, 0));
    if (v == -1 && PyErr_Occurred()) return nullptr;
    Stars st;
    View views[8];
    if (!get_stars(args, 1, st, views)) return nullptr;
    if (v < 0 || v >= st.n_star) {
        PyErr_SetString(PyExc_ValueError, "star_pieces: v out of range");
        return nullptr;
    }
    const std::int64_t k = st.sp[v + 1] - st.sp[v];
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(8 * k));
    if (out == nullptr) return nullptr;
    st.pieces(v, reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out)));
    return out;
}

PyObject* piece_counts(PyObject*, PyObject* args) {
    Stars st;
    View views[8];
    if (!get_stars(args, 0, st, views)) return nullptr;
    // count() finds a star's cells by bisection: each star must be sorted (LabelEditor sorts them)
    for (std::int64_t v = 0; v < st.n_star; ++v)
        if (!std::is_sorted(st.sc + st.sp[v], st.sc + st.sp[v + 1])) {
            PyErr_SetString(PyExc_ValueError, "piece_counts: each star's cells must be sorted");
            return nullptr;
        }
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(8 * st.n_star));
    if (out == nullptr) return nullptr;
    auto* count = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out));
    Py_BEGIN_ALLOW_THREADS;
    // two halves of the vertices on two threads, each with its own scratch (the vertices are independent);
    // where no thread can be started, one thread does both halves
    const std::int64_t half = st.n_star / 2;
    Stars other = st;
    auto upper = [&] {
        for (std::int64_t v = half; v < other.n_star; ++v) count[v] = other.count(v);
    };
    std::thread second;
    bool started = true;
    try {
        second = std::thread(upper);
    } catch (...) {
        started = false;
    }
    for (std::int64_t v = 0; v < half; ++v) count[v] = st.count(v);
    if (started)
        second.join();
    else
        upper();
    Py_END_ALLOW_THREADS;
    return out;
}


// The two pole cells of every sample (crustview.core.robust.labelling.Labelling._pole_pairs): over the
// sample's incidences in cell-major order, the cell of largest radius (the last incidence reaching it;
// NaN radii passed over), then, among the incidences whose centre lies on the other side of the sample
// (negative dot product with the direction to the first pole), the same again.  -1 where there is none.
PyObject* pole_cells(PyObject*, PyObject* args) {
    PyObject *os, *or_, *oc, *op;
    long long n, w, k;
    if (!PyArg_ParseTuple(args, "LLLOOOO", &n, &w, &k, &os, &or_, &oc, &op)) return nullptr;
    View vs, vr, vc, vp;
    if (!get(os, vs, 8, "simplices") || !get(or_, vr, 8, "radius") || !get(oc, vc, 8, "centres") ||
        !get(op, vp, 8, "points"))
        return nullptr;
    const std::int64_t m = vr.b.len / 8;
    if (n <= 0 || w <= 0 || k <= 0 || vs.b.len / 8 != m * w || vc.b.len / 8 != m * k || vp.b.len / 8 < n * k) {
        PyErr_SetString(PyExc_ValueError, "pole_cells: inconsistent arrays");
        return nullptr;
    }
    const auto* s = static_cast<const std::int64_t*>(vs.b.buf);
    const auto* r = static_cast<const double*>(vr.b.buf);
    const auto* c = static_cast<const double*>(vc.b.buf);
    const auto* pt = static_cast<const double*>(vp.b.buf);
    PyObject* out_plus = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(8 * n));
    PyObject* out_minus = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(8 * n));
    if (!out_plus || !out_minus) {
        Py_XDECREF(out_plus);
        Py_XDECREF(out_minus);
        return nullptr;
    }
    auto* plus = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out_plus));
    auto* minus = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out_minus));
    Py_BEGIN_ALLOW_THREADS;
    std::vector<double> top(static_cast<std::size_t>(n), -HUGE_VAL);
    for (std::int64_t i = 0; i < n; ++i) plus[i] = minus[i] = -1;
    // first pole: the largest radius (>= keeps the last incidence that reaches it)
    for (std::int64_t q = 0; q < m; ++q) {
        const double rq = r[q];
        if (rq != rq) continue;  // NaN
        for (std::int64_t j = 0; j < w; ++j) {
            const std::int64_t v = s[q * w + j];
            if (v < 0 || v >= n) continue;
            if (rq >= top[v]) {
                top[v] = rq;
                plus[v] = q;
            }
        }
    }
    std::fill(top.begin(), top.end(), -HUGE_VAL);
    for (std::int64_t q = 0; q < m; ++q) {
        const double rq = r[q];
        if (rq != rq) continue;
        for (std::int64_t j = 0; j < w; ++j) {
            const std::int64_t v = s[q * w + j];
            if (v < 0 || v >= n || plus[v] < 0) continue;
            double dot = 0.0;
            for (std::int64_t x = 0; x < k; ++x)
                dot += (c[q * k + x] - pt[v * k + x]) * (c[plus[v] * k + x] - pt[v * k + x]);
            if (dot < 0 && rq >= top[v]) {
                top[v] = rq;
                minus[v] = q;
            }
        }
    }
    Py_END_ALLOW_THREADS;
    PyObject* res = Py_BuildValue("(NN)", out_plus, out_minus);
    return res;
}

// descending_order(values): the stable order of float64 values from largest to smallest, what
// numpy's argsort(-values, kind="stable") gives for values without NaN (the caller checks): an LSD
// radix sort, 11 bits a pass, of keys whose unsigned order is the order of -value (-0.0 taken as 0.0,
// since numpy's comparison sees them equal), passes whose digit is the same for every key skipped.
PyObject* descending_order(PyObject*, PyObject* args) {
    PyObject* o = nullptr;
    if (!PyArg_ParseTuple(args, "O", &o)) return nullptr;
    View v;
    if (!get(o, v, 8, "values")) return nullptr;
    const auto* x = static_cast<const double*>(v.b.buf);
    const std::size_t n = static_cast<std::size_t>(v.b.len / 8);
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n * 8));
    if (out == nullptr) return nullptr;
    auto* order = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out));
    bool nan = false;
    Py_BEGIN_ALLOW_THREADS;
    std::vector<std::uint64_t> key(n), key2(n);
    std::vector<std::int64_t> idx(n), idx2(n);
    std::uint64_t all_or = 0, all_and = ~std::uint64_t{0};
    for (std::size_t i = 0; i < n && !nan; ++i) {
        double y = -x[i];
        nan = std::isnan(y);
        if (y == 0.0) y = 0.0;  // -0.0 and 0.0 compare equal
        std::uint64_t u = 0;
        std::memcpy(&u, &y, 8);
        key[i] = (u >> 63) ? ~u : (u | (std::uint64_t{1} << 63));
        idx[i] = static_cast<std::int64_t>(i);
        all_or |= key[i];
        all_and &= key[i];
    }
    if (!nan) {
        std::vector<std::size_t> start(2049);
        for (int shift = 0; shift < 64; shift += 11) {
            if ((((all_or ^ all_and) >> shift) & 0x7FFu) == 0) continue;  // one digit for every key
            std::fill(start.begin(), start.end(), 0);
            for (std::size_t i = 0; i < n; ++i) ++start[((key[i] >> shift) & 0x7FFu) + 1];
            for (std::size_t b = 0; b < 2048; ++b) start[b + 1] += start[b];
            for (std::size_t i = 0; i < n; ++i) {
                const std::size_t at = start[(key[i] >> shift) & 0x7FFu]++;
                key2[at] = key[i];
                idx2[at] = idx[i];
            }
            key.swap(key2);
            idx.swap(idx2);
        }
        std::copy(idx.begin(), idx.end(), order);
    }
    Py_END_ALLOW_THREADS;
    if (nan) {
        Py_DECREF(out);
        PyErr_SetString(PyExc_ValueError, "values must not be NaN");
        return nullptr;
    }
    return out;
}

PyMethodDef methods[] = {
    {"label", label, METH_VARARGS,
     "label(n, a, b, sign, root) -> (label, when, violated)\n\n"
     "Greedy signed-graph labelling over edges given most confident first: a, b\n"
     "int64 endpoints, sign int8 (+1 same label, -1 opposite).  Returns bytearrays:\n"
     "label int8 per node relative to root (0 = root's, 1 = the other, -1 = not\n"
     "connected), when int64 per node (the edge at which its set joined root's, -1\n"
     "for root and unconnected nodes), violated int8 per edge."},
    {"star_pieces", star_pieces, METH_VARARGS,
     "star_pieces(v, width, star_ptr, star_cells, cell_ptr, cell_faces, faces, a, b, inside) -> bytearray\n\n"
     "The piece of each cell of v's star (int64, in star order): cells joined through\n"
     "faces at v whose two cells have the same label.  Index arrays int64, inside 1 byte."},
    {"piece_counts", piece_counts, METH_VARARGS,
     "piece_counts(width, star_ptr, star_cells, cell_ptr, cell_faces, faces, a, b, inside) -> bytearray\n\n"
     "The number of pieces of every vertex's star (int64; 0 for a vertex in no cell); each star's cells\n"
     "sorted (bisection), on two threads."},
    {"descending_order", descending_order, METH_VARARGS,
     "descending_order(values) -> bytearray\n\n"
     "The stable order of float64 values (no NaN) from largest to smallest, as int64:\n"
     "numpy's argsort(-values, kind='stable')."},
    {"pole_cells", pole_cells, METH_VARARGS,
     "pole_cells(n, width, k, simplices, radius, centres, points) -> (plus, minus)\n\n"
     "Per sample, the cell of largest radius among its incidences and the same among those whose\n"
     "centre is on the other side (negative dot product with the way to the first): int64\n"
     "bytearrays, -1 for none.  simplices int64 (m, width), radius float64 (m,), centres (m, k),\n"
     "points (n, k) float64; vertices >= n (bounding points) are passed over."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_labels", "Greedy signed-graph labelling (robust extraction).", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__labels(void) { return PyModule_Create(&module); }
