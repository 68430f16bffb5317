// Algorithm 2's cocone score in codimension 1, first two steps, as
// crustview.core.paper.candidates._score_segments does them in numpy.
//
// In codimension 1 the dual cell of a face is a segment between two Voronoi
// vertices c0, c1 and every sample has one unit normal n.  For each face and
// each of its vertices s, with x_i = c_i - s:
//   p_i = n . x_i, q_i = max(|x_i|^2, 1e-300)
//   best = min(p_0^2 / q_0, p_1^2 / q_1)          (sin^2 at the segment's ends)
//   u_i = p_i / sqrt(q_i), side = sign(u_0 + u_1)  (u_0 + u_1 over max(|u_0 + u_1|, 1e-300))
//   lean = min(u_0 side, u_1 side)                 (the one-sided certificate)
// The caller certifies lean >= sin(limit) and runs the exact minimum on the
// rest.  The arithmetic is numpy's, operation for operation (dot products
// summed from the first coordinate, no fused multiply-add: -ffp-contract=off
// in setup.py), so the scores are the same bit for bit.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace {

struct Inputs {
    const double* work;     // (rows, r)
    const double* normals;  // (n, r)
    const double* centres;  // (t, r)
    const std::int64_t* faces;  // (f, w)
    const std::int64_t* cells;  // (f, 2)
    std::int64_t f;
    int r, w;
};

void score(const Inputs& in, double* best, double* lean) {
    for (std::int64_t i = 0; i < in.f; ++i) {
        const double* c0 = in.centres + in.cells[2 * i] * in.r;
        const double* c1 = in.centres + in.cells[2 * i + 1] * in.r;
        for (int a = 0; a < in.w; ++a) {
            const std::int64_t v = in.faces[i * in.w + a];
            const double* s = in.work + v * in.r;
            const double* nr = in.normals + v * in.r;
            double x0 = c0[0] - s[0], x1 = c1[0] - s[0];
            double p0 = x0 * nr[0], p1 = x1 * nr[0];
            double q0 = x0 * x0, q1 = x1 * x1;
            for (int c = 1; c < in.r; ++c) {
                x0 = c0[c] - s[c];
                x1 = c1[c] - s[c];
                p0 += x0 * nr[c];
                p1 += x1 * nr[c];
                q0 += x0 * x0;
                q1 += x1 * x1;
            }
            q0 = std::max(q0, 1e-300);
            q1 = std::max(q1, 1e-300);
            best[i * in.w + a] = std::min(p0 * p0 / q0, p1 * p1 / q1);
            const double u0 = p0 / std::sqrt(q0), u1 = p1 / std::sqrt(q1);
            double side = u0 + u1;
            side /= std::max(std::fabs(side), 1e-300);
            lean[i * in.w + a] = std::min(u0 * side, u1 * side);
        }
    }
}

PyObject* segments(PyObject* /*self*/, PyObject* args) {
    Py_buffer work, normals, centres, faces, cells;
    int r = 0, w = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*y*y*ii", &work, &normals, &centres, &faces, &cells, &r, &w)) {
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
    const bool shapes = r >= 1 && w >= 2 && faces.len == f * w * 8 && cells.len == f * 16 &&
                        work.len % row == 0 && normals.len % row == 0 && centres.len % row == 0;
    if (!shapes) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 work, normals and centres of r columns, int64 faces (f x w) "
                        "and int64 cells (f x 2)");
        return nullptr;
    }
    Inputs in{static_cast<const double*>(work.buf), static_cast<const double*>(normals.buf),
              static_cast<const double*>(centres.buf), static_cast<const std::int64_t*>(faces.buf),
              static_cast<const std::int64_t*>(cells.buf), static_cast<std::int64_t>(f), r, w};
    const std::int64_t n_rows = normals.len / row, t_rows = centres.len / row, w_rows = work.len / row;
    bool bad = false;
    for (std::int64_t i = 0; i < in.f * in.w && !bad; ++i) {
        bad = in.faces[i] < 0 || in.faces[i] >= std::min(n_rows, w_rows);
    }
    for (std::int64_t i = 0; i < 2 * in.f && !bad; ++i) {
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
    score(in, b, l);
    Py_END_ALLOW_THREADS
    release();
    return Py_BuildValue("NN", best, lean);
}

PyMethodDef methods[] = {
    {"segments", segments, METH_VARARGS,
     "segments(work, normals, centres, faces, cells, r, w) -> (best, lean)\n\n"
     "Per face (int64 rows of w samples) and vertex s, with the face's dual\n"
     "segment between the Voronoi vertices cells[f] (int64 pairs): the\n"
     "smaller sin^2 of the angle between c - s and AT_s at the two ends, and\n"
     "the one-sided lower bound of sin over the segment; float64 (f x w)\n"
     "bytearrays."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_segments", "Algorithm 2's codimension-1 cocone ends and certificate.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__segments(void) { return PyModule_Create(&module); }
