// The Delaunay d-faces among the samples and the simplices around each
// (Algorithm 2's input), as crustview.core.delaunay.faces computes them in numpy, in
// one pass and one radix sort.  Integer work only, so the arrays are the same
// as numpy's, not just close.
//
// facets(): codimension 1, from the neighbour table.
// Input: the simplices (t x w int32 vertex numbers, w = d + 2), their
// neighbour table (t x w int32; neighbour j across the facet opposite vertex j,
// -1 across the hull) and the number of samples n (vertices >= n are bounding
// points; facets with one are left out).  Each facet is listed once, by the
// lower-numbered of its two simplices (or by its only one across the hull),
// keyed by its sorted vertices read as digits in base n (the caller checks
// that n^(w-1) < 2^62), and the records are sorted by key.
//
// Output: (faces, ptr, owners, count) with faces the sorted vertex rows as
// int64 (count x (w - 1)), ptr the int64 CSR pointers (count + 1) and owners
// the int32 simplices of each facet (one or two, in increasing order), all as
// bytearrays numpy wraps without a copy.  Keys are distinct, so the order is
// the one numpy's stable sort gives.
//
// faces(): any codimension, from the simplices alone.  Every (d+1)-subset of
// every simplex whose vertices are samples is one record (key as above, the
// simplex), sorted stably by key, so each face's simplices come in
// increasing order, as numpy's stable argsort of the instances gives them.
//
// From 2**20 records the instances and the sort run on two threads with the
// GIL released, in a way that gives the one-thread order exactly.
//
// No third-party code: builds wherever a C++17 compiler is.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace {

struct Record {
    std::int64_t key;
    std::int32_t first;
    std::int32_t second;  // -1: a hull facet
};

#pragma pack(push, 4)
struct Instance {  // 12 bytes: there are (w choose d+1) per simplex
    std::int64_t key;
    std::int32_t simplex;
};
#pragma pack(pop)

// Stable LSD radix sort of the records by key, 16 bits per pass, skipping
// passes whose digit is the same in every record.
//: Records from which the sort and the face instances use a second thread (the functions' last,
//: optional argument; the tests lower it to check that two threads give the one-thread order).
constexpr long long kThreadedRecords = 1 << 20;

// Stable LSD radix sort on 16-bit digits of the key.  Large inputs use two
// threads: each counts and scatters its own contiguous half, and a bucket's
// records from the first half go before those from the second, so the order
// is the one-thread order exactly.
template <typename Rec>
void radix_sort(std::vector<Rec>& records, long long threaded) {
    const std::size_t size = records.size();
    const int parts = size >= 2 && static_cast<long long>(size) >= threaded ? 2 : 1;
    const std::size_t bounds[3] = {0, parts == 2 ? size / 2 : size, size};
    std::vector<Rec> buffer(size);
    std::vector<std::size_t> count[2] = {std::vector<std::size_t>(1 << 16), std::vector<std::size_t>(1 << 16)};
    const auto in_parts = [&](auto&& body) {  // body(part) on each half, the second on its own thread
        if (parts == 1) {
            body(0);
            return;
        }
        std::thread other([&] { body(1); });
        body(0);
        other.join();
    };
    for (int shift = 0; shift < 64; shift += 16) {
        in_parts([&](int part) {
            std::vector<std::size_t>& c = count[part];
            std::fill(c.begin(), c.end(), 0);
            for (std::size_t i = bounds[part]; i < bounds[part + 1]; ++i) {
                ++c[static_cast<std::size_t>((records[i].key >> shift) & 0xFFFF)];
            }
        });
        bool one_bucket = false;
        for (std::size_t b = 0; b < count[0].size() && !one_bucket; ++b) {
            one_bucket = count[0][b] + (parts == 2 ? count[1][b] : 0) == size;
        }
        if (one_bucket) {
            continue;  // one bucket holds everything: this digit does not order anything
        }
        std::size_t at = 0;
        for (std::size_t b = 0; b < count[0].size(); ++b) {
            for (int part = 0; part < parts; ++part) {
                const std::size_t here = count[part][b];
                count[part][b] = at;
                at += here;
            }
        }
        in_parts([&](int part) {
            std::vector<std::size_t>& c = count[part];
            for (std::size_t i = bounds[part]; i < bounds[part + 1]; ++i) {
                buffer[c[static_cast<std::size_t>((records[i].key >> shift) & 0xFFFF)]++] = records[i];
            }
        });
        records.swap(buffer);
    }
}

