// The local sampling radius's cover term (crustview.core.analysis.features.local_spacing):
// the largest enclosing radius of the simplices at each sample.
//
// A small CPython extension (no numpy headers, no third-party code).  It takes
// the points as one contiguous float64 buffer (n x k) and the simplices as one
// contiguous int64 buffer (s x (d + 1)), and returns float64 bytes of length n:
// for every sample the largest enclosing radius of its simplices, 0 for a
// sample in none.  The radii are computed on two threads with the GIL released,
// then scattered in one pass (max is order-free, so the result does not depend
// on the split).
//
// The enclosing radius is features.enclosing_radii's: for a triangle its
// circumradius when no angle is obtuse (c^2 < a^2 + b^2 with c its longest
// edge), else half its longest edge; for other simplices half the longest edge.
// The circumradius solves the same 2x2 Gram system as the numpy code
// (G lam = diag(G) / 2, c = lam_0 a + lam_1 b), by Cramer's rule instead of
// LAPACK's LU, so values agree to rounding (the test compares with the numpy
// reference at rtol 1e-12), not bit for bit.  A non-obtuse triangle has a
// non-singular Gram matrix, so no least-squares fallback is needed.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

namespace {

using i64 = std::int64_t;

double edge(const double* p, const double* q, int k) {
    double s = 0.0;
    for (int i = 0; i < k; ++i) {
        const double t = p[i] - q[i];
        s += t * t;
    }
    return std::sqrt(s);
}

void radii(const double* pts, int k, const i64* cells, int d1, i64 begin, i64 end, double* out) {
    std::vector<double> lengths(static_cast<std::size_t>(d1 * (d1 - 1) / 2));
    for (i64 t = begin; t < end; ++t) {
        const i64* cell = cells + t * d1;
        double longest = 0.0;
        int e = 0;
        for (int i = 0; i < d1; ++i)
            for (int j = i + 1; j < d1; ++j) {
                lengths[e] = edge(pts + cell[i] * k, pts + cell[j] * k, k);
                longest = std::max(longest, lengths[e]);
                ++e;
            }
        double r = longest / 2;
        if (d1 == 3) {
            double s[3] = {lengths[0], lengths[1], lengths[2]};
            std::sort(s, s + 3);
            if (!(s[2] * s[2] >= s[0] * s[0] + s[1] * s[1])) {
                const double* p0 = pts + cell[0] * k;
                const double* p1 = pts + cell[1] * k;
                const double* p2 = pts + cell[2] * k;
                double aa = 0.0, ab = 0.0, bb = 0.0;
                for (int i = 0; i < k; ++i) {
                    const double a = p1[i] - p0[i], b = p2[i] - p0[i];
                    aa += a * a;
                    ab += a * b;
                    bb += b * b;
                }
                const double det = aa * bb - ab * ab;
                const double l0 = (0.5 * aa * bb - ab * 0.5 * bb) / det;
                const double l1 = (aa * 0.5 * bb - ab * 0.5 * aa) / det;
                double c2 = 0.0;
                for (int i = 0; i < k; ++i) {
                    const double c = l0 * (p1[i] - p0[i]) + l1 * (p2[i] - p0[i]);
                    c2 += c * c;
                }
                r = std::sqrt(c2);
            }
        }
        out[t] = r;
    }
}

PyObject* cover(PyObject*, PyObject* args) {
    Py_buffer pb, sb;
    long long n, k, d1;
    if (!PyArg_ParseTuple(args, "y*Ly*L", &pb, &k, &sb, &d1)) return nullptr;
    PyObject* result = nullptr;
    n = k > 0 ? pb.len / 8 / k : 0;
    if (k < 1 || k > 64 || d1 < 2 || d1 > 64 || pb.len != n * k * 8 || sb.len % (8 * d1) != 0) {
        PyErr_SetString(PyExc_ValueError, "cover: points must be float64 (n, k) and simplices int64 (s, d + 1)");
    } else {
        const auto* pts = static_cast<const double*>(pb.buf);
        const auto* cells = static_cast<const i64*>(sb.buf);
        const i64 s = sb.len / 8 / d1;
        bool ok = true;
        for (i64 i = 0; i < s * d1 && ok; ++i) ok = cells[i] >= 0 && cells[i] < n;
        if (!ok) {
            PyErr_SetString(PyExc_ValueError, "cover: a simplex vertex is not a sample");
        } else {
            result = PyBytes_FromStringAndSize(nullptr, static_cast<Py_ssize_t>(n) * 8);
            if (result != nullptr) {
                auto* best = reinterpret_cast<double*>(PyBytes_AS_STRING(result));
                std::vector<double> r(static_cast<std::size_t>(s));
                Py_BEGIN_ALLOW_THREADS;
                const i64 half = s / 2;
                if (s >= 2 * 4096) {
                    std::thread other(radii, pts, static_cast<int>(k), cells, static_cast<int>(d1), half, s,
                                      r.data());
                    radii(pts, static_cast<int>(k), cells, static_cast<int>(d1), 0, half, r.data());
                    other.join();
                } else {
                    radii(pts, static_cast<int>(k), cells, static_cast<int>(d1), 0, s, r.data());
                }
                std::fill(best, best + n, 0.0);
                for (i64 t = 0; t < s; ++t)
                    for (int i = 0; i < d1; ++i) {
                        double& b = best[cells[t * d1 + i]];
                        b = std::max(b, r[t]);
                    }
                Py_END_ALLOW_THREADS;
            }
        }
    }
    PyBuffer_Release(&pb);
    PyBuffer_Release(&sb);
    return result;
}

PyMethodDef methods[] = {
    {"cover", cover, METH_VARARGS,
     "cover(points, k, simplices, d1) -> bytes: float64 per sample, its simplices' largest enclosing radius"},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {PyModuleDef_HEAD_INIT, "_spacing", "Largest enclosing radius per sample.", -1, methods};

}  // namespace

PyMODINIT_FUNC PyInit__spacing() { return PyModule_Create(&module); }
