// Circumcentres of Delaunay simplices in R^2..R^5, the same values bit for bit
// as crustview.core.delaunay.triangulation.circumcenters' numpy code.
//
// A small CPython extension (no numpy headers, no third-party code).  It takes
// the points as one contiguous float64 buffer (n x r), the simplices as one
// contiguous int32 or int64 buffer (t x (r + 1)) and fills a float64 output
// buffer (t x r), on two threads with the GIL released.
//
// Same arithmetic as the numpy code, in the same order (built with
// -ffp-contract=off: no fused multiply-add): a_i = p_i - p_0, b_i = a_i . a_i / 2
// summed as numpy's einsum sums it, Gaussian elimination with partial pivoting (the first
// largest pivot), back substitution, then c = x + p_0.  A simplex whose
// determinant fails numpy's test (|det| <= 1e-14 max|a|^r) is flagged instead:
// the caller solves it by least squares, as the numpy code does.  The caller
// also checks once that both give the same bits (einsum's order belongs to
// numpy's build), and uses numpy alone otherwise.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

namespace {

template <int R, typename Index>
void centres(const double* pts, const Index* cells, std::int64_t begin, std::int64_t end, double* out,
             unsigned char* bad) {
    for (std::int64_t t = begin; t < end; ++t) {
        const Index* cell = cells + t * (R + 1);
        const double* p0 = pts + static_cast<std::int64_t>(cell[0]) * R;
        double mat[R][R];
        double rhs[R];
        double scale = 0.0;
        for (int i = 0; i < R; ++i) {
            const double* pi = pts + static_cast<std::int64_t>(cell[i + 1]) * R;
            double top = 0.0;
            for (int j = 0; j < R; ++j) {
                mat[i][j] = pi[j] - p0[j];
                top = std::fabs(mat[i][j]) > top ? std::fabs(mat[i][j]) : top;
            }
            // numpy's einsum over r < 8 terms: even and odd terms in two lanes, then their sum
            double even = mat[i][0] * mat[i][0];
            double odd = mat[i][1] * mat[i][1];
            for (int j = 2; j < R; j += 2) even += mat[i][j] * mat[i][j];
            for (int j = 3; j < R; j += 2) odd += mat[i][j] * mat[i][j];
            rhs[i] = 0.5 * (even + odd);
            scale = top > scale ? top : scale;
        }
        scale = std::pow(scale, static_cast<double>(R));
        double det = 1.0;
        for (int col = 0; col < R; ++col) {
            if (col < R - 1) {
                int piv = col;
                double best = std::fabs(mat[col][col]);
                for (int i = col + 1; i < R; ++i) {
                    if (std::fabs(mat[i][col]) > best) {
                        best = std::fabs(mat[i][col]);
                        piv = i;
                    }
                }
                if (piv != col) {
                    det = -det;
                    for (int j = col; j < R; ++j) {
                        const double keep = mat[col][j];
                        mat[col][j] = mat[piv][j];
                        mat[piv][j] = keep;
                    }
                    const double keep = rhs[col];
                    rhs[col] = rhs[piv];
                    rhs[piv] = keep;
                }
            }
            const double pivot = mat[col][col];
            det *= pivot;
            for (int i = col + 1; i < R; ++i) {
                const double f = mat[i][col] / pivot;
                for (int j = col + 1; j < R; ++j) {
                    mat[i][j] -= f * mat[col][j];
                }
                rhs[i] -= f * rhs[col];
            }
        }
        double x[R];
        for (int i = R - 1; i >= 0; --i) {
            double acc = rhs[i];
            for (int j = i + 1; j < R; ++j) {
                acc -= mat[i][j] * x[j];
            }
            x[i] = acc / mat[i][i];
        }
        const bool ok = std::fabs(det) > 1e-14 * (scale > 1e-300 ? scale : 1e-300);
        bad[t] = ok ? 0 : 1;
        double* dst = out + t * R;
        for (int j = 0; j < R; ++j) {
            dst[j] = x[j] + p0[j];
        }
    }
}

template <int R, typename Index>
void run(const double* pts, const void* cells, std::int64_t t, double* out, unsigned char* bad, int threads) {
    const Index* idx = static_cast<const Index*>(cells);
    std::vector<std::thread> pool;
    const std::int64_t step = (t + threads - 1) / threads;
    for (int w = 1; w < threads; ++w) {
        const std::int64_t lo = w * step, hi = lo + step < t ? lo + step : t;
        if (lo < hi) pool.emplace_back([=] { centres<R, Index>(pts, idx, lo, hi, out, bad); });
    }
    centres<R, Index>(pts, idx, 0, step < t ? step : t, out, bad);
    for (auto& th : pool) th.join();
}

template <int R>
void dispatch(const double* pts, const void* cells, int itemsize, std::int64_t t, double* out, unsigned char* bad,
              int threads) {
    if (itemsize == 4) {
        run<R, std::int32_t>(pts, cells, t, out, bad, threads);
    } else {
        run<R, std::int64_t>(pts, cells, t, out, bad, threads);
    }
}

PyObject* circumcentres(PyObject* /*self*/, PyObject* args) {
    Py_buffer points, cells, out, bad;
    int r = 0, itemsize = 0, threads = 1;
    if (!PyArg_ParseTuple(args, "y*y*iiw*w*i", &points, &cells, &r, &itemsize, &out, &bad, &threads)) {
        return nullptr;
    }
    const std::int64_t t = r >= 2 ? cells.len / ((r + 1) * static_cast<Py_ssize_t>(itemsize > 0 ? itemsize : 1)) : 0;
    const bool fits = r >= 2 && r <= 5 && (itemsize == 4 || itemsize == 8) &&
                      cells.len == t * (r + 1) * itemsize && out.len == t * r * 8 && bad.len == t &&
                      points.len % (r * 8) == 0;
    if (!fits) {
        PyBuffer_Release(&points);
        PyBuffer_Release(&cells);
        PyBuffer_Release(&out);
        PyBuffer_Release(&bad);
        PyErr_SetString(PyExc_ValueError, "expected points (n x r), simplices (t x (r + 1)), out (t x r), bad (t)");
        return nullptr;
    }
    const double* p = static_cast<const double*>(points.buf);
    double* o = static_cast<double*>(out.buf);
    unsigned char* b = static_cast<unsigned char*>(bad.buf);
    threads = threads < 1 ? 1 : threads;
    Py_BEGIN_ALLOW_THREADS
    switch (r) {
        case 2: dispatch<2>(p, cells.buf, itemsize, t, o, b, threads); break;
        case 3: dispatch<3>(p, cells.buf, itemsize, t, o, b, threads); break;
        case 4: dispatch<4>(p, cells.buf, itemsize, t, o, b, threads); break;
        default: dispatch<5>(p, cells.buf, itemsize, t, o, b, threads); break;
    }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&points);
    PyBuffer_Release(&cells);
    PyBuffer_Release(&out);
    PyBuffer_Release(&bad);
    Py_RETURN_NONE;
}

PyMethodDef methods[] = {
    {"circumcentres", circumcentres, METH_VARARGS,
     "circumcentres(points, simplices, r, itemsize, out, bad, threads) -> None\n\n"
     "Fill out (t x r float64) with the circumcentres of the simplices (t x (r + 1),\n"
     "int32 or int64 as itemsize says) of the float64 points (n x r), 2 <= r <= 5,\n"
     "and bad (t bytes) with 1 where the determinant test fails (solve those\n"
     "by least squares). Vertex numbers are not checked: callers pass valid ones."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_centres",
    "Circumcentres of Delaunay simplices, as crustview's numpy code computes them.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__centres(void) { return PyModule_Create(&module); }
