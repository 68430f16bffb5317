// A union-find over int64 nodes whose roots are their set's smallest node (path halving), shared by the
// compiled graph components (core/analysis/_components.cpp) and the triangle complex's counts
// (core/util/_surface.cpp).  Header only; no third-party code.

#ifndef CRUSTVIEW_UNION_FIND_H
#define CRUSTVIEW_UNION_FIND_H

#include <cstdint>
#include <vector>

namespace crustview {

inline std::int64_t find(std::vector<std::int64_t>& parent, std::int64_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];  // path halving
        v = parent[v];
    }
    return v;
}

// Joins the sets of a and b; the smaller root stays the root.
inline void unite(std::vector<std::int64_t>& parent, std::int64_t a, std::int64_t b) {
    a = find(parent, a);
    b = find(parent, b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

}  // namespace crustview

#endif  // CRUSTVIEW_UNION_FIND_H
