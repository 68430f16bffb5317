// One round of Algorithm 1's greedy pole search over every (sample, Voronoi
// vertex) pair, as crustview.core.paper.normals does it in numpy.
//
// Round j: for every vertex a of every Delaunay simplex sid that is a sample
// s (entry position sid * w + a, in that order), the vector centre(sid) - s
// has the sample's j chosen normal directions removed one after another
// (Gram-Schmidt, basis[s, :, 0..j-1]) and its squared length compared with
// the sample's best so far; the first entry attaining a sample's maximum is
// its pole candidate.  Returns, per sample, that entry's position (-1 if the
// sample is in no simplex) and the maximum (-inf), and the largest |coordinate|
// of any vector before projection.
//
// The arithmetic is the numpy code's, operation for operation: products
// first, then sums from the first coordinate on (what numpy's sum(axis=1)
// does on these short rows), no fused multiply-add (-ffp-contract=off in
// setup.py), so the chosen poles are the same, not just close.  No third-party
// code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace {

struct Round {
    const double* centres;
    const double* work;
    const std::int32_t* simplices;
    const double* basis;  // (n, r, p)
    std::int64_t t, n;
    int r, w, p, j;
};

void scan(const Round& in, std::int64_t* first, double* best, double* max_abs) {
    double v[8];
    double top = 0.0;
    for (std::int64_t sid = 0; sid < in.t; ++sid) {
        for (int a = 0; a < in.w; ++a) {
            const std::int64_t s = in.simplices[sid * in.w + a];
            if (s >= in.n) continue;  // a bounding point
            for (int c = 0; c < in.r; ++c) {
                v[c] = in.centres[sid * in.r + c] - in.work[s * in.r + c];
                const double mag = std::fabs(v[c]);
                if (mag > top) top = mag;
            }
            const double* u0 = in.basis + s * in.r * in.p;
            for (int i = 0; i < in.j; ++i) {
                double dot = v[0] * u0[i];
                for (int c = 1; c < in.r; ++c) dot += v[c] * u0[c * in.p + i];
                for (int c = 0; c < in.r; ++c) v[c] -= dot * u0[c * in.p + i];
            }
            double sq = v[0] * v[0];
            for (int c = 1; c < in.r; ++c) sq += v[c] * v[c];
            if (sq > best[s]) {
                best[s] = sq;
                first[s] = sid * in.w + a;
            }
        }
    }
    *max_abs = top;
}

PyObject* farthest(PyObject* /*self*/, PyObject* args) {
    Py_buffer cen, wrk, simp, basis;
    long long n = 0;
    int r = 0, w = 0, p = 0, j = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*y*Liiii", &cen, &wrk, &simp, &basis, &n, &r, &w, &p, &j)) {
        return nullptr;
    }
    const auto release = [&] {
        PyBuffer_Release(&cen);
        PyBuffer_Release(&wrk);
        PyBuffer_Release(&simp);
        PyBuffer_Release(&basis);
    };
    const Py_ssize_t t = w > 0 ? simp.len / (4 * static_cast<Py_ssize_t>(w)) : 0;
    const bool ok = r >= 1 && r <= 8 && w == r + 1 && p >= 1 && j >= 0 && j <= p && n >= 1 &&
                    simp.len == t * w * 4 && cen.len == t * r * 8 && wrk.len >= n * r * 8 &&
                    wrk.len % (8 * static_cast<Py_ssize_t>(r)) == 0 && basis.len == n * r * p * 8;
    if (!ok) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 centres (t x r), work (>= n x r), int32 simplices (t x (r + 1)), "
                        "float64 basis (n x r x p), 1 <= r <= 8 and 0 <= j <= p");
        return nullptr;
    }
    // vertex numbers must address rows of work
    const std::int64_t rows = wrk.len / (8 * static_cast<Py_ssize_t>(r));
    PyObject* first_out = PyByteArray_FromStringAndSize(nullptr, n * 8);
    PyObject* best_out = PyByteArray_FromStringAndSize(nullptr, n * 8);
    if (first_out == nullptr || best_out == nullptr) {
        Py_XDECREF(first_out);
        Py_XDECREF(best_out);
        release();
        return nullptr;
    }
    auto* first = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(first_out));
    auto* best = reinterpret_cast<double*>(PyByteArray_AS_STRING(best_out));
    Round in{static_cast<const double*>(cen.buf), static_cast<const double*>(wrk.buf),
             static_cast<const std::int32_t*>(simp.buf), static_cast<const double*>(basis.buf),
             static_cast<std::int64_t>(t), static_cast<std::int64_t>(n), r, w, p, j};
    double max_abs = 0.0;
    bool bad_vertex = false;
    Py_BEGIN_ALLOW_THREADS
    for (std::int64_t i = 0; i < in.t * in.w; ++i) {
        if (in.simplices[i] < 0 || in.simplices[i] >= rows) bad_vertex = true;
    }
    if (!bad_vertex) {
        for (std::int64_t s = 0; s < in.n; ++s) {
            first[s] = -1;
            best[s] = -std::numeric_limits<double>::infinity();
        }
        scan(in, first, best, &max_abs);
    }
    Py_END_ALLOW_THREADS
    release();
    if (bad_vertex) {
        Py_DECREF(first_out);
        Py_DECREF(best_out);
        PyErr_SetString(PyExc_ValueError, "a simplex names a vertex outside work");
        return nullptr;
    }
    return Py_BuildValue("NNd", first_out, best_out, max_abs);
}

