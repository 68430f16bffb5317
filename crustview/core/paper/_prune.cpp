// Algorithm 3's loop (core/paper/extraction.py, extract) in C++: the same
// steps in the same order, from the same tables.
//
// The Python loop is the reference; this is its transcription, decision for
// decision: the prune queue (a FIFO with a "queued" flag per facet), the heap
// of non-manifold facets (smallest (-angle, facet) first, stale entries
// re-queued with their true angle), the pair choice by the simulated prune
// cascade (capped at `limit` simplices), then the flattest pair, then the
// smallest ids.  Angles are computed as the Python code computes them: the
// dot product summed from the first coordinate on (no fused multiply-add:
// -ffp-contract=off in setup.py), clamped to [-1, 1], then libm's acos,
// which is what math.acos calls; maxima keep the first of equal values.
// The caller passes only finite unit vectors, so no NaN reaches the heap.
//
// The mutable tables (alive, count, removed_at, exposer, vcount) are the
// caller's numpy arrays, updated in place; the steps come back as flat
// arrays (bytes).  `cancel.is_set()` is asked after every step whose count
// is a multiple of 256 and `progress(fraction)` called after every 64th
// resolve step, as in the Python loop.  No third-party code.

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace {

using i64 = std::int64_t;
constexpr double HALF_PI = M_PI / 2;

struct Tables {
    const i64* simplices;  // (c, dp1), rows sorted
    const i64* facet_of;   // (c, dp1)
    const i64* ptr;        // (g + 1)
    const i64* inc;        // simplices by facet
    const double* u;       // (c, dp1, k)
    i64 c, g;
    int dp1, k;
    bool prune_boundary;
    unsigned char* alive;  // (c)
    i64* count;            // (g)
    i64* removed_at;       // (c)
    i64* exposer;          // (g)
    i64* vcount;           // (n)
    i64 lost = -1;
};

struct Steps {
    std::vector<unsigned char> rule;  // 0 prune, 1 resolve
    std::vector<i64> facet, keep_a, keep_b, cause, size, rptr{0}, removed;
    std::vector<double> angle;
};

void alive_at(const Tables& t, i64 g, std::vector<i64>& out) {
    out.clear();
    for (i64 p = t.ptr[g]; p < t.ptr[g + 1]; ++p) {
        const i64 s = t.inc[p];
        if (t.alive[s]) out.push_back(s);
    }
}

const double* vec_of(const Tables& t, i64 s, i64 g) {
    int a = 0;
    while (t.facet_of[s * t.dp1 + a] != g) ++a;
    return t.u + (s * t.dp1 + a) * t.k;
}

// The pairwise angles (m x m, row-major) at facet g, as _Extractor.pair_angles.
void pair_angles(const Tables& t, i64 g, const std::vector<i64>& simp, std::vector<double>& ang) {
    const std::size_t m = simp.size();
    ang.assign(m * m, 0.0);
    std::vector<const double*> vec(m);
    for (std::size_t i = 0; i < m; ++i) vec[i] = vec_of(t, simp[i], g);
    for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = i + 1; j < m; ++j) {
            double dot = 0.0;
            for (int q = 0; q < t.k; ++q) dot += vec[i][q] * vec[j][q];
            const double clamped = dot < -1.0 ? -1.0 : dot > 1.0 ? 1.0 : dot;
            ang[i * m + j] = ang[j * m + i] = std::acos(clamped);
        }
    }
}

// _max_pair: the largest entry above the diagonal, the first of equal ones.
double max_pair(const std::vector<double>& ang, std::size_t m) {
    double best = 0.0;
    for (std::size_t i = 0; i + 1 < m; ++i) {
        double row = ang[i * m + i + 1];
        for (std::size_t j = i + 2; j < m; ++j) {
            if (ang[i * m + j] > row) row = ang[i * m + j];
        }
        if (i == 0 || row > best) best = row;
    }
    return best;
}

