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

#include "_cgal_buffers.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cstdint>
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

PyObject* tetrahedra(PyObject* /*self*/, PyObject* args) {
    Py_buffer buffer;
    int want_neighbours = 0;
    if (!PyArg_ParseTuple(args, "y*|p", &buffer, &want_neighbours)) {
        return nullptr;
    }
    const std::int64_t n = crustview::buffer_rows(buffer, 3);
    if (n < 0) {
        PyBuffer_Release(&buffer);
        return nullptr;
    }
    const bool wide = n >= (std::int64_t(1) << 31);  // vertex numbers

    Triangulation tri;
    const double* xyz = static_cast<const double*>(buffer.buf);
    const std::string error = crustview::run_without_gil([&] {
        std::vector<std::pair<Point, std::int64_t>> points;
        points.reserve(static_cast<std::size_t>(n));
        for (std::int64_t i = 0; i < n; ++i) {
            points.emplace_back(Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]), i);
        }
        // the range insert sorts along a Hilbert curve before inserting
        tri.insert(points.begin(), points.end());
    });
    PyBuffer_Release(&buffer);
    if (!error.empty()) {
        PyErr_Format(PyExc_RuntimeError, "CGAL failed: %s", error.c_str());
        return nullptr;
    }

    const int dimension = tri.dimension();
    const Py_ssize_t cells = dimension == 3 ? static_cast<Py_ssize_t>(tri.number_of_finite_cells()) : 0;
    return crustview::cells_result(
        dimension, static_cast<std::int64_t>(tri.number_of_vertices()), cells, 4, wide, want_neighbours != 0,
        [&](char* dst, auto zero) { write_cells<decltype(zero)>(tri, dst); },
        [&](char* dst, auto zero) { write_neighbours<decltype(zero)>(tri, dst); },
        [&] { tri.clear(); });
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
