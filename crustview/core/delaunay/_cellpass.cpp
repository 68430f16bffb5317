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
//
// cellpass_rows() does the same for rows of the whole face list, reading the
// faces and cells itself and writing the chunk's scores (the numpy gathers
// and the bookkeeping of crustview.core.paper.cocone2 held the GIL: a third
// of the pass).  cell_edges() lists the edges of two-dimensional dual cells
// for the exact step, as crustview.core.paper.dualcells.cell_structure does
// (integers only: the same rows in the same order).
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

// cellpass_rows: the same pass for the faces rows[] of the whole face list, gathering their
// vertices and cells itself (cells[i] = cell_simplices[cell_ptr[row] + c]) and finishing the
// chunk as crustview.core.paper.cocone2 did in numpy: sq[row, a] = lean^2 where lean >= sin_lim
// (the certificate holds), else best; the pairs left for the exact step are returned vertex
// position by vertex position, each in the order of rows[].
PyObject* cellpass_rows(PyObject* /*self*/, PyObject* args) {
    Py_buffer work, normals, centres, faces, ptr, owners, rows, sq;
    int r = 0, m = 0, w = 0, nv = 0;
    double sin_lim = 0.0;
    if (!PyArg_ParseTuple(args, "y*y*y*y*y*y*y*w*iiiid", &work, &normals, &centres, &faces, &ptr, &owners, &rows,
                          &sq, &r, &m, &w, &nv, &sin_lim)) {
        return nullptr;
    }
    Py_buffer* bufs[] = {&work, &normals, &centres, &faces, &ptr, &owners, &rows, &sq};
    const auto release = [&] {
        for (Py_buffer* b : bufs) PyBuffer_Release(b);
    };
    const Py_ssize_t row = 8 * static_cast<Py_ssize_t>(r);
    const Py_ssize_t f_all = w > 0 ? faces.len / (8 * static_cast<Py_ssize_t>(w)) : 0;
    const Py_ssize_t count = rows.len / 8;
    const bool shapes = r >= 1 && m >= 1 && w >= 1 && nv >= 1 && faces.len == f_all * w * 8 &&
                        ptr.len == (f_all + 1) * 8 && owners.len % 4 == 0 && rows.len % 8 == 0 &&
                        sq.len == f_all * w * 8 && work.len % row == 0 && normals.len % (row * m) == 0 &&
                        centres.len % row == 0;
    if (!shapes) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected float64 work, normals and centres, int64 faces (f x w) and pointers (f + 1), "
                        "int32 owners, int64 rows and a writable float64 (f x w) output");
        return nullptr;
    }
    const auto* fa = static_cast<const std::int64_t*>(faces.buf);
    const auto* pa = static_cast<const std::int64_t*>(ptr.buf);
    const auto* oa = static_cast<const std::int32_t*>(owners.buf);
    const auto* ra = static_cast<const std::int64_t*>(rows.buf);
    const std::int64_t n_owners = owners.len / 4;
    std::vector<std::int64_t> fc(static_cast<std::size_t>(count) * w), cells(static_cast<std::size_t>(count) * nv);
    const std::int64_t n_rows = normals.len / (row * m), t_rows = centres.len / row, w_rows = work.len / row;
    bool bad = false;
    Py_BEGIN_ALLOW_THREADS  // the gather reads no Python object: the other chunk's thread goes on
    for (Py_ssize_t i = 0; i < count && !bad; ++i) {
        const std::int64_t q = ra[i];
        bad = q < 0 || q >= f_all || pa[q] < 0 || pa[q + 1] - pa[q] != nv || pa[q] + nv > n_owners;
        if (bad) break;
        for (int a = 0; a < w; ++a) fc[static_cast<std::size_t>(i) * w + a] = fa[q * w + a];
        for (int c = 0; c < nv; ++c) cells[static_cast<std::size_t>(i) * nv + c] = oa[pa[q] + c];
    }
    for (std::size_t i = 0; i < fc.size() && !bad; ++i) bad = fc[i] < 0 || fc[i] >= std::min(n_rows, w_rows);
    for (std::size_t i = 0; i < cells.size() && !bad; ++i) bad = cells[i] < 0 || cells[i] >= t_rows;
    Py_END_ALLOW_THREADS
    if (bad) {
        release();
        PyErr_SetString(PyExc_ValueError, "a row, face or cell names an entry outside its array (or a cell of another size)");
        return nullptr;
    }
    Inputs in{static_cast<const double*>(work.buf),
              static_cast<const double*>(normals.buf),
              static_cast<const double*>(centres.buf),
              fc.data(),
              cells.data(),
              static_cast<std::int64_t>(count),
              r,
              m,
              w,
              nv};
    std::vector<double> best(static_cast<std::size_t>(count) * w), lean(static_cast<std::size_t>(count) * w);
    std::vector<std::int64_t> left_rows;
    std::vector<std::int8_t> left_pos;
    auto* out = static_cast<double*>(sq.buf);
    Py_BEGIN_ALLOW_THREADS
    score_any(in, best.data(), lean.data());
    for (Py_ssize_t i = 0; i < count; ++i) {
        for (int a = 0; a < w; ++a) {
            const std::size_t at = static_cast<std::size_t>(i) * w + a;
            out[ra[i] * w + a] = lean[at] >= sin_lim ? lean[at] * lean[at] : best[at];
        }
    }
    for (int a = 0; a < w; ++a) {
        for (Py_ssize_t i = 0; i < count; ++i) {
            if (!(lean[static_cast<std::size_t>(i) * w + a] >= sin_lim)) {
                left_rows.push_back(ra[i]);
                left_pos.push_back(static_cast<std::int8_t>(a));
            }
        }
    }
    Py_END_ALLOW_THREADS
    release();
    const Py_ssize_t n_left = static_cast<Py_ssize_t>(left_rows.size());
    PyObject* lr = PyByteArray_FromStringAndSize(reinterpret_cast<const char*>(left_rows.data()), n_left * 8);
    PyObject* lp = PyByteArray_FromStringAndSize(reinterpret_cast<const char*>(left_pos.data()), n_left);
    if (lr == nullptr || lp == nullptr) {
        Py_XDECREF(lr);
        Py_XDECREF(lp);
        return nullptr;
    }
    return Py_BuildValue("NN", lr, lp);
}