// _Extractor.remove: touched facets come back sorted and unique.
void remove(Tables& t, const std::vector<i64>& simp, i64 step, std::vector<i64>& touched) {
    touched.clear();
    for (const i64 s : simp) {
        if (!t.alive[s]) continue;
        t.alive[s] = 0;
        t.removed_at[s] = step;
        for (int a = 0; a < t.dp1; ++a) {
            const i64 g = t.facet_of[s * t.dp1 + a];
            t.count[g] -= 1;
            touched.push_back(g);
        }
        for (int a = 0; a < t.dp1; ++a) {
            const i64 v = t.simplices[s * t.dp1 + a];
            t.vcount[v] -= 1;
            if (t.vcount[v] == 0 && t.lost < 0) t.lost = v;
        }
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (const i64 g : touched) t.exposer[g] = step;
}

bool contains(const std::vector<i64>& v, i64 x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// _cascade_loss
i64 cascade_loss(const Tables& t, const std::vector<i64>& drop, i64 limit) {
    std::vector<i64> gone(drop), opened, simp, here;
    std::vector<double> ang;
    std::deque<i64> queue;
    for (const i64 s : drop) {
        for (int a = 0; a < t.dp1; ++a) queue.push_back(t.facet_of[s * t.dp1 + a]);
    }
    while (!queue.empty() && static_cast<i64>(gone.size() + opened.size()) < limit) {
        const i64 h = queue.front();
        queue.pop_front();
        alive_at(t, h, here);
        simp.clear();
        for (const i64 s : here) {
            if (!contains(gone, s)) simp.push_back(s);
        }
        if (simp.size() == 1 && !t.prune_boundary) {
            if (t.count[h] >= 2 && !contains(opened, h)) opened.push_back(h);
            continue;
        }
        if (simp.empty()) continue;
        if (simp.size() > 1) {
            pair_angles(t, h, simp, ang);
            if (max_pair(ang, simp.size()) >= HALF_PI) continue;
        }
        for (const i64 s : simp) {
            gone.push_back(s);
            for (int a = 0; a < t.dp1; ++a) {
                const i64 f = t.facet_of[s * t.dp1 + a];
                if (f != h) queue.push_back(f);
            }
        }
    }
    return static_cast<i64>(gone.size() + opened.size());
}

// _choose_pair: false when no pair meets at phi > pi/2.
bool choose_pair(const Tables& t, const std::vector<i64>& simp, const std::vector<double>& ang, i64 limit,
                 std::size_t& bi, std::size_t& bj) {
    const std::size_t m = simp.size();
    bool found = false;
    i64 best_loss = 0, best_a = 0, best_b = 0;
    double best_neg = 0.0;
    std::vector<i64> drop;
    for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = i + 1; j < m; ++j) {
            const double phi = ang[i * m + j];
            if (!(phi > HALF_PI)) continue;
            drop.clear();
            for (std::size_t q = 0; q < m; ++q) {
                if (q != i && q != j) drop.push_back(simp[q]);
            }
            const i64 loss = cascade_loss(t, drop, limit);
            const double neg = -phi;
            bool better = !found;
            if (found) {  // (loss, -phi, simp[i], simp[j]) < best, lexicographically
                if (loss != best_loss) better = loss < best_loss;
                else if (neg != best_neg) better = neg < best_neg;
                else if (simp[i] != best_a) better = simp[i] < best_a;
                else better = simp[j] < best_b;
            }
            if (better) {
                found = true;
                best_loss = loss, best_neg = neg, best_a = simp[i], best_b = simp[j];
                bi = i, bj = j;
            }
        }
    }
    return found;
}

void record(Steps& out, unsigned char rule, i64 g, i64 ka, i64 kb, const std::vector<i64>& removed, double angle,
            i64 cause, i64 size) {
    out.rule.push_back(rule);
    out.facet.push_back(g);
    out.keep_a.push_back(ka);
    out.keep_b.push_back(kb);
    out.angle.push_back(angle);
    out.cause.push_back(cause);
    out.size.push_back(size);
    out.removed.insert(out.removed.end(), removed.begin(), removed.end());
    out.rptr.push_back(static_cast<i64>(out.removed.size()));
}

