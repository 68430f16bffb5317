// Algorithm 2's cocone score on polygonal dual cells, first two steps, as
// crustview.core.paper.candidates._score_chunk does them in numpy.
//
// For a chunk of faces whose dual cells all have nv vertices (Voronoi
// vertices c_v), and each face vertex s with its m normal directions
// N = normals[s] (r x m, row-major), with x_v = c_v - s:
//   q_v = max(|x_v|^2, 1e-300), p_vj = N_j . x_v   (sums from the first coordinate)
//   best = min_v (sum_j p_vj^2) / q_v               (sin^2 at the cell's vertices)
//   u_vj = p_vj / sqrt(q_v)                          (unit normal components)
//   nu = sum_v u_v, nu /= max(|nu|, 1e-300)          (the mean direction)
//   lean = min_v nu . u_v                            (the one-sided certificate)
// The caller certifies lean >= sin(limit) and runs the exact minimum on the
// rest.  The arithmetic is numpy's, operation for operation (every sum
// sequential from its first term, as numpy's whole-array loops and its
// einsum over the cell axis do; no fused multiply-add: -ffp-contract=off in
// setup.py), so the scores are the same bit for bit.  The GIL is released:
// the thread pool of crustview.core.util.parallel runs two chunks at once.
// No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

struct Inputs {
    const double* work;         // (rows, r)
    const double* normals;      // (n, r, m)
    const double* centres;      // (t, r)
    const std::int64_t* faces;  // (f, w)
    const std::int64_t* cells;  // (f, nv)
    std::int64_t f;
    int r, m, w, nv;
};

//: Faces ahead of the current one whose cell vertices are prefetched.
constexpr std::int64_t kAhead = 6;

// R coordinates and M normal directions as compile-time constants (0: the
// run-time in.r, in.m): the compiler keeps a vertex's values in registers.
// The operations and their order are the same in every instance.
template <int R, int M>
void score(const Inputs& in, double* best, double* lean) {
    const int r = R > 0 ? R : in.r, m = M > 0 ? M : in.m, nv = in.nv;
    std::vector<double> unit(static_cast<std::size_t>(nv) * m), nu(m);
    for (std::int64_t i = 0; i < in.f; ++i) {
        const std::int64_t* cell = in.cells + i * nv;
        if (i + kAhead < in.f) {  // the Voronoi vertices are scattered over the triangulation: ask early
            const std::int64_t* later = in.cells + (i + kAhead) * nv;
            for (int c = 0; c < nv; ++c) {
                __builtin_prefetch(in.centres + later[c] * r);
                __builtin_prefetch(in.centres + later[c] * r + r - 1);
            }
        }
        for (int a = 0; a < in.w; ++a) {
            const std::int64_t v = in.faces[i * in.w + a];
            const double* s = in.work + v * r;
            const double* nr = in.normals + v * r * m;  // nr[q * m + j]
            double low = 0.0;
            for (int c = 0; c < nv; ++c) {
                const double* cv = in.centres + cell[c] * r;
                double* u = unit.data() + static_cast<std::size_t>(c) * m;
                double x = cv[0] - s[0];
                double q = x * x;
                for (int j = 0; j < m; ++j) {
                    u[j] = x * nr[j];
                }
                for (int k = 1; k < r; ++k) {
                    x = cv[k] - s[k];
                    q += x * x;
                    for (int j = 0; j < m; ++j) {
                        u[j] += x * nr[k * m + j];
                    }
                }
                q = std::max(q, 1e-300);
                double num = u[0] * u[0];
                for (int j = 1; j < m; ++j) {
                    num += u[j] * u[j];
                }
                const double ratio = num / q;
                low = c == 0 ? ratio : std::min(low, ratio);
                const double len = std::sqrt(q);
                for (int j = 0; j < m; ++j) {
                    u[j] /= len;
                }
            }
            best[i * in.w + a] = low;
            for (int j = 0; j < m; ++j) {
                nu[j] = unit[j];
            }
            for (int c = 1; c < nv; ++c) {
                for (int j = 0; j < m; ++j) {
                    nu[j] += unit[static_cast<std::size_t>(c) * m + j];
                }
            }
            double size = nu[0] * nu[0];
            for (int j = 1; j < m; ++j) {
                size += nu[j] * nu[j];
            }
            size = std::max(std::sqrt(size), 1e-300);
            for (int j = 0; j < m; ++j) {
                nu[j] /= size;
            }
            double bound = 0.0;
            for (int c = 0; c < nv; ++c) {
                const double* u = unit.data() + static_cast<std::size_t>(c) * m;
                double dot = u[0] * nu[0];
                for (int j = 1; j < m; ++j) {
                    dot += u[j] * nu[j];
                }
                bound = c == 0 ? dot : std::min(bound, dot);
            }
            lean[i * in.w + a] = bound;
        }
    }
}