std::vector<Record> collect(const std::int32_t* simp, const std::int32_t* nbrs, std::int64_t t, int w,
                            std::int64_t n) {
    std::vector<Record> records;
    records.reserve(static_cast<std::size_t>(t) * static_cast<std::size_t>(w) / 2 + 16);
    std::int64_t facet[8];
    for (std::int64_t i = 0; i < t; ++i) {
        const std::int32_t* row = simp + i * w;
        for (int j = 0; j < w; ++j) {
            const std::int32_t other = nbrs[i * w + j];
            if (other >= 0 && other < i) continue;  // listed by the lower-numbered simplex
            int at = 0;
            for (int c = 0; c < w; ++c) {
                if (c != j) facet[at++] = row[c];
            }
            std::sort(facet, facet + at);
            if (facet[at - 1] >= n) continue;  // a bounding point
            std::int64_t key = facet[0];
            for (int c = 1; c < at; ++c) key = key * n + facet[c];
            records.push_back({key, static_cast<std::int32_t>(i), other});
        }
    }
    return records;
}

// The three result bytearrays (faces, pointers, owners) of the given byte
// sizes; false (a Python error set, nothing leaked) if one cannot be made.
bool face_outputs(Py_ssize_t face_bytes, Py_ssize_t ptr_bytes, Py_ssize_t owner_bytes, PyObject* out[3]) {
    out[0] = PyByteArray_FromStringAndSize(nullptr, face_bytes);
    out[1] = PyByteArray_FromStringAndSize(nullptr, ptr_bytes);
    out[2] = PyByteArray_FromStringAndSize(nullptr, owner_bytes);
    if (out[0] != nullptr && out[1] != nullptr && out[2] != nullptr) return true;
    for (int i = 0; i < 3; ++i) Py_XDECREF(out[i]);
    return false;
}

PyObject* facets(PyObject* /*self*/, PyObject* args) {
    Py_buffer simp_buf, nbr_buf;
    int w = 0;
    long long n = 0, threaded = kThreadedRecords;
    if (!PyArg_ParseTuple(args, "y*y*iL|L", &simp_buf, &nbr_buf, &w, &n, &threaded)) {
        return nullptr;
    }
    const Py_ssize_t row_bytes = static_cast<Py_ssize_t>(w) * 4;
    if (w < 2 || w > 8 || simp_buf.len % row_bytes != 0 || nbr_buf.len != simp_buf.len || n < 1) {
        PyBuffer_Release(&simp_buf);
        PyBuffer_Release(&nbr_buf);
        PyErr_SetString(PyExc_ValueError,
                        "expected int32 simplices and neighbours of the same shape (t x w, 2 <= w <= 8) and n >= 1");
        return nullptr;
    }
    const std::int64_t t = simp_buf.len / row_bytes;
    const auto* simp = static_cast<const std::int32_t*>(simp_buf.buf);
    const auto* nbrs = static_cast<const std::int32_t*>(nbr_buf.buf);
    std::vector<Record> records;
    Py_BEGIN_ALLOW_THREADS
    records = collect(simp, nbrs, t, w, n);
    radix_sort(records, threaded);
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&simp_buf);
    PyBuffer_Release(&nbr_buf);

    const Py_ssize_t count = static_cast<Py_ssize_t>(records.size());
    const int fw = w - 1;
    Py_ssize_t n_owners = 0;
    for (const Record& rec : records) n_owners += rec.second >= 0 ? 2 : 1;
    PyObject* out[3];
    if (!face_outputs(count * fw * 8, (count + 1) * 8, n_owners * 4, out)) return nullptr;
    auto* f = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[0]));
    auto* p = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[1]));
    auto* o = reinterpret_cast<std::int32_t*>(PyByteArray_AS_STRING(out[2]));
    Py_BEGIN_ALLOW_THREADS
    std::int64_t at = 0;
    for (Py_ssize_t i = 0; i < count; ++i) {
        std::int64_t key = records[static_cast<std::size_t>(i)].key;
        for (int c = fw - 1; c >= 0; --c) {
            f[i * fw + c] = key % n;
            key /= n;
        }
        p[i] = at;
        o[at++] = records[static_cast<std::size_t>(i)].first;
        if (records[static_cast<std::size_t>(i)].second >= 0) o[at++] = records[static_cast<std::size_t>(i)].second;
    }
    p[count] = at;
    Py_END_ALLOW_THREADS
    return Py_BuildValue("NNNn", out[0], out[1], out[2], count);
}

