// Delaunay tetrahedra of points in R^3 with CGAL's Delaunay_triangulation_3.
//
// A small CPython extension (no numpy headers): it takes the points as one
// contiguous float64 buffer of n x 3 values and returns the finite
// tetrahedra as a bytearray of vertex numbers (rows of the input), int32 when
// n < 2^31 and int64 otherwise, so numpy can wrap it without a copy; on
// request also each tetrahedron's four neighbours (neighbour j is across the
// facet opposite vertex j; -1 across a convex hull facet), as Qhull gives them.
//
// Why native code: CGAL builds the triangulation of 300,000 surface points in
// a few seconds, but the `cgal` wheel can only hand it back one Python object
// per cell or as CGAL's text stream, which costs more than the build itself.
//
// Kernel: Exact_predicates_inexact_constructions_kernel (filtered predicates,
// exact on demand); CGAL's Delaunay_triangulation_3 breaks cospherical ties by
// symbolic perturbation, so the result is always a Delaunay triangulation.
// The GIL is released while CGAL works; C++ exceptions become RuntimeError.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cstdint>
#include <exception>
#include <string>
#include <utility>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<std::int64_t, Kernel>;
// each cell carries its number among the finite cells (-1: an infinite cell)
using CellBase = CGAL::Triangulation_cell_base_with_info_3<std::int64_t, Kernel,
                                                           CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Triangulation = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
using Point = Kernel::Point_3;

// Copy the finite cells' vertex numbers into out (4 per cell).
template <typename Index>
void write_cells(const Triangulation& tri, char* out) {
    Index* dst = reinterpret_cast<Index*>(out);
    for (auto cell = tri.finite_cells_begin(); cell != tri.finite_cells_end(); ++cell) {
        for (int j = 0; j < 4; ++j) {
            *dst++ = static_cast<Index>(cell->vertex(j)->info());
        }
    }
}

// Number the cells (finite ones 0, 1, ... in iteration order, infinite -1)
// and copy each finite cell's neighbour numbers into out (4 per cell).
template <typename Index>
void write_neighbours(Triangulation& tri, char* out) {
    for (auto cell = tri.all_cells_begin(); cell != tri.all_cells_end(); ++cell) {
        cell->info() = -1;
    }
    std::int64_t number = 0;
    for (auto cell = tri.finite_cells_begin(); cell != tri.finite_cells_end(); ++cell) {
        cell->info() = number++;
    }
    Index* dst = reinterpret_cast<Index*>(out);
    for (auto cell = tri.finite_cells_begin(); cell != tri.finite_cells_end(); ++cell) {
        for (int j = 0; j < 4; ++j) {
            *dst++ = static_cast<Index>(cell->neighbor(j)->info());
        }
    }
}

// Calls fn with a zero of the narrowest index type that holds the numbers:
// std::int64_t when wide, std::int32_t otherwise.
template <typename Fn>
void with_index_type(bool wide, Fn fn) {
    if (wide) {
        fn(std::int64_t{0});
    } else {
        fn(std::int32_t{0});
    }
}

PyObject* tetrahedra(PyObject* /*self*/, PyObject* args) {
    Py_buffer buffer;
    int want_neighbours = 0;
    if (!PyArg_ParseTuple(args, "y*|p", &buffer, &want_neighbours)) {
        return nullptr;
    }
    const Py_ssize_t row_bytes = 3 * static_cast<Py_ssize_t>(sizeof(double));
    if (buffer.len % row_bytes != 0) {
        PyBuffer_Release(&buffer);
        PyErr_SetString(PyExc_ValueError, "expected a float64 buffer of n x 3 values");
        return nullptr;
    }
    const std::int64_t n = buffer.len / row_bytes;
    const bool wide = n >= (std::int64_t(1) << 31);  // vertex numbers

    Triangulation tri;
    std::string error;
    {
        const double* xyz = static_cast<const double*>(buffer.buf);
        Py_BEGIN_ALLOW_THREADS
        try {
            std::vector<std::pair<Point, std::int64_t>> points;
            points.reserve(static_cast<std::size_t>(n));
            for (std::int64_t i = 0; i < n; ++i) {
                points.emplace_back(Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]), i);
            }
            // the range insert sorts along a Hilbert curve before inserting
            tri.insert(points.begin(), points.end());
        } catch (const std::exception& exc) {
            error = exc.what();
            if (error.empty()) error = "unknown C++ exception";
        } catch (...) {
            error = "unknown C++ exception";
        }
        Py_END_ALLOW_THREADS
    }
    PyBuffer_Release(&buffer);
    if (!error.empty()) {
        PyErr_Format(PyExc_RuntimeError, "CGAL failed: %s", error.c_str());
        return nullptr;
    }

    const int dimension = tri.dimension();
    const std::int64_t vertices = static_cast<std::int64_t>(tri.number_of_vertices());
    Py_ssize_t cells = 0;
    if (dimension == 3) {
        cells = static_cast<Py_ssize_t>(tri.number_of_finite_cells());
    }
    const Py_ssize_t item = wide ? 8 : 4;
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, cells * 4 * item);
    if (out == nullptr) {
        return nullptr;
    }
    if (cells > 0) {
        char* dst = PyByteArray_AS_STRING(out);
        Py_BEGIN_ALLOW_THREADS
        with_index_type(wide, [&](auto zero) { write_cells<decltype(zero)>(tri, dst); });
        Py_END_ALLOW_THREADS
    }
    const bool wide_cells = static_cast<std::int64_t>(cells) >= (std::int64_t(1) << 31);
    const Py_ssize_t nitem = wide_cells ? 8 : 4;
    PyObject* nbrs = Py_None;
    Py_INCREF(Py_None);
    if (want_neighbours && dimension == 3) {
        Py_DECREF(Py_None);
        nbrs = PyByteArray_FromStringAndSize(nullptr, cells * 4 * nitem);
        if (nbrs == nullptr) {
            Py_DECREF(out);
            return nullptr;
        }
        char* dst = PyByteArray_AS_STRING(nbrs);
        Py_BEGIN_ALLOW_THREADS
        with_index_type(wide_cells, [&](auto zero) { write_neighbours<decltype(zero)>(tri, dst); });
        Py_END_ALLOW_THREADS
    }
    {
        // free CGAL's memory before numpy takes over the result
        Py_BEGIN_ALLOW_THREADS
        tri.clear();
        Py_END_ALLOW_THREADS
    }
    return Py_BuildValue("iLNNii", dimension, static_cast<long long>(vertices), out, nbrs, static_cast<int>(item),
                         static_cast<int>(nitem));
}

PyMethodDef methods[] = {
    {"tetrahedra", tetrahedra, METH_VARARGS,
     "tetrahedra(xyz, neighbours=False) -> (dimension, vertices, cells, neighbours, itemsize, neighbour_itemsize)\n\n"
     "Delaunay triangulation of the float64 points in the buffer xyz (n x 3,\n"
     "C order). Returns CGAL's dimension, its vertex count (less than n when\n"
     "points repeat), the finite tetrahedra as a bytearray of row numbers\n"
     "(4 per cell), their neighbours as a bytearray of cell numbers (4 per\n"
     "cell, -1 across the hull; None unless asked for) and the byte size of\n"
     "one number in each (4 or 8)."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_delaunay3",
    "CGAL's 3D Delaunay triangulation, returned as an index buffer.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__delaunay3(void) { return PyModule_Create(&module); }