// size_groups: the faces ordered by the size of their dual cell (cell_ptr[i + 1] - cell_ptr[i]),
// each size's faces in increasing order (a counting sort: what numpy's stable argsort gives), and
// the sizes with their counts.  Returns (order int64 bytes, sizes int64 bytes, counts int64 bytes).
PyObject* size_groups(PyObject* /*self*/, PyObject* args) {
    Py_buffer ptr;
    if (!PyArg_ParseTuple(args, "y*", &ptr)) {
        return nullptr;
    }
    if (ptr.len % 8 != 0 || ptr.len < 8) {
        PyBuffer_Release(&ptr);
        PyErr_SetString(PyExc_ValueError, "expected int64 pointers (f + 1)");
        return nullptr;
    }
    const auto* pa = static_cast<const std::int64_t*>(ptr.buf);
    const std::int64_t f = ptr.len / 8 - 1;
    std::vector<std::int64_t> order(static_cast<std::size_t>(f)), sizes, counts;
    bool bad = false;
    Py_BEGIN_ALLOW_THREADS
    std::int64_t top = 0;
    for (std::int64_t i = 0; i < f && !bad; ++i) {
        const std::int64_t nv = pa[i + 1] - pa[i];
        bad = nv < 0 || nv > (std::int64_t{1} << 24);
        top = std::max(top, nv);
    }
    if (!bad) {
        std::vector<std::int64_t> start(static_cast<std::size_t>(top) + 2, 0);
        for (std::int64_t i = 0; i < f; ++i) ++start[static_cast<std::size_t>(pa[i + 1] - pa[i]) + 1];
        for (std::int64_t v = 0; v <= top; ++v) {
            const std::int64_t k = start[static_cast<std::size_t>(v) + 1];
            if (k > 0) {
                sizes.push_back(v);
                counts.push_back(k);
            }
            start[static_cast<std::size_t>(v) + 1] += start[static_cast<std::size_t>(v)];
        }
        for (std::int64_t i = 0; i < f; ++i) order[static_cast<std::size_t>(start[static_cast<std::size_t>(pa[i + 1] - pa[i])]++)] = i;
    }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&ptr);
    if (bad) {
        PyErr_SetString(PyExc_ValueError, "cell pointers must not decrease (and sizes stay under 2^24)");
        return nullptr;
    }
    const auto bytes = [](const std::vector<std::int64_t>& v) {
        return PyByteArray_FromStringAndSize(reinterpret_cast<const char*>(v.data()),
                                             static_cast<Py_ssize_t>(v.size()) * 8);
    };
    return Py_BuildValue("NNN", bytes(order), bytes(sizes), bytes(counts));
}

