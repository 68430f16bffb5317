// Algorithm 2's literal test on triangles, as
// crustview.core.paper.literal.literal_angles does it in numpy for 2-faces.
//
// For a face with vertices p0, p1, p2 (rows of work, r coordinates), the
// orthonormal basis of its edge span by Gram-Schmidt from p0:
//   e1 = (p1 - p0) / max(|p1 - p0|, 1e-300)
//   w = p2 - p0, w -= (w . e1) e1, e2 = w / max(|w|, 1e-300)
// and for each vertex s with normal basis N (r x m, row-major) the squared
// spectral norm of N^T [e1 e2]: with g_cj = N_j . e_c,
//   a = g_1 . g_1, b = g_1 . g_2, c = g_2 . g_2
//   ||.||^2 = 0.5 (a + c) + sqrt(0.25 (a - c)^2 + b^2)   (the sum of squares when m = 1)
// The result is the smallest sqrt of that over the three vertices (the sine
// of the literal angle); the caller takes arcsin.  The arithmetic is numpy's,
// operation for operation (sums sequential from their first term, no fused
// multiply-add: -ffp-contract=off in setup.py), so the sines are the same bit
// for bit.  The GIL is released.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

struct Inputs {
    const double* work;         // (rows, r)
    const double* normals;      // (n, r, m)
    const std::int64_t* faces;  // (f, 3)
    std::int64_t f;
    int r, m;
};

// R coordinates and M normal directions as compile-time constants (0: the
// run-time in.r, in.m), so the compiler keeps a face's values in registers;
// the operations and their order are the same in every instance.
template <int R, int M>
void sines(const Inputs& in, double* out) {
    constexpr int kMax = 8;  // R and M above this take the run-time instance's heap buffers
    const int r = R > 0 ? R : in.r, m = M > 0 ? M : in.m;
    std::vector<double> heap(R > 0 && M > 0 ? 0 : 2 * (r + m));
    double local[4 * kMax];
    double* e1 = R > 0 && M > 0 ? local : heap.data();
    double* e2 = e1 + r;
    double* g1 = e2 + r;
    double* g2 = g1 + m;
    const auto dot = [](const double* a, const double* b, int size) {
        double acc = a[0] * b[0];
        for (int q = 1; q < size; ++q) {
            acc += a[q] * b[q];
        }
        return acc;
    };
    const auto normalise = [&](double* v) {
        const double size = std::max(std::sqrt(dot(v, v, r)), 1e-300);
        for (int q = 0; q < r; ++q) {
            v[q] /= size;
        }
    };
    for (std::int64_t i = 0; i < in.f; ++i) {
        const std::int64_t* face = in.faces + 3 * i;
        const double* p0 = in.work + face[0] * r;
        const double* p1 = in.work + face[1] * r;
        const double* p2 = in.work + face[2] * r;
        for (int q = 0; q < r; ++q) {
            e1[q] = p1[q] - p0[q];
        }
        normalise(e1);
        for (int q = 0; q < r; ++q) {
            e2[q] = p2[q] - p0[q];
        }
        const double proj = dot(e2, e1, r);
        for (int q = 0; q < r; ++q) {
            e2[q] -= proj * e1[q];
        }
        normalise(e2);
        double best = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            const double* nr = in.normals + face[a] * r * m;  // nr[q * m + j]
            for (int j = 0; j < m; ++j) {
                double x = nr[j] * e1[0], y = nr[j] * e2[0];
                for (int q = 1; q < r; ++q) {
                    x += nr[q * m + j] * e1[q];
                    y += nr[q * m + j] * e2[q];
                }
                g1[j] = x;
                g2[j] = y;
            }
            double sq;
            if (m == 1) {  // rank one: the Frobenius norm
                sq = g1[0] * g1[0] + g2[0] * g2[0];
            } else {
                const double aa = dot(g1, g1, m);
                const double bb = dot(g1, g2, m);
                const double cc = dot(g2, g2, m);
                const double diff = aa - cc;
                sq = 0.5 * (aa + cc) + std::sqrt(0.25 * (diff * diff) + bb * bb);
            }
            best = std::min(best, std::sqrt(sq));
        }
        out[i] = best;
    }
}

void sines_any(const Inputs& in, double* out) {
    if (in.r == 3 && in.m == 1) {
        sines<3, 1>(in, out);
    } else if (in.r == 4 && in.m == 2) {
        sines<4, 2>(in, out);
    } else if (in.r == 5 && in.m == 3) {
        sines<5, 3>(in, out);
    } else {
        sines<0, 0>(in, out);
    }
}

PyObject* literal(PyObject* /*self*/, PyObject* args) {
    Py_buffer work, normals, faces;
    int r = 0, m = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*ii", &work, &normals, &faces, &r, &m)) {
        return nullptr;
    }
    const auto release = [&] {
        PyBuffer_Release(&work);
        PyBuffer_Release(&normals);
        PyBuffer_Release(&faces);
    };
    const Py_ssize_t f = faces.len / 24;
    const Py_ssize_t row = 8 * static_cast<Py_ssize_t>(r);
    const bool shapes = r >= 1 && m >= 1 && faces.len == f * 24 && work.len % row == 0 &&
                        normals.len % (row * m) == 0;
    if (!shapes) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 work (rows x r), float64 normals (n x r x m) and int64 faces (f x 3)");
        return nullptr;
    }
    Inputs in{static_cast<const double*>(work.buf), static_cast<const double*>(normals.buf),
              static_cast<const std::int64_t*>(faces.buf), static_cast<std::int64_t>(f), r, m};
    const std::int64_t rows = std::min(work.len / row, normals.len / (row * m));
    bool bad = false;
    for (std::int64_t i = 0; i < 3 * in.f && !bad; ++i) {
        bad = in.faces[i] < 0 || in.faces[i] >= rows;
    }
    if (bad) {
        release();
        PyErr_SetString(PyExc_ValueError, "a face names a row outside work or normals");
        return nullptr;
    }
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, f * 8);
    if (out == nullptr) {
        release();
        return nullptr;
    }
    double* o = reinterpret_cast<double*>(PyByteArray_AS_STRING(out));
    Py_BEGIN_ALLOW_THREADS
    sines_any(in, o);
    Py_END_ALLOW_THREADS
    release();
    return out;
}

PyMethodDef methods[] = {
    {"literal", literal, METH_VARARGS,
     "literal(work, normals, faces, r, m) -> sines\n\n"
     "Per triangle (int64 rows of 3 samples): the smallest, over its vertices,\n"
     "sine of the largest principal angle between its plane and the vertex's\n"
     "tangent plane; a float64 (f,) bytearray."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_literal", "Algorithm 2's literal test on triangles.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__literal(void) { return PyModule_Create(&module); }