void score_any(const Inputs& in, double* best, double* lean) {
    if (in.m == 2 && in.r == 3) {
        score<3, 2>(in, best, lean);
    } else if (in.m == 2 && in.r == 4) {
        score<4, 2>(in, best, lean);
    } else if (in.m == 2 && in.r == 5) {
        score<5, 2>(in, best, lean);
    } else {
        score<0, 0>(in, best, lean);
    }
}

PyObject* cellpass(PyObject* /*self*/, PyObject* args) {
    Py_buffer work, normals, centres, faces, cells;
    int r = 0, m = 0, w = 0, nv = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*y*y*iiii", &work, &normals, &centres, &faces, &cells, &r, &m, &w, &nv)) {
        return nullptr;
    }
    const auto release = [&] {
        PyBuffer_Release(&work);
        PyBuffer_Release(&normals);
        PyBuffer_Release(&centres);
        PyBuffer_Release(&faces);
        PyBuffer_Release(&cells);
    };
    const Py_ssize_t f = w > 0 ? faces.len / (8 * static_cast<Py_ssize_t>(w)) : 0;
    const Py_ssize_t row = 8 * static_cast<Py_ssize_t>(r);
    const bool shapes = r >= 1 && m >= 1 && w >= 1 && nv >= 1 && faces.len == f * w * 8 &&
                        cells.len == f * nv * 8 && work.len % row == 0 && normals.len % (row * m) == 0 &&
                        centres.len % row == 0;
    if (!shapes) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 work and centres of r columns, float64 normals (n x r x m), int64 "
                        "faces (f x w) and int64 cells (f x nv)");
        return nullptr;
    }
    Inputs in{static_cast<const double*>(work.buf),
              static_cast<const double*>(normals.buf),
              static_cast<const double*>(centres.buf),
              static_cast<const std::int64_t*>(faces.buf),
              static_cast<const std::int64_t*>(cells.buf),
              static_cast<std::int64_t>(f),
              r,
              m,
              w,
              nv};
    const std::int64_t n_rows = normals.len / (row * m), t_rows = centres.len / row, w_rows = work.len / row;
    bool bad = false;
    for (std::int64_t i = 0; i < in.f * in.w && !bad; ++i) {
        bad = in.faces[i] < 0 || in.faces[i] >= std::min(n_rows, w_rows);
    }
    for (std::int64_t i = 0; i < in.f * nv && !bad; ++i) {
        bad = in.cells[i] < 0 || in.cells[i] >= t_rows;
    }
    if (bad) {
        release();
        PyErr_SetString(PyExc_ValueError, "a face or cell names a row outside work, normals or centres");
        return nullptr;
    }
    PyObject* best = PyByteArray_FromStringAndSize(nullptr, f * w * 8);
    PyObject* lean = PyByteArray_FromStringAndSize(nullptr, f * w * 8);
    if (best == nullptr || lean == nullptr) {
        Py_XDECREF(best);
        Py_XDECREF(lean);
        release();
        return nullptr;
    }
    double* b = reinterpret_cast<double*>(PyByteArray_AS_STRING(best));
    double* l = reinterpret_cast<double*>(PyByteArray_AS_STRING(lean));
    Py_BEGIN_ALLOW_THREADS
    score_any(in, b, l);
    Py_END_ALLOW_THREADS
    release();
    return Py_BuildValue("NN", best, lean);
}

PyMethodDef methods[] = {
    {"cellpass", cellpass, METH_VARARGS,
     "cellpass(work, normals, centres, faces, cells, r, m, w, nv) -> (best, lean)\n\n"
     "Per face (int64 rows of w samples) and vertex s, with the face's dual\n"
     "cell spanned by the Voronoi vertices cells[f] (int64 rows of nv): the\n"
     "smallest sin^2 of the angle between c - s and AT_s over the cell's\n"
     "vertices, and the one-sided lower bound of sin over the cell (mean\n"
     "direction, no refinement); float64 (f x w) bytearrays."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cellpass", "Algorithm 2's cocone vertex minimum and certificate on dual cells.", -1,
    methods, nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__cellpass(void) { return PyModule_Create(&module); }