// 0: go on, 1: cancelled, -1: a Python error is set.
int ask_cancel(PyObject* cancel, std::size_t n_steps) {
    if (cancel == Py_None || n_steps % 256 != 0) return 0;
    PyObject* r = PyObject_CallMethod(cancel, "is_set", nullptr);
    if (r == nullptr) return -1;
    const int truth = PyObject_IsTrue(r);
    Py_DECREF(r);
    return truth < 0 ? -1 : truth;
}

using Entry = std::pair<double, i64>;
using Heap = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;

// The loop of extract(); returns 0 when it ended, 1 when cancelled, -1 on a Python error.
int run(Tables& t, std::deque<i64>& prune, Heap& heap, bool stop_when_lost, i64 limit, PyObject* cancel,
        PyObject* progress, Steps& out) {
    std::vector<unsigned char> queued(static_cast<std::size_t>(t.g), 0);
    for (const i64 g : prune) queued[g] = 1;
    std::vector<i64> simp, touched, drop;
    std::vector<double> ang;
    while (true) {
        while (!prune.empty()) {
            const i64 g = prune.front();
            prune.pop_front();
            queued[g] = 0;
            alive_at(t, g, simp);
            if (simp.empty()) continue;
            double best = std::numeric_limits<double>::quiet_NaN();
            if (simp.size() == 1) {
                if (!t.prune_boundary) continue;
            } else {
                pair_angles(t, g, simp, ang);
                best = max_pair(ang, simp.size());
                if (!(best < HALF_PI)) continue;
            }
            const i64 idx = static_cast<i64>(out.rule.size());
            const i64 cause = t.exposer[g];
            remove(t, simp, idx, touched);
            record(out, 0, g, -1, -1, simp, best, cause, static_cast<i64>(simp.size()));
            for (const i64 h : touched) {
                if (h != g && t.count[h] > 0 && !queued[h]) {
                    prune.push_back(h);
                    queued[h] = 1;
                }
            }
            const int c = ask_cancel(cancel, out.rule.size());
            if (c != 0) return c;
            if (stop_when_lost && t.lost >= 0) break;
        }
        if (stop_when_lost && t.lost >= 0) break;
        bool chosen = false;
        i64 g = -1;
        while (!heap.empty()) {
            const Entry top = heap.top();
            heap.pop();
            g = top.second;
            if (t.count[g] <= 2) continue;
            alive_at(t, g, simp);
            pair_angles(t, g, simp, ang);
            const double best = max_pair(ang, simp.size());
            if (-top.first > best + 1e-12) {
                heap.push({-best, g});
                continue;
            }
            chosen = true;
            break;
        }
        if (!chosen) break;
        std::size_t i = 0, j = 0;
        if (!choose_pair(t, simp, ang, limit, i, j)) {
            prune.push_back(g);
            queued[g] = 1;
            continue;
        }
        const std::size_t m = simp.size();
        drop.clear();
        for (std::size_t q = 0; q < m; ++q) {
            if (q != i && q != j) drop.push_back(simp[q]);
        }
        const i64 idx = static_cast<i64>(out.rule.size());
        remove(t, drop, idx, touched);
        record(out, 1, g, simp[i], simp[j], drop, ang[i * m + j], -1, static_cast<i64>(m));
        for (const i64 h : touched) {
            if (t.count[h] > 0 && !queued[h]) {
                prune.push_back(h);
                queued[h] = 1;
            }
            if (t.count[h] > 2) heap.push({-M_PI, h});
        }
        const int c = ask_cancel(cancel, out.rule.size());
        if (c != 0) return c;
        if (stop_when_lost && t.lost >= 0) break;
        if (progress != Py_None && idx % 64 == 0) {
            const double frac = 1.0 - static_cast<double>(heap.size()) / static_cast<double>(std::max<i64>(t.g, 1));
            PyObject* r = PyObject_CallFunction(progress, "d", frac);
            if (r == nullptr) return -1;
            Py_DECREF(r);
        }
    }
    return 0;
}

template <typename T>
PyObject* as_bytes(const std::vector<T>& v) {
    return PyBytes_FromStringAndSize(reinterpret_cast<const char*>(v.data()),
                                     static_cast<Py_ssize_t>(v.size() * sizeof(T)));
}

