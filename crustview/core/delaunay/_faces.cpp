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
// increasing order, as numpy's stable argsort of the instances gives them
// (grouped by lowest vertex first, then sorted per group: see instances()).
//
// From 2**20 records the instances and the sort run on two threads with the
// GIL released, in a way that gives the one-thread order exactly.
//
// No third-party code: builds wherever a C++17 compiler is.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <memory>
#include <atomic>
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

//: Second threads started so far (``second_threads()``: the tests see that two threads ran).
std::atomic<long long> g_second_threads{0};

template <typename Body>
void in_parts(int parts, Body&& body) {  // body(part) on each part, the second on its own thread
    if (parts == 1) {
        body(0);
        return;
    }
    std::thread other([&] { body(1); });
    g_second_threads.fetch_add(1, std::memory_order_relaxed);
    body(0);
    other.join();
}

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
    for (int shift = 0; shift < 64; shift += 16) {
        in_parts(parts, [&](int part) {
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
        in_parts(parts, [&](int part) {
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

// The face masks of a w-vertex simplex with fw vertices, in lexicographic order of
// the chosen positions (the order of itertools.combinations).
std::vector<unsigned> face_masks(int w, int fw) {
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
    return combos;
}

// Every face instance of the sample faces, grouped by the face's lowest vertex
// (a counting sort: bucket v holds its instances in increasing simplex order),
// then each bucket sorted by (key, simplex), which is the stable order by key.
// A bucket is a few thousand instances (the simplices around one sample), so
// its sort stays in cache, where a radix sort of all instances scatters every
// pass over the whole array.  Two threads: each fills its half of the
// simplices into its own part of each bucket (the first half's part first),
// then sorts and writes out the buckets of half of the instances; the arrays
// are the one-thread arrays.
struct Grouped {
    std::unique_ptr<Instance[]> inst;  // sorted
    std::int64_t total = 0;
    int parts = 1;
    std::int64_t first_v[3] = {0, 0, 0};   // each part's buckets [first_v[p], first_v[p + 1])
    std::int64_t first_i[3] = {0, 0, 0};   // and instances
    std::int64_t distinct[2] = {0, 0};     // distinct faces in each part
};

Grouped group_instances(const std::int32_t* simp, std::int64_t t, int w, int fw, std::int64_t n, long long threaded) {
    const std::vector<unsigned> combos = face_masks(w, fw);
    Grouped g;
    g.parts = t >= 2 && static_cast<long long>(t * combos.size()) >= threaded ? 2 : 1;
    const int parts = g.parts;
    const std::int64_t split[3] = {0, parts == 2 ? t / 2 : t, t};
    std::vector<int> low_pos(combos.size()), high_pos(combos.size());
    for (std::size_t q = 0; q < combos.size(); ++q) {  // in the sorted row: the face's lowest and highest vertex
        low_pos[q] = __builtin_ctz(combos[q]);
        high_pos[q] = 31 - __builtin_clz(combos[q]);
    }
    const auto sorted_row = [&](std::int64_t i, std::int64_t* row) {
        for (int c = 0; c < w; ++c) row[c] = simp[i * w + c];
        std::sort(row, row + w);
    };
    const std::size_t nb = static_cast<std::size_t>(n);
    std::vector<std::int64_t> count[2] = {std::vector<std::int64_t>(nb, 0), std::vector<std::int64_t>(parts == 2 ? nb : 0, 0)};
    in_parts(parts, [&](int part) {
        std::vector<std::int64_t>& c = count[part];
        std::int64_t row[8];
        for (std::int64_t i = split[part]; i < split[part + 1]; ++i) {
            sorted_row(i, row);
            for (std::size_t q = 0; q < combos.size(); ++q) {
                if (row[high_pos[q]] < n) ++c[static_cast<std::size_t>(row[low_pos[q]])];
            }
        }
    });
    std::vector<std::int64_t> bucket(nb + 1);  // bucket v: part 0's instances, then part 1's
    std::int64_t at = 0;
    for (std::size_t v = 0; v < nb; ++v) {
        bucket[v] = at;
        for (int part = 0; part < parts; ++part) {
            const std::int64_t here = count[part][v];
            count[part][v] = at;
            at += here;
        }
    }
    bucket[nb] = at;
    g.total = at;
    g.inst.reset(new Instance[static_cast<std::size_t>(at > 0 ? at : 1)]);  // not zeroed: every slot is written
    Instance* out = g.inst.get();
    in_parts(parts, [&](int part) {
        std::vector<std::int64_t>& c = count[part];
        std::int64_t row[8];
        for (std::int64_t i = split[part]; i < split[part + 1]; ++i) {
            sorted_row(i, row);
            for (std::size_t q = 0; q < combos.size(); ++q) {
                if (row[high_pos[q]] >= n) continue;
                std::int64_t key = 0;
                for (int k = 0; k < w; ++k) {
                    if ((combos[q] >> k) & 1u) key = key * n + row[k];
                }
                out[c[static_cast<std::size_t>(row[low_pos[q]])]++] = {key, static_cast<std::int32_t>(i)};
            }
        }
    });
    // the parts' buckets: split where half of the instances are done
    std::size_t mid = 0;
    while (mid < nb && bucket[mid] < at / 2) ++mid;
    g.first_v[1] = parts == 2 ? static_cast<std::int64_t>(mid) : n;
    g.first_v[2] = n;
    for (int p = 0; p < 3; ++p) g.first_i[p] = bucket[static_cast<std::size_t>(g.first_v[p])];
    // within a bucket the key's first digit is the bucket: (rest of the key, simplex) packed in one
    // word sorts as (key, simplex) when the rest fits 32 bits
    std::int64_t lead = 1;
    bool packed = true;
    for (int c = 1; c < fw && packed; ++c) {
        packed = lead <= (std::int64_t{1} << 32) / n;
        lead *= n;
    }
    packed = packed && lead <= (std::int64_t{1} << 32);
    in_parts(parts, [&](int part) {
        std::vector<std::uint64_t> words, spare;
        std::int64_t distinct = 0;
        for (std::int64_t v = g.first_v[part]; v < g.first_v[part + 1]; ++v) {
            Instance* lo = out + bucket[static_cast<std::size_t>(v)];
            Instance* hi = out + bucket[static_cast<std::size_t>(v) + 1];
            const std::size_t size = static_cast<std::size_t>(hi - lo);
            if (packed) {
                const std::int64_t base = v * lead;
                words.resize(size);
                for (std::size_t i = 0; i < size; ++i) {
                    words[i] = (static_cast<std::uint64_t>(lo[i].key - base) << 32) |
                               static_cast<std::uint32_t>(lo[i].simplex);
                }
                // the bucket holds its instances in increasing simplex order, so a stable sort by the key's
                // rest (the word's upper half) is the sort of the words: LSD radix, 8 bits a pass, as
                // many passes as the bucket's largest rest needs (std::sort took most of the listing)
                std::uint64_t top = 0;
                for (std::size_t i = 0; i < size; ++i) top = std::max(top, words[i] >> 32);
                spare.resize(size);
                for (int shift = 32; shift < 64 && (top >> (shift - 32)) != 0; shift += 8) {
                    std::size_t start[257] = {0};
                    for (std::size_t i = 0; i < size; ++i) ++start[((words[i] >> shift) & 255u) + 1];
                    for (int b = 0; b < 256; ++b) start[b + 1] += start[b];
                    for (std::size_t i = 0; i < size; ++i) spare[start[(words[i] >> shift) & 255u]++] = words[i];
                    words.swap(spare);
                }
                for (std::size_t i = 0; i < size; ++i) {
                    lo[i] = {base + static_cast<std::int64_t>(words[i] >> 32),
                             static_cast<std::int32_t>(words[i] & 0xFFFFFFFFu)};
                }
            } else {
                std::sort(lo, hi, [](const Instance& a, const Instance& b) {
                    return a.key != b.key ? a.key < b.key : a.simplex < b.simplex;
                });
            }
            for (std::size_t i = 0; i < size; ++i) {
                if (i == 0 || lo[i].key != lo[i - 1].key) ++distinct;
            }
        }
        g.distinct[part] = distinct;
    });
    return g;
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
    Grouped g;
    const auto* simp = static_cast<const std::int32_t*>(simp_buf.buf);
    bool negative = false, no_memory = false;
    Py_BEGIN_ALLOW_THREADS
    for (std::int64_t i = 0; i < t * w && !negative; ++i) negative = simp[i] < 0;  // a vertex id is a bucket
    if (!negative) {
        try {
            g = group_instances(simp, t, w, fw, n, threaded);
        } catch (const std::exception&) {  // bad_alloc, or a thread that could not start
            no_memory = true;
        }
    }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&simp_buf);
    if (negative) {
        PyErr_SetString(PyExc_ValueError, "a simplex names a negative vertex");
        return nullptr;
    }
    if (no_memory) return PyErr_NoMemory();
    const Py_ssize_t total = static_cast<Py_ssize_t>(g.total);
    const Py_ssize_t distinct = static_cast<Py_ssize_t>(g.distinct[0] + g.distinct[1]);
    PyObject* out[3];
    if (!face_outputs(distinct * fw * 8, (distinct + 1) * 8, total * 4, out)) return nullptr;
    auto* f = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[0]));
    auto* p = reinterpret_cast<std::int64_t*>(PyByteArray_AS_STRING(out[1]));
    auto* o = reinterpret_cast<std::int32_t*>(PyByteArray_AS_STRING(out[2]));
    const Instance* recs = g.inst.get();
    Py_BEGIN_ALLOW_THREADS
    in_parts(g.parts, [&](int part) {  // part 1's faces follow part 0's
        Py_ssize_t at = part == 0 ? 0 : static_cast<Py_ssize_t>(g.distinct[0]);
        for (std::int64_t i = g.first_i[part]; i < g.first_i[part + 1]; ++i) {
            const Instance& rec = recs[i];
            o[i] = rec.simplex;
            if (i > g.first_i[part] && rec.key == recs[i - 1].key) continue;
            std::int64_t key = rec.key;
            for (int c = fw - 1; c >= 0; --c) {
                f[at * fw + c] = key % n;
                key /= n;
            }
            p[at++] = i;
        }
    });
    p[distinct] = total;
    Py_END_ALLOW_THREADS
    return Py_BuildValue("NNNn", out[0], out[1], out[2], distinct);
}

PyObject* second_threads(PyObject*, PyObject*) {
    return PyLong_FromLongLong(g_second_threads.load(std::memory_order_relaxed));
}

PyMethodDef methods[] = {
    {"second_threads", second_threads, METH_NOARGS,
     "second_threads() -> int: the second threads the sorts and face instances have started so far."},
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