// Simplices per sample and whether a simplex has a vertex >= n (a bounding point): numpy's
// bincount(simplices.ravel(), minlength=n)[:n] and (simplices >= n).any(axis=1), in one pass
// over the int32 table, without bincount's int64 copy of it.
PyObject* vertex_counts(PyObject* /*self*/, PyObject* args) {
    Py_buffer simp;
    long long n = 0;
    int w = 0;
    if (!PyArg_ParseTuple(args, "y*Li", &simp, &n, &w)) {
        return nullptr;
    }
    const Py_ssize_t t = w > 0 ? simp.len / (4 * static_cast<Py_ssize_t>(w)) : 0;
    if (w < 1 || n < 0 || simp.len != t * w * 4) {
        PyBuffer_Release(&simp);
        PyErr_SetString(PyExc_ValueError, "expected int32 simplices (t x w), w >= 1 and n >= 0");
        return nullptr;
    }
    PyObject* count_out = PyByteArray_FromStringAndSize(nullptr, n * 8);
    PyObject* far_out = PyByteArray_FromStringAndSize(nullptr, t);
    if (count_out == nullptr || far_out == nullptr) {
        Py_XDECREF(count_out);
        Py_XDECREF(far_out);
        PyBuffer_Release(&simp);
        return nullptr;
    }
    auto* count = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(count_out));
    auto* far = reinterpret_cast<unsigned char*>(PyByteArray_AS_STRING(far_out));
    const auto* v = static_cast<const std::int32_t*>(simp.buf);
    bool negative = false;
    Py_BEGIN_ALLOW_THREADS
    for (std::int64_t s = 0; s < n; ++s) count[s] = 0;
    for (Py_ssize_t i = 0; i < t; ++i) {
        unsigned char out = 0;
        for (int a = 0; a < w; ++a) {
            const std::int64_t x = v[i * w + a];
            if (x < 0) negative = true;
            if (x >= n) {
                out = 1;
            } else if (x >= 0) {
                ++count[x];
            }
        }
        far[i] = out;
    }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&simp);
    if (negative) {  // numpy's bincount refuses these
        Py_DECREF(count_out);
        Py_DECREF(far_out);
        PyErr_SetString(PyExc_ValueError, "a simplex has a negative vertex number");
        return nullptr;
    }
    return Py_BuildValue("NN", count_out, far_out);
}

PyMethodDef methods[] = {
    {"vertex_counts", vertex_counts, METH_VARARGS,
     "vertex_counts(simplices, n, w) -> (count, far)\n\n"
     "For int32 simplices (t x w): per vertex 0 .. n - 1 the number of\n"
     "entries naming it (int64) and per simplex whether an entry is >= n\n"
     "(bool), as bytearrays."},
    {"farthest", farthest, METH_VARARGS,
     "farthest(centres, work, simplices, basis, n, r, w, p, j) -> (first, best, max_abs)\n\n"
     "One greedy round of Algorithm 1: per sample, the position of the first\n"
     "(simplex, vertex) entry whose vector centre - sample, with the sample's\n"
     "first j basis columns projected out, is longest (int64, -1 if none), that\n"
     "squared length (float64, -inf if none), as bytearrays, and the largest\n"
     "|coordinate| of any vector before projection."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_poles", "One round of Algorithm 1's greedy pole search.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__poles(void) { return PyModule_Create(&module); }
