// ngi offline: non-manifold repair by cutting (see manifold_repair.h for the contract).
// Approach of CGAL's Polygon Mesh Processing (orient_polygon_soup, Attene's "orientable
// pairing" of fans around an edge): pair triangles around each edge, then split every
// vertex into its corner fans with a union-find over the kept pairs.
#include "ngi/mesh/manifold_repair.h"

#include "union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

namespace ngi {
namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

// One side of a triangle: triangle f, corner k (the side runs from corner k to k + 1).
struct Side {
    uint64_t key;
    uint32_t face;
    uint32_t corner;
};

// Pairs the triangles around one edge (lo, hi), shared by more than two of them: sorted by
// their angle about the edge, consecutive ones of opposite direction become neighbours.
// Returns the pairs as indices into `sides`.
std::vector<std::pair<size_t, size_t>> pairAroundEdge(const TriangleMesh& mesh, const std::vector<Side>& sides,
                                                      size_t begin, size_t end)
{
    const uint32_t lo = uint32_t(sides[begin].key >> 32), hi = uint32_t(sides[begin].key & 0xffffffffu);
    const glm::dvec3 a = mesh.positions[lo], axis = mesh.positions[hi] - a;
    const double axisLength = glm::length(axis);
    const glm::dvec3 d = axisLength > 0.0 ? axis / axisLength : glm::dvec3(1, 0, 0);
    struct Fan {
        size_t side;
        double angle;
        bool forward;
    };
    std::vector<Fan> fans;
    glm::dvec3 reference(0.0);
    for (size_t i = begin; i < end; ++i) {
        const glm::uvec3& t = mesh.triangles[sides[i].face];
        const uint32_t k = sides[i].corner;
        const uint32_t opposite = t[(k + 2) % 3];
        glm::dvec3 w = mesh.positions[opposite] - a;
        w -= d * glm::dot(w, d);
        if (i == begin) reference = glm::length(w) > 0.0 ? glm::normalize(w) : glm::dvec3(0.0);
        const double angle = std::atan2(glm::dot(glm::cross(reference, w), d), glm::dot(reference, w));
        fans.push_back({i, angle, t[k] == lo});
    }
    std::sort(fans.begin(), fans.end(), [](const Fan& l, const Fan& r) { return l.angle < r.angle; });
    // Two ways to pair a cyclic sequence into consecutive pairs; keep the one with more
    // opposite-direction pairs (those bound one wedge of space consistently).
    std::vector<std::pair<size_t, size_t>> best;
    const size_t n = fans.size();
    for (size_t start = 0; start < 2; ++start) {
        std::vector<std::pair<size_t, size_t>> pairs;
        for (size_t i = 0; i + 1 < n; i += 2) {
            const Fan &f = fans[(start + i) % n], &g = fans[(start + i + 1) % n];
            if (f.forward != g.forward) pairs.push_back({f.side, g.side});
        }
        if (pairs.size() > best.size()) best = std::move(pairs);
    }
    return best;
}

}  // namespace

ManifoldRepair splitNonManifold(TriangleMesh& mesh, const std::vector<glm::uvec2>& forcedCuts)
{
    ManifoldRepair repair;
    std::unordered_set<uint64_t> cut;
    for (const glm::uvec2& e : forcedCuts) cut.insert(edgeKey(e.x, e.y));

    for (int pass = 0; pass < 2; ++pass) {
        std::vector<Side> sides;
        sides.reserve(mesh.triangles.size() * 3);
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            for (uint32_t k = 0; k < 3; ++k)
                sides.push_back({edgeKey(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]), f, k});
        std::sort(sides.begin(), sides.end(), [](const Side& l, const Side& r) {
            return std::tie(l.key, l.face, l.corner) < std::tie(r.key, r.face, r.corner);
        });

        // Kept neighbour pairs join the corners at both ends of their shared side.
        detail::UnionFind corners(mesh.triangles.size() * 3);
        auto join = [&](const Side& s, const Side& t) {
            const glm::uvec3 &p = mesh.triangles[s.face], &q = mesh.triangles[t.face];
            for (uint32_t i : {s.corner, (s.corner + 1) % 3})
                for (uint32_t j : {t.corner, (t.corner + 1) % 3})
                    if (p[i] == q[j]) corners.unite(s.face * 3 + i, t.face * 3 + j);
        };
        std::vector<uint8_t> unresolved(mesh.triangles.size(), 0);
        size_t nonManifold = 0;
        for (size_t i = 0; i < sides.size();) {
            size_t j = i;
            while (j < sides.size() && sides[j].key == sides[i].key) ++j;
            const size_t count = j - i;
            if (cut.count(sides[i].key)) {
                repair.cutEdgeSides += pass == 0 ? count : 0;
            } else if (count == 2) {
                join(sides[i], sides[i + 1]);
            } else if (count > 2) {
                ++nonManifold;
                const auto pairs = pairAroundEdge(mesh, sides, i, j);
                for (const auto& [s, t] : pairs) join(sides[s], sides[t]);
                if (pass == 0) repair.cutEdgeSides += count - 2 * pairs.size();
                // In the second pass an edge still shared by more than two triangles had its
                // leftovers re-joined through other edges: those triangles are dropped.
                if (pass == 1) {
                    std::vector<uint8_t> paired(count, 0);
                    for (const auto& [s, t] : pairs) paired[s - i] = paired[t - i] = 1;
                    for (size_t s = i; s < j; ++s)
                        if (!paired[s - i]) unresolved[sides[s].face] = 1;
                }
            }
            i = j;
        }
        if (pass == 0) repair.nonManifoldEdges = nonManifold;
        if (pass == 1) {
            if (nonManifold == 0) break;
            std::vector<glm::uvec3> kept;
            for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
                if (!unresolved[f]) kept.push_back(mesh.triangles[f]);
            repair.droppedTriangles += mesh.triangles.size() - kept.size();
            mesh.triangles = std::move(kept);
            break;
        }

        // Each vertex keeps its first fan of corners; every other fan gets a copy.
        std::vector<uint32_t> fanOfVertex(mesh.positions.size(), UINT32_MAX);  // root of the first fan
        std::vector<uint32_t> copyOfFan(mesh.triangles.size() * 3, UINT32_MAX);
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t v = mesh.triangles[f][k], root = corners.find(f * 3 + k);
                if (fanOfVertex[v] == UINT32_MAX) fanOfVertex[v] = root;
                if (fanOfVertex[v] == root) continue;
                if (copyOfFan[root] == UINT32_MAX) {
                    copyOfFan[root] = uint32_t(mesh.positions.size());
                    mesh.positions.push_back(mesh.positions[v]);
                    ++repair.splitVertices;
                }
                mesh.triangles[f][k] = copyOfFan[root];
            }
        if (nonManifold == 0) break;
        // Forced cuts now name vertices that may have been copied; they did their work.
        cut.clear();
    }
    return repair;
}

}  // namespace ngi