// cell_edges: the edges of two-dimensional dual cells (codimension 2), as
// crustview.core.paper.dualcells.cell_structure lists them in numpy.  Cell
// simplices i and j of face f are joined when they share the facet f + u,
// u one of the two vertices of each outside f.  The numpy code sorts the
// instances (f, the vertex kept, q, i), q the position dropped among the two
// sorted others, stably, and pairs neighbours with the same (f, kept vertex);
// this does the same per face.  Integers only: the same edges in the same order.
PyObject* cell_edges(PyObject* /*self*/, PyObject* args) {
    Py_buffer faces, simplices, cells;
    int w = 0, width = 0, nv = 0;
    if (!PyArg_ParseTuple(args, "y*y*y*iii", &faces, &simplices, &cells, &w, &width, &nv)) {
        return nullptr;
    }
    const auto release = [&] {
        PyBuffer_Release(&faces);
        PyBuffer_Release(&simplices);
        PyBuffer_Release(&cells);
    };
    const Py_ssize_t count = w > 0 ? faces.len / (8 * static_cast<Py_ssize_t>(w)) : 0;
    if (w < 1 || width != w + 2 || width > 16 || nv < 1 || faces.len != count * w * 8 ||
        simplices.len % (4 * static_cast<Py_ssize_t>(width)) != 0 || cells.len != count * nv * 8) {
        release();
        PyErr_SetString(PyExc_ValueError,
                        "expected int64 faces (F x w), int32 simplices of w + 2 vertices and int64 cells (F x nv)");
        return nullptr;
    }
    const auto* fa = static_cast<const std::int64_t*>(faces.buf);
    const auto* sa = static_cast<const std::int32_t*>(simplices.buf);
    const auto* ca = static_cast<const std::int64_t*>(cells.buf);
    const std::int64_t t = simplices.len / (4 * width);
    struct Inst {
        std::int64_t kept;
        int q, v;
    };
    std::vector<std::int64_t> edges;
    bool bad = false;
    Py_BEGIN_ALLOW_THREADS
    std::vector<Inst> inst(static_cast<std::size_t>(nv) * 2);
    for (Py_ssize_t f = 0; f < count && !bad; ++f) {
        const std::int64_t* face = fa + f * w;
        for (int v = 0; v < nv && !bad; ++v) {
            const std::int64_t id = ca[f * nv + v];
            if (id < 0 || id >= t) {
                bad = true;
                break;
            }
            std::int64_t others[2];
            int at = 0;
            for (int c = 0; c < width; ++c) {
                const std::int64_t u = sa[id * width + c];
                bool in_face = false;
                for (int a = 0; a < w; ++a) in_face = in_face || u == face[a];
                if (!in_face) {
                    if (at == 2) {
                        bad = true;
                        break;
                    }
                    others[at++] = u;
                }
            }
            if (bad || at != 2) {
                bad = true;
                break;
            }
            if (others[1] < others[0]) std::swap(others[0], others[1]);
            inst[static_cast<std::size_t>(2 * v)] = {others[1], 0, v};  // q = 0 drops others[0]
            inst[static_cast<std::size_t>(2 * v + 1)] = {others[0], 1, v};
        }
        if (bad) break;
        std::sort(inst.begin(), inst.end(), [](const Inst& a, const Inst& b) {
            if (a.kept != b.kept) return a.kept < b.kept;
            if (a.q != b.q) return a.q < b.q;
            return a.v < b.v;
        });
        for (std::size_t i = 0; i + 1 < inst.size(); ++i) {
            if (inst[i].kept == inst[i + 1].kept) {
                edges.push_back(f);
                edges.push_back(inst[i].v);
                edges.push_back(inst[i + 1].v);
            }
        }
    }
    Py_END_ALLOW_THREADS
    release();
    if (bad) {
        PyErr_SetString(PyExc_ValueError, "a cell names a simplex outside the table, or one without its face");
        return nullptr;
    }
    return PyByteArray_FromStringAndSize(reinterpret_cast<const char*>(edges.data()),
                                         static_cast<Py_ssize_t>(edges.size()) * 8);
}

PyMethodDef methods[] = {
    {"cellpass", cellpass, METH_VARARGS,
     "cellpass(work, normals, centres, faces, cells, r, m, w, nv) -> (best, lean)\n\n"
     "Per face (int64 rows of w samples) and vertex s, with the face's dual\n"
     "cell spanned by the Voronoi vertices cells[f] (int64 rows of nv): the\n"
     "smallest sin^2 of the angle between c - s and AT_s over the cell's\n"
     "vertices, and the one-sided lower bound of sin over the cell (mean\n"
     "direction, no refinement); float64 (f x w) bytearrays."},
    {"cellpass_rows", cellpass_rows, METH_VARARGS,
     "cellpass_rows(work, normals, centres, faces, cell_ptr, owners, rows, sq, r, m, w, nv, sin_lim)\n"
     "-> (left_rows, left_pos)\n\n"
     "cellpass on the faces rows[] (int64) of the whole list, cells read from the\n"
     "int32 owners through the int64 pointers; writes sq[row] (lean^2 where\n"
     "lean >= sin_lim, else the vertex minimum) and returns the pairs left, as\n"
     "int64 rows and int8 vertex positions, position by position."},
    {"size_groups", size_groups, METH_VARARGS,
     "size_groups(cell_ptr) -> (order, sizes, counts)\n\n"
     "The faces in a stable counting sort by dual cell size, and each size's count\n"
     "(int64 bytearrays)."},
    {"cell_edges", cell_edges, METH_VARARGS,
     "cell_edges(faces, simplices, cells, w, width, nv) -> edges\n\n"
     "Edges (face, i, j) of the two-dimensional dual cells of int64 faces (F x w),\n"
     "cells[f] (int64 F x nv) naming int32 simplices of width = w + 2 vertices,\n"
     "in the order of dualcells.cell_structure; an int64 (E x 3) bytearray."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_cellpass", "Algorithm 2's cocone vertex minimum and certificate on dual cells.", -1,
    methods, nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__cellpass(void) { return PyModule_Create(&module); }
