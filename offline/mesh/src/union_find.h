// ngi offline (private to ngi_mesh): disjoint sets over 0 .. n-1 with path halving, the one
// union-find of the mesh stages (clean.cpp: corners glued across manifold edges; cut.cpp:
// faces of the face-peeling cut graph and corners of the cut mesh).
#pragma once

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace ngi::detail {

struct UnionFind {
    std::vector<uint32_t> parent;

    // n singleton sets {0}, ..., {n-1}.
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }

    // The representative of x's set (x < n); halves the path on the way.
    uint32_t find(uint32_t x)
    {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }

    // Merges the sets of a and b; false when they were one set already. The representative of
    // the merged set is b's.
    bool unite(uint32_t a, uint32_t b)
    {
        a = find(a), b = find(b);
        if (a == b) return false;
        parent[a] = b;
        return true;
    }
};

}  // namespace ngi::detail