std::vector<Instance> instances(const std::int32_t* simp, std::int64_t t, int w, int fw, std::int64_t n,
                                long long threaded) {
    // the (fw)-subsets of positions 0..w-1 in lexicographic order, as bit masks
    std::vector<unsigned> combos;
    for (unsigned mask = 0; mask < (1u << w); ++mask) {
        if (__builtin_popcount(mask) == fw) combos.push_back(mask);
    }
    std::sort(combos.begin(), combos.end(), [w](unsigned a, unsigned b) {
        for (int c = 0; c < w; ++c) {  // lexicographic on the chosen positions
            const bool ia = (a >> c) & 1u, ib = (b >> c) & 1u;
            if (ia != ib) return ia;
        }
        return false;
    });
    // simplices [lo, hi) in order; a large triangulation's second half on another thread, appended after
    const auto range = [&](std::int64_t lo, std::int64_t hi, std::vector<Instance>& out) {
        out.reserve(static_cast<std::size_t>(hi - lo) * combos.size());
        std::int64_t row[8];
        for (std::int64_t i = lo; i < hi; ++i) {
            for (int c = 0; c < w; ++c) row[c] = simp[i * w + c];
            std::sort(row, row + w);
            for (unsigned mask : combos) {
                std::int64_t key = 0, last = 0;
                for (int c = 0; c < w; ++c) {
                    if ((mask >> c) & 1u) {
                        key = key * n + row[c];
                        last = row[c];
                    }
                }
                if (last < n) out.push_back({key, static_cast<std::int32_t>(i)});
            }
        }
    };
    std::vector<Instance> out;
    if (t < 2 || static_cast<long long>(t * combos.size()) < threaded) {
        range(0, t, out);
        return out;
    }
    std::vector<Instance> second;
    std::thread other([&] { range(t / 2, t, second); });
    range(0, t / 2, out);
    other.join();
    out.insert(out.end(), second.begin(), second.end());
    return out;
}

PyObject* faces(PyObject* /*self*/, PyObject* args) {
    Py_buffer simp_buf;
    int w = 0, fw = 0;
    long long n = 0, threaded = kThreadedRecords;
    if (!PyArg_ParseTuple(args, "y*iiL|L", &simp_buf, &w, &fw, &n, &threaded)) {
        return nullptr;
    }
    if (w < 2 || w > 8 || fw < 1 || fw > w || simp_buf.len % (static_cast<Py_ssize_t>(w) * 4) != 0 || n < 1) {
        PyBuffer_Release(&simp_buf);
        PyErr_SetString(PyExc_ValueError,
                        "expected int32 simplices (t x w, 2 <= w <= 8), a face width 1 <= fw <= w and n >= 1");
        return nullptr;
    }
    const std::int64_t t = simp_buf.len / (static_cast<Py_ssize_t>(w) * 4);
    std::vector<Instance> recs;
    Py_ssize_t distinct = 0;
    Py_BEGIN_ALLOW_THREADS
    recs = instances(static_cast<const std::int32_t*>(simp_buf.buf), t, w, fw, n, threaded);
    radix_sort(recs, threaded);
    for (std::size_t i = 0; i < recs.size(); ++i) {
        if (i == 0 || recs[i].key != recs[i - 1].key) ++distinct;
    }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&simp_buf);
    const Py_ssize_t total = static_cast<Py_ssize_t>(recs.size());
    PyObject* out[3];
    if (!face_outputs(distinct * fw * 8, (distinct + 1) * 8, total * 4, out)) return nullptr;
    auto* f = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[0]));
    auto* p = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[1]));
    auto* o = reinterpret_cast<std::int32_t*>(PyByteArray_AS_STRING(out[2]));
    Py_BEGIN_ALLOW_THREADS
    Py_ssize_t at = 0;
    for (Py_ssize_t i = 0; i < total; ++i) {
        const Instance& rec = recs[static_cast<std::size_t>(i)];
        o[i] = rec.simplex;
        if (i > 0 && rec.key == recs[static_cast<std::size_t>(i - 1)].key) continue;
        std::int64_t key = rec.key;
        for (int c = fw - 1; c >= 0; --c) {
            f[at * fw + c] = key % n;
            key /= n;
        }
        p[at++] = i;
    }
    p[distinct] = total;
    Py_END_ALLOW_THREADS
    return Py_BuildValue("NNNn", out[0], out[1], out[2], distinct);
}

PyMethodDef methods[] = {
    {"facets", facets, METH_VARARGS,
     "facets(simplices, neighbours, w, n[, threaded]) -> (faces, ptr, owners, count)\n\n"
     "The facets of the int32 simplices (t x w) whose vertices are all < n,\n"
     "from the int32 neighbour table: int64 sorted rows (count x (w - 1)) in\n"
     "lexicographic order, int64 CSR pointers and the int32 simplices of each\n"
     "facet, as bytearrays.  From `threaded` records (default 2**20) the sort\n"
     "runs on two threads (the same order)."},
    {"faces", faces, METH_VARARGS,
     "faces(simplices, w, fw, n[, threaded]) -> (faces, ptr, owners, count)\n\n"
     "The distinct fw-vertex faces of the int32 simplices (t x w) whose vertices\n"
     "are all < n: int64 sorted rows in lexicographic order, int64 CSR pointers\n"
     "and the int32 simplices containing each face in increasing order.  From\n"
     "`threaded` records (default 2**20) two threads (the same arrays)."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_faces", "Faces of a triangulation and the simplices around each.", -1, methods,
    nullptr, nullptr, nullptr, nullptr,
};

}  // namespace

PyMODINIT_FUNC PyInit__faces(void) { return PyModule_Create(&module); }
