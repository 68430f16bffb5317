// Algorithm 2's cocone score in codimension 1, as
// crustview.core.paper.candidates._score_segments does it in numpy.
//
// In codimension 1 the dual cell of a face is a segment between two Voronoi
// vertices c0, c1 and every sample has one unit normal n.  For each face and
// each of its vertices s, with x_i = c_i - s:
//   p_i = n . x_i, q_i = max(|x_i|^2, 1e-300)
//   best = min(p_0^2 / q_0, p_1^2 / q_1)          (sin^2 at the segment's ends)
//   u_i = p_i / sqrt(q_i), side = sign(u_0 + u_1)  (u_0 + u_1 over max(|u_0 + u_1|, 1e-300))
//   lean = min(u_0 side, u_1 side)                 (the one-sided certificate)
// sin2() returns the exact minimum over the segment from them
// (candidates.segment_sin2: the segment crosses the tangent plane where
// lean <= 0, and otherwise its minimum is at an end).  The arithmetic is
// numpy's, operation for operation (dot products summed from the first
// coordinate, no fused multiply-add: -ffp-contract=off in setup.py), so the
// scores are the same bit for bit.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace {

// numpy's minimum: a NaN on either side is the result (std::min keeps the first argument then).
inline double minimum(double a, double b) {
    if (a != a) return a;
    if (b != b) return b;
    return b < a ? b : a;
}

struct Inputs {
    const double* work;     // (rows, r)
    const double* normals;  // (n, r)
    const double* centres;  // (t, r)
    const std::int64_t* faces;  // (f, w)
    const std::int64_t* cells;  // (f, 2)
    std::int64_t f;
    int r, w;
};

//: Faces ahead of the current one whose segment ends are prefetched.
constexpr std::int64_t kAhead = 16;

// The exact minimum over the segment (candidates.segment_sin2, operation for operation): lean^2 where
// lean >= sin_lim, 0 where lean <= 0 (the segment crosses the tangent plane), else best (the nearer end:
// no point inside beats it).
void score(const Inputs& in, double* sin2, double sin_lim) {
    for (std::int64_t i = 0; i < in.f; ++i) {
        if (i + kAhead < in.f) {  // the Voronoi vertices are scattered over the triangulation: ask early
            __builtin_prefetch(in.centres + in.cells[2 * (i + kAhead)] * in.r);
            __builtin_prefetch(in.centres + in.cells[2 * (i + kAhead) + 1] * in.r);
        }
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
            const double b = minimum(p0 * p0 / q0, p1 * p1 / q1);
            const double u0 = p0 / std::sqrt(q0), u1 = p1 / std::sqrt(q1);
            double side = u0 + u1;
            side /= std::max(std::fabs(side), 1e-300);
            const double l = minimum(u0 * side, u1 * side);
            sin2[i * in.w + a] = l >= sin_lim ? l * l : (l <= 0.0 ? 0.0 : b);
        }
    }
}

// Parses and checks the arrays; false (with a Python error set) if they do not fit.
bool parse(PyObject* args, Py_buffer (&bufs)[5], Inputs& in, double* sin_lim) {
    int r = 0, w = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*y*y*iid", &bufs[0], &bufs[1], &bufs[2], &bufs[3], &bufs[4], &r, &w, sin_lim)) {
        return false;
    }
    const auto release = [&] {
        for (auto& b : bufs) {
            PyBuffer_Release(&b);
        }
    };
    Py_buffer &work = bufs[0], &normals = bufs[1], &centres = bufs[2], &faces = bufs[3], &cells = bufs[4];
    const Py_ssize_t f = w > 0 ? faces.len / (8 * static_cast<Py_ssize_t>(w)) : 0;
    const Py_ssize_t row = 8 * static_cast<Py_ssize_t>(r);
    const bool shapes = r >= 1 && w >= 2 && faces.len == f * w * 8 && cells.len == f * 16 &&
                        work.len % row == 0 && normals.len % row == 0 && centres.len % row == 0;
    if (!shapes) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 work, normals and centres of r columns, int64 faces (f x w) "
                        "and int64 cells (f x 2)");
        return false;
    }
    in = Inputs{static_cast<const double*>(work.buf), static_cast<const double*>(normals.buf),
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
        return false;
    }
    return true;
}

PyObject* sin2(PyObject* /*self*/, PyObject* args) {
    Py_buffer bufs[5] = {};
    Inputs in{};
    double sin_lim = 0.0;
    if (!parse(args, bufs, in, &sin_lim)) {
        return nullptr;
    }
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, in.f * in.w * 8);
    if (out != nullptr) {
        double* v = reinterpret_cast<double*>(PyByteArray_AS_STRING(out));
        Py_BEGIN_ALLOW_THREADS
        score(in, v, sin_lim);
        Py_END_ALLOW_THREADS
    }
    for (auto& b : bufs) {
        PyBuffer_Release(&b);
    }
    return out;
}

PyMethodDef methods[] = {
    {"sin2", sin2, METH_VARARGS,
     "sin2(work, normals, centres, faces, cells, r, w, sin_lim) -> sin2\n\n"
     "Per face (int64 rows of w samples) and vertex s, with the face's dual\n"
     "segment between the Voronoi vertices cells[f] (int64 pairs): the exact\n"
     "minimum of sin^2 of the angle between y - s and AT_s over the segment\n"
     "(candidates.segment_sin2 of the ends' best and lean, bit for bit); a\n"
     "float64 (f x w) bytearray."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_segments", "Algorithm 2's codimension-1 cocone scores.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__segments(void) { return PyModule_Create(&module); }
