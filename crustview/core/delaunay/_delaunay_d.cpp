// Delaunay triangulations of points in R^4 and R^5 with CGAL's dD
// Delaunay_triangulation, the dimension fixed at compile time.
//
// Same interface as _delaunay3 (see _cgal_buffers.h): the points come as one
// contiguous float64 buffer of n x dim values, the finite full cells go back
// as a bytearray of vertex numbers (dim + 1 per cell) and, on request, each
// cell's neighbours (neighbour j is across the facet opposite vertex j; -1
// across the convex hull), as Qhull gives them.
//
// Why: Qhull builds the 2.7 million 4-simplices of a 10,000-point Klein
// bottle in R^4 in 30-50 s here; CGAL's dD triangulation with the dimension
// as a template parameter (Epick_d<Dimension_tag<4>>: fixed-size points,
// filtered exact predicates, no dynamic allocation per point) builds the same
// simplices in about 11 s.  With a run-time dimension (as GUDHI and the `cgal`
// wheel use it) it is no faster than Qhull.
//
// Insertion: the points are sorted along a Hilbert curve (CGAL's
// spatial_sort) and each is located from a cell of the previous one.  CGAL's
// Delaunay_triangulation breaks cospherical ties by symbolic perturbation,
// so the result is always a Delaunay triangulation.

#include "_cgal_buffers.h"

#include <CGAL/Delaunay_triangulation.h>
#include <CGAL/Epick_d.h>
#include <CGAL/Spatial_sort_traits_adapter_d.h>
#include <CGAL/Triangulation_data_structure.h>
#include <CGAL/Triangulation_full_cell.h>
#include <CGAL/Triangulation_vertex.h>
#include <CGAL/spatial_sort.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

// The triangulation types for dimension D; vertices and full cells carry an
// int64 (a vertex's input row; a cell's number among the finite cells).
template <int D>
struct Types {
    using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
    using Vertex = CGAL::Triangulation_vertex<Kernel, std::int64_t>;
    using Cell = CGAL::Triangulation_full_cell<Kernel, std::int64_t>;
    using Tds = CGAL::Triangulation_data_structure<CGAL::Dimension_tag<D>, Vertex, Cell>;
    using Triangulation = CGAL::Delaunay_triangulation<Kernel, Tds>;
    using Point = typename Kernel::Point_d;
};

template <int D>
void build(typename Types<D>::Triangulation& tri, const double* coords, std::int64_t n) {
    using Point = typename Types<D>::Point;
    std::vector<Point> points;
    points.reserve(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i) {
        points.emplace_back(coords + D * i, coords + D * (i + 1));
    }
    std::vector<std::ptrdiff_t> order(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i) {
        order[static_cast<std::size_t>(i)] = static_cast<std::ptrdiff_t>(i);
    }
    using Kernel = typename Types<D>::Kernel;
    CGAL::spatial_sort(order.begin(), order.end(),
                       CGAL::Spatial_sort_traits_adapter_d<Kernel, const Point*>(points.data()));
    typename Types<D>::Triangulation::Full_cell_handle hint;
    for (std::ptrdiff_t i : order) {
        auto vertex = tri.insert(points[static_cast<std::size_t>(i)], hint);
        vertex->data() = static_cast<std::int64_t>(i);
        hint = vertex->full_cell();
    }
}

template <int D, typename Index>
void write_cells(const typename Types<D>::Triangulation& tri, char* out) {
    Index* dst = reinterpret_cast<Index*>(out);
    for (auto cell = tri.finite_full_cells_begin(); cell != tri.finite_full_cells_end(); ++cell) {
        for (int j = 0; j <= D; ++j) {
            *dst++ = static_cast<Index>(cell->vertex(j)->data());
        }
    }
}

// Number the full cells (finite ones 0, 1, ... in iteration order, infinite
// -1) and copy each finite cell's neighbour numbers into out.
template <int D, typename Index>
void write_neighbours(typename Types<D>::Triangulation& tri, char* out) {
    auto& tds = tri.tds();
    for (auto cell = tds.full_cells_begin(); cell != tds.full_cells_end(); ++cell) {
        cell->data() = -1;
    }
    std::int64_t number = 0;
    for (auto cell = tri.finite_full_cells_begin(); cell != tri.finite_full_cells_end(); ++cell) {
        cell->data() = number++;
    }
    Index* dst = reinterpret_cast<Index*>(out);
    for (auto cell = tri.finite_full_cells_begin(); cell != tri.finite_full_cells_end(); ++cell) {
        for (int j = 0; j <= D; ++j) {
            *dst++ = static_cast<Index>(cell->neighbor(j)->data());
        }
    }
}

template <int D>
PyObject* triangulate(const Py_buffer& buffer, std::int64_t n, bool want_neighbours) {
    using Triangulation = typename Types<D>::Triangulation;
    const bool wide = n >= (std::int64_t(1) << 31);  // vertex numbers
    Triangulation tri(D);
    const double* coords = static_cast<const double*>(buffer.buf);
    const std::string error = crustview::run_without_gil([&] { build<D>(tri, coords, n); });
    if (!error.empty()) {
        PyErr_Format(PyExc_RuntimeError, "CGAL failed: %s", error.c_str());
        return nullptr;
    }
    const int dimension = tri.current_dimension();
    const Py_ssize_t cells = dimension == D ? static_cast<Py_ssize_t>(tri.number_of_finite_full_cells()) : 0;
    return crustview::cells_result(
        dimension, static_cast<std::int64_t>(tri.number_of_vertices()), cells, D + 1, wide, want_neighbours,
        [&](char* dst, auto zero) { write_cells<D, decltype(zero)>(tri, dst); },
        [&](char* dst, auto zero) { write_neighbours<D, decltype(zero)>(tri, dst); },
        [&] { tri.clear(); });
}

PyObject* full_cells(PyObject* /*self*/, PyObject* args) {
    Py_buffer buffer;
    int dim = 0;
    int want_neighbours = 0;
    if (!PyArg_ParseTuple(args, "y*i|p", &buffer, &dim, &want_neighbours)) {
        return nullptr;
    }
    if (dim != 4 && dim != 5) {
        PyBuffer_Release(&buffer);
        PyErr_Format(PyExc_ValueError, "this extension triangulates in R^4 and R^5 only, not R^%d", dim);
        return nullptr;
    }
    const std::int64_t n = crustview::buffer_rows(buffer, dim);
    PyObject* result = nullptr;
    if (n >= 0) {
        result = dim == 4 ? triangulate<4>(buffer, n, want_neighbours != 0)
                          : triangulate<5>(buffer, n, want_neighbours != 0);
    }
    PyBuffer_Release(&buffer);
    return result;
}

PyMethodDef methods[] = {
    {"full_cells", full_cells, METH_VARARGS,
     "full_cells(coords, dim, neighbours=False) -> (dimension, vertices, cells, neighbours, itemsize,\n"
     "neighbour_itemsize)\n\n"
     "Delaunay triangulation of the float64 points in the buffer coords (n x dim,\n"
     "C order, dim 4 or 5). Returns CGAL's current dimension, its vertex count\n"
     "(less than n when points repeat), the finite full cells as a bytearray of\n"
     "row numbers (dim + 1 per cell), their neighbours as a bytearray of cell\n"
     "numbers (dim + 1 per cell, -1 across the hull; None unless asked for) and\n"
     "the byte size of one number in each (4 or 8)."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_delaunay_d",
    "CGAL's dD Delaunay triangulation in R^4 and R^5, returned as index buffers.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__delaunay_d(void) { return PyModule_Create(&module); }
