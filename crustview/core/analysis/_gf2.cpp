// The rank over GF(2) of a boundary matrix (crustview.core.analysis.ranks.boundary_rank_gf2).
//
// The standard column reduction: the columns are taken in their order; a column's "low" is its largest
// row; while another column already reduced has the same low, the two are added (over GF(2): the
// symmetric difference of their rows); a column left non-zero is a pivot, and the rank is the number of
// pivots.  The Python reference does the same with integers as bit sets; the rank does not depend on
// the order, so both give the same number (tests/test_core_topology_compiled.py).  Columns are sorted
// row lists, so a sum costs the two columns' lengths, not the matrix's height.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <vector>

namespace {

using i64 = std::int64_t;

PyObject* rank(PyObject*, PyObject* args) {
    Py_buffer a;
    long long rows, width;
    if (!PyArg_ParseTuple(args, "y*LL", &a, &rows, &width)) return nullptr;
    PyObject* result = nullptr;
    if (rows < 0 || width < 1 || a.len % (8 * width) != 0) {
        PyErr_SetString(PyExc_ValueError, "rank: int64 entries in rows of the given width, and rows >= 0");
        PyBuffer_Release(&a);
        return nullptr;
    }
    const i64* entry = static_cast<const i64*>(a.buf);
    const Py_ssize_t n_cols = a.len / 8 / width;
    bool ok = true;
    for (Py_ssize_t i = 0; i < n_cols * width && ok; ++i) ok = entry[i] >= 0 && entry[i] < rows;
    if (!ok) {
        PyErr_SetString(PyExc_ValueError, "rank: an entry is not a row");
    } else {
        i64 count = 0;
        bool no_memory = false;
        Py_BEGIN_ALLOW_THREADS;
        try {
        // pivot[r]: the reduced column whose largest row is r (empty: none yet)
        std::vector<std::vector<i64>> pivot(static_cast<std::size_t>(rows));
        std::vector<i64> col, sum, once;
        for (Py_ssize_t c = 0; c < n_cols; ++c) {
            col.assign(entry + c * width, entry + (c + 1) * width);
            std::sort(col.begin(), col.end());
            // a row named twice cancels (the Python reference XORs its bits the same way)
            once.clear();
            for (std::size_t i = 0; i < col.size();) {
                std::size_t j = i;
                while (j < col.size() && col[j] == col[i]) ++j;
                if ((j - i) % 2 == 1) once.push_back(col[i]);
                i = j;
            }
            col.swap(once);
            while (!col.empty()) {
                std::vector<i64>& p = pivot[static_cast<std::size_t>(col.back())];
                if (p.empty()) {
                    p.swap(col);
                    ++count;
                    break;
                }
                sum.clear();
                std::set_symmetric_difference(col.begin(), col.end(), p.begin(), p.end(), std::back_inserter(sum));
                col.swap(sum);
            }
        }
        } catch (const std::bad_alloc&) {  // a MemoryError in Python, never an abort of the process
            no_memory = true;
        }
        Py_END_ALLOW_THREADS;
        if (no_memory) {
            PyErr_NoMemory();
        } else {
            result = PyLong_FromLongLong(count);
        }
    }
    PyBuffer_Release(&a);
    return result;
}

PyMethodDef methods[] = {
    {"rank", rank, METH_VARARGS,
     "rank(entries, rows, width) -> int: the rank over GF(2) of the matrix whose columns are the rows of "
     "``entries`` (int64 bytes, ``width`` row numbers each, every one below ``rows``; a row named twice "
     "in one column cancels)."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {PyModuleDef_HEAD_INIT, "_gf2", "Rank of a boundary matrix over GF(2).", -1, methods};

}  // namespace

PyMODINIT_FUNC PyInit__gf2() { return PyModule_Create(&module); }
