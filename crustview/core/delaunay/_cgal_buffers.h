// What crustview's CGAL extensions share: reading a float64 point buffer,
// running CGAL with the GIL released, and handing cells back as index buffers.
//
// Every extension function returns the same tuple
//   (dimension, vertices, cells, neighbours, itemsize, neighbour_itemsize)
// where cells and neighbours are bytearrays numpy wraps without a copy
// (int32 numbers when they fit, int64 otherwise; neighbours None unless asked
// for).  Header-only so that each extension stays one translation unit.

#ifndef CRUSTVIEW_CGAL_BUFFERS_H
#define CRUSTVIEW_CGAL_BUFFERS_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cstdint>
#include <exception>
#include <string>
#include <system_error>
#include <thread>

namespace crustview {

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

// Rows of `width` float64 values in the buffer, or -1 (with ValueError set).
inline std::int64_t buffer_rows(const Py_buffer& buffer, int width) {
    const Py_ssize_t row_bytes = width * static_cast<Py_ssize_t>(sizeof(double));
    if (buffer.len % row_bytes != 0) {
        PyErr_Format(PyExc_ValueError, "expected a float64 buffer of n x %d values", width);
        return -1;
    }
    return buffer.len / row_bytes;
}

// Runs work() without the GIL; a C++ exception becomes the returned message
// (empty on success).
template <typename Work>
std::string run_without_gil(Work work) {
    std::string error;
    Py_BEGIN_ALLOW_THREADS
    try {
        work();
    } catch (const std::exception& exc) {
        error = exc.what();
        if (error.empty()) error = "unknown C++ exception";
    } catch (...) {
        error = "unknown C++ exception";
    }
    Py_END_ALLOW_THREADS
    return error;
}

// The extension functions' result tuple.  write_cells(char*, zero) and
// write_neighbours(char*, zero) fill per_cell numbers per cell, of the type of
// zero; they run without the GIL, and at the same time on two threads when
// both are asked for: write_cells reads only the vertices' numbers and
// write_neighbours writes only the cells' (both walk the cells read-only), so
// neither sees the other's writes (300,000 torus points: the two passes took
// 0.14 s and 0.28 s one after the other).  free_all() releases CGAL's memory.
template <typename WriteCells, typename WriteNeighbours, typename Free>
PyObject* cells_result(int dimension, std::int64_t vertices, Py_ssize_t cells, int per_cell, bool wide,
                       bool want_neighbours, WriteCells write_cells, WriteNeighbours write_neighbours,
                       Free free_all) {
    const Py_ssize_t item = wide ? 8 : 4;
    PyObject* out = PyByteArray_FromStringAndSize(nullptr, cells * per_cell * item);
    if (out == nullptr) {
        return nullptr;
    }
    const bool wide_cells = static_cast<std::int64_t>(cells) >= (std::int64_t(1) << 31);
    const Py_ssize_t nitem = wide_cells ? 8 : 4;
    PyObject* nbrs = Py_None;
    Py_INCREF(Py_None);
    if (want_neighbours && cells > 0) {
        Py_DECREF(Py_None);
        nbrs = PyByteArray_FromStringAndSize(nullptr, cells * per_cell * nitem);
        if (nbrs == nullptr) {
            Py_DECREF(out);
            return nullptr;
        }
    }
    if (cells > 0) {
        char* dst = PyByteArray_AS_STRING(out);
        char* ndst = nbrs == Py_None ? nullptr : PyByteArray_AS_STRING(nbrs);
        Py_BEGIN_ALLOW_THREADS
        auto cells_pass = [&] { with_index_type(wide, [&](auto zero) { write_cells(dst, zero); }); };
        std::thread other;
        if (ndst != nullptr) {
            try {
                other = std::thread(cells_pass);
            } catch (const std::system_error&) {  // no thread to be had: one pass after the other
                cells_pass();
            }
            with_index_type(wide_cells, [&](auto zero) { write_neighbours(ndst, zero); });
        } else {
            cells_pass();
        }
        if (other.joinable()) {
            other.join();
        }
        Py_END_ALLOW_THREADS
    }
    {
        // free CGAL's memory before numpy takes over the result
        Py_BEGIN_ALLOW_THREADS
        free_all();
        Py_END_ALLOW_THREADS
    }
    return Py_BuildValue("iLNNii", dimension, static_cast<long long>(vertices), out, nbrs, static_cast<int>(item),
                         static_cast<int>(nitem));
}

}  // namespace crustview

#endif  // CRUSTVIEW_CGAL_BUFFERS_H