bool sized(const Py_buffer& b, Py_ssize_t items, Py_ssize_t item) { return b.len == items * item; }

PyObject* extract_loop(PyObject*, PyObject* args) {
    Py_buffer simp, fof, ptr, inc, u, first, alive, count, removed_at, exposer, vcount;
    int dp1, k, prune_boundary, stop_when_lost;
    long long limit;
    PyObject *cancel, *progress;
    if (!PyArg_ParseTuple(args, "y*y*y*y*y*y*w*w*w*w*w*iippLOO", &simp, &fof, &ptr, &inc, &u, &first, &alive,
                          &count, &removed_at, &exposer, &vcount, &dp1, &k, &prune_boundary, &stop_when_lost, &limit,
                          &cancel, &progress)) {
        return nullptr;
    }
    Py_buffer* all[] = {&simp, &fof, &ptr, &inc, &u, &first, &alive, &count, &removed_at, &exposer, &vcount};
    const Py_ssize_t c = alive.len;
    const Py_ssize_t g = count.len / 8;
    PyObject* result = nullptr;
    if (dp1 < 1 || k < 1 || !sized(simp, c * dp1, 8) || !sized(fof, c * dp1, 8) || !sized(ptr, g + 1, 8) ||
        !sized(inc, c * dp1, 8) || !sized(u, c * dp1 * k, 8) || first.len % 8 != 0 || !sized(removed_at, c, 8) ||
        !sized(exposer, g, 8) || vcount.len % 8 != 0) {
        PyErr_SetString(PyExc_ValueError, "extract_loop: array sizes do not match");
    } else {
        Tables t;
        t.simplices = static_cast<const i64*>(simp.buf);
        t.facet_of = static_cast<const i64*>(fof.buf);
        t.ptr = static_cast<const i64*>(ptr.buf);
        t.inc = static_cast<const i64*>(inc.buf);
        t.u = static_cast<const double*>(u.buf);
        t.c = c, t.g = g, t.dp1 = dp1, t.k = k;
        t.prune_boundary = prune_boundary != 0;
        t.alive = static_cast<unsigned char*>(alive.buf);
        t.count = static_cast<i64*>(count.buf);
        t.removed_at = static_cast<i64*>(removed_at.buf);
        t.exposer = static_cast<i64*>(exposer.buf);
        t.vcount = static_cast<i64*>(vcount.buf);
        const i64* f = static_cast<const i64*>(first.buf);
        std::deque<i64> prune(f, f + first.len / 8);
        std::vector<Entry> entries;
        for (i64 h = 0; h < g; ++h) {
            if (t.count[h] > 2) entries.push_back({-M_PI, h});
        }
        Heap heap(std::greater<Entry>(), std::move(entries));
        Steps out;
        const int status = run(t, prune, heap, stop_when_lost != 0, limit, cancel, progress, out);
        if (status >= 0) {
            result = Py_BuildValue("(iLNNNNNNNNN)", status, static_cast<long long>(t.lost), as_bytes(out.rule),
                                   as_bytes(out.facet), as_bytes(out.keep_a), as_bytes(out.keep_b),
                                   as_bytes(out.angle), as_bytes(out.cause), as_bytes(out.size), as_bytes(out.rptr),
                                   as_bytes(out.removed));
        }
    }
    for (Py_buffer* b : all) PyBuffer_Release(b);
    return result;
}

PyMethodDef methods[] = {
    {"extract_loop", extract_loop, METH_VARARGS,
     "extract_loop(simplices, facet_of, ptr, inc, u, first, alive, count, removed_at, exposer, vcount, dp1, k, "
     "prune_boundary, stop_when_sample_lost, limit, cancel, progress) -> (status, lost, rule, facet, keep_a, "
     "keep_b, angle, cause, size, removed_ptr, removed)\n\n"
     "Algorithm 3's loop on int64 / float64 / bool buffers; the last five tables are updated in place."},
    {nullptr, nullptr, 0, nullptr},
};

PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_prune", "Algorithm 3's loop (core/paper/extraction.py) in C++.", -1, methods,
};

}  // namespace

PyMODINIT_FUNC PyInit__prune() { return PyModule_Create(&module); }
