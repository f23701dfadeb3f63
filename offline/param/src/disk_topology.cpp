// ngi offline: validation of disk meshes and the square border shared by every map
// (paper section 3.1: "four boundary vertices are fixed to the corners of a square").
// Corners: the cut's corner hints when it has them (genus >= 1: the polygon schema's
// corners), else the boundary's own sharp corners where it has two or more, else equal 3D arc
// length along the boundary loop, so each side of the square receives a quarter of the boundary;
// the boundary between two corners goes on a straight side.
#include "ngi/param/disk_topology.h"

#include "ngi/error.h"
#include "ngi/mesh/mesh_topology.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

namespace ngi {

DiskTopology analyzeDisk(const DiskMesh& disk)
{
    const auto& positions = disk.mesh.positions;
    const auto& triangles = disk.mesh.triangles;
    const size_t n = positions.size();
    if (n == 0 || triangles.empty()) throw Error("parameterization: the disk mesh is empty");
    for (size_t v = 0; v < n; ++v) {
        const glm::dvec3& p = positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw Error("parameterization: vertex " + std::to_string(v) + " has a NaN/Inf coordinate");
    }
    if (!disk.originalVertex.empty() && disk.originalVertex.size() != n)
        throw Error("parameterization: originalVertex has " + std::to_string(disk.originalVertex.size()) +
                    " entries for " + std::to_string(n) + " vertices");

    // Directed half-edges (a, b, triangle), sorted by undirected key, to find edge multiplicities.
    struct HalfEdge {
        uint32_t lo, hi;
        bool forward;
        uint32_t triangle;
    };
    std::vector<HalfEdge> halfEdges;
    halfEdges.reserve(triangles.size() * 3);
    std::vector<uint8_t> used(n, 0);
    for (size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[k] >= n)
                throw Error("parameterization: triangle " + std::to_string(t) + " has an out-of-range index");
            used[tri[k]] = 1;
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            throw Error("parameterization: triangle " + std::to_string(t) + " repeats a vertex");
        const glm::dvec3 e1 = positions[tri[1]] - positions[tri[0]], e2 = positions[tri[2]] - positions[tri[0]];
        if (glm::length(glm::cross(e1, e2)) <= 0.0)
            throw Error("parameterization: triangle " + std::to_string(t) + " has zero area");
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            halfEdges.push_back({std::min(a, b), std::max(a, b), a < b, uint32_t(t)});
        }
    }
    for (size_t v = 0; v < n; ++v)
        if (!used[v]) throw Error("parameterization: vertex " + std::to_string(v) + " is in no triangle");
    std::sort(halfEdges.begin(), halfEdges.end(),
              [](const HalfEdge& a, const HalfEdge& b) { return std::tie(a.lo, a.hi) < std::tie(b.lo, b.hi); });

    DiskTopology topology;
    std::vector<uint32_t> boundaryNext(n, UINT32_MAX);  // boundary half-edge a -> b (triangle side)
    size_t boundaryEdges = 0;
    for (size_t i = 0; i < halfEdges.size();) {
        size_t j = i;
        while (j < halfEdges.size() && halfEdges[j].lo == halfEdges[i].lo && halfEdges[j].hi == halfEdges[i].hi) ++j;
        const size_t count = j - i;
        const HalfEdge& h = halfEdges[i];
        if (count > 2)
            throw Error("parameterization: edge (" + std::to_string(h.lo) + ", " + std::to_string(h.hi) +
                        ") is shared by " + std::to_string(count) + " triangles (non-manifold)");
        if (count == 2 && halfEdges[i].forward == halfEdges[i + 1].forward)
            throw Error("parameterization: triangles " + std::to_string(halfEdges[i].triangle) + " and " +
                        std::to_string(halfEdges[i + 1].triangle) + " have inconsistent orientation");
        if (count == 1) {
            const uint32_t a = h.forward ? h.lo : h.hi, b = h.forward ? h.hi : h.lo;
            if (boundaryNext[a] != UINT32_MAX)
                throw Error("parameterization: boundary vertex " + std::to_string(a) + " is non-manifold");
            boundaryNext[a] = b;
            ++boundaryEdges;
        }
        topology.edges.push_back({h.lo, h.hi});
        i = j;
    }

    const auto& loop = disk.boundaryLoop;
    if (boundaryEdges == 0) throw Error("parameterization: the mesh has no boundary (not a disk; cut it first)");
    if (loop.size() != boundaryEdges)
        throw Error("parameterization: boundaryLoop has " + std::to_string(loop.size()) +
                    " vertices but the mesh has " + std::to_string(boundaryEdges) +
                    " boundary edges (more than one boundary loop?)");
    if (loop.size() < 4)
        throw Error("parameterization: the boundary has fewer than 4 vertices (no room for 4 corners)");
    topology.boundaryPosition.assign(n, -1);
    for (size_t k = 0; k < loop.size(); ++k) {
        const uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
        if (a >= n || topology.boundaryPosition[a] != -1)
            throw Error("parameterization: boundaryLoop entry " + std::to_string(k) + " is out of range or repeated");
        if (boundaryNext[a] != b)
            throw Error(
                "parameterization: boundaryLoop is not the mesh boundary in counter-clockwise order (at entry " +
                std::to_string(k) + ")");
        topology.boundaryPosition[a] = int32_t(k);
    }
    const long euler = long(n) - long(topology.edges.size()) + long(triangles.size());
    if (euler != 1)
        throw Error("parameterization: Euler characteristic is " + std::to_string(euler) +
                    ", a disk has 1 (handles or several components left after the cut)");
    topology.interiorVertexCount = n - loop.size();
    return topology;
}

std::array<size_t, 4> chooseCornerPositions(const DiskMesh& disk)
{
    const auto& loop = disk.boundaryLoop;
    const auto& p = disk.mesh.positions;
    const size_t m = loop.size();
    if (disk.cornerHints.size() == 4) {
        // The cut's polygon-schema corners (copies of the cut graph's junctions, cut.h): the
        // boundary already turns there, so the flat metric needs far less conformal scaling.
        std::vector<int64_t> position(p.size(), -1);
        for (size_t k = 0; k < m; ++k) position[loop[k]] = int64_t(k);
        std::array<size_t, 4> corners{};
        bool valid = true;
        for (int c = 0; c < 4; ++c) {
            const uint32_t v = disk.cornerHints[c];
            valid = valid && v < p.size() && position[v] >= 0;
            if (valid) corners[c] = size_t(position[v]);
        }
        if (valid) {
            std::sort(corners.begin(), corners.end());
            if (std::adjacent_find(corners.begin(), corners.end()) == corners.end()) return corners;
        }
    }
    std::vector<double> arc(m + 1, 0.0);
    for (size_t k = 0; k < m; ++k) arc[k + 1] = arc[k] + glm::length(p[loop[(k + 1) % m]] - p[loop[k]]);
    // Arc length at a position of the loop unrolled once (positions m..2m-1 wrap around).
    auto arcAt = [&](size_t k) { return k < m ? arc[k] : arc[m] + arc[k - m]; };
    // An "ear" (boundary vertex of a single triangle) that is not a corner gets a degenerate
    // triangle on a straight side; prefer ears within 1/16 of the boundary of each quarter.
    std::vector<int> triangleCount(p.size(), 0);
    for (const glm::uvec3& tri : disk.mesh.triangles)
        for (int k = 0; k < 3; ++k) ++triangleCount[tri[k]];
    const double window = arc[m] / 16.0;
    // The position in [lo, hi] (unrolled) closest in arc length to `target`, an ear within the
    // window preferred.
    auto nearest = [&](size_t lo, size_t hi, double target) {
        size_t best = lo;
        bool bestEar = false;
        for (size_t k = lo; k <= hi; ++k) {
            const bool ear = triangleCount[loop[k % m]] == 1 && std::abs(arcAt(k) - target) <= window;
            const bool closer = std::abs(arcAt(k) - target) < std::abs(arcAt(best) - target);
            if ((ear && !bestEar) || (ear == bestEar && closer)) {
                best = k;
                bestEar = ear;
            }
        }
        return best;
    };

    // The boundary's own sharp corners (a flat part's corners, a single triangle's) become
    // corners of the square: where it turns by more than 45 degrees, at the vertex and over 1/64
    // of its length either side weighted by a tent (so that a ragged scan border's zigzag is no
    // corner), at most four, sharpest first and a sixteenth of the boundary apart. A corner of
    // interior angle a placed on a straight side
    // must open to 180 degrees, and the conformal start shrinks the surface around it by r^(2 pi /
    // a - 2): a 60-degree corner by r^4, which no remesh density resolves and which reads as a thin
    // part. Placed on a corner of the square, it opens to 90 degrees only (r^1 for 60 degrees).
    // Only on a border that is wholly the surface's own (DiskMesh::surfaceBoundary, where the cut
    // gave it), each vertex met once: no copies of a cut path, no tips, no seam to other pieces
    // of a split.
    const std::vector<double> angleSum = vertexAngleSums(disk.mesh);
    auto original = [&](uint32_t v) { return disk.originalVertex.empty() ? v : disk.originalVertex[v]; };
    auto ownBoundary = [&](uint32_t v) { return v < disk.surfaceBoundary.size() && disk.surfaceBoundary[v]; };
    std::map<uint32_t, int> visits;
    for (uint32_t v : loop) ++visits[original(v)];
    // Only where the whole border is the surface's own, met once (an open part not cut further):
    // where a cut joins several boundary loops, corners on their turns can gather on one loop and
    // stretch the map (a blob with two holes: conformal shrink e^6.14 against e^4.26 at equal arc
    // lengths).
    bool wholeBorderOwn = true;
    for (uint32_t v : loop) wholeBorderOwn = wholeBorderOwn && ownBoundary(v) && visits[original(v)] == 1;
    constexpr double kPi = 3.14159265358979323846, kSharpTurn = 0.25 * kPi;  // 45 degrees
    const double reach = arc[m] / 64.0;
    std::vector<std::pair<double, size_t>> sharp;  // (-turn over the tent, position)
    for (size_t k = 0; k < m && wholeBorderOwn; ++k) {
        if (kPi - angleSum[loop[k]] <= kSharpTurn) continue;
        double turn = kPi - angleSum[loop[k]];
        for (int dir : {-1, 1})
            for (size_t step = 1; step < m / 2; ++step) {
                const size_t j = dir > 0 ? (k + step) % m : (k + m - step) % m;
                const double d = std::abs(arc[j] - arc[k]), distance = std::min(d, arc[m] - d);
                if (distance >= reach) break;
                turn += (kPi - angleSum[loop[j]]) * (1.0 - distance / reach);
            }
        if (turn > kSharpTurn) sharp.push_back({-turn, k});
    }
    std::sort(sharp.begin(), sharp.end());
    std::vector<size_t> chosen;
    for (const auto& [angle, k] : sharp) {
        if (chosen.size() == 4) break;
        bool apart = true;
        for (size_t c : chosen) {
            const double d = std::abs(arc[k] - arc[c]);
            apart = apart && std::min(d, arc[m] - d) >= window;
        }
        if (apart) chosen.push_back(k);
    }
    std::sort(chosen.begin(), chosen.end());
    if (chosen.size() >= 2) {
        // The rest of the four at the middle of the longest stretches between corners.
        while (chosen.size() < 4) {
            size_t longest = chosen.size();
            double longestArc = -1.0;
            for (size_t i = 0; i < chosen.size(); ++i) {
                const size_t a = chosen[i], b = i + 1 < chosen.size() ? chosen[i + 1] : chosen[0] + m;
                if (b - a >= 2 && arcAt(b) - arcAt(a) > longestArc) longest = i, longestArc = arcAt(b) - arcAt(a);
            }
            if (longest == chosen.size()) break;  // no vertex left between corners (m < 4)
            const size_t a = chosen[longest], b = longest + 1 < chosen.size() ? chosen[longest + 1] : chosen[0] + m;
            chosen.push_back(nearest(a + 1, b - 1, arcAt(a) + 0.5 * longestArc) % m);
            std::sort(chosen.begin(), chosen.end());
        }
        if (chosen.size() == 4) return {chosen[0], chosen[1], chosen[2], chosen[3]};
    }

    // Otherwise four equally spaced arc lengths, from the one sharp corner where there is one.
    // Corner 0 may move off position 0 (rotating the loop) when an ear is near the start.
    size_t first = chosen.size() == 1 ? chosen[0] : nearest(0, m - 1, 0.0);
    if (chosen.size() != 1 && std::abs(arc[first]) > window && std::abs(arc[m] - arc[first]) > window) first = 0;
    std::array<size_t, 4> corners{first, 0, 0, 0};
    for (int c = 1; c < 4; ++c)
        corners[c] = nearest(corners[c - 1] + 1, first + m - (4 - c), arc[first] + arc[m] * c / 4.0);
    for (size_t& c : corners) c %= m;
    return corners;
}

std::vector<glm::dvec2> placeBoundaryOnSquare(const std::vector<double>& edgeLength,
                                              const std::array<size_t, 4>& cornerPositions)
{
    static const glm::dvec2 kCorner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const size_t m = edgeLength.size();
    std::vector<glm::dvec2> uv(m);
    for (int side = 0; side < 4; ++side) {
        const auto [begin, end] = sideRange(side, cornerPositions, m);
        double total = 0.0;
        for (size_t k = begin; k < end; ++k) total += edgeLength[k % m];
        if (!(total > 0.0)) throw Error("parameterization: a side of the square has zero boundary length");
        double walked = 0.0;
        for (size_t k = begin; k < end; ++k) {
            const double t = walked / total;
            uv[k % m] = kCorner[side] + t * (kCorner[(side + 1) % 4] - kCorner[side]);
            walked += edgeLength[k % m];
        }
    }
    // Exact corners and exact border coordinates (no rounding drift off the border).
    for (int c = 0; c < 4; ++c) uv[cornerPositions[c]] = kCorner[c];
    return uv;
}

SideRange sideRange(int side, const std::array<size_t, 4>& cornerPositions, size_t loopSize)
{
    const size_t begin = cornerPositions[side];
    size_t end = cornerPositions[(side + 1) % 4];
    if (end <= begin) end += loopSize;
    return {begin, end};
}

int boundarySide(size_t loopPosition, const std::array<size_t, 4>& cornerPositions, size_t loopSize)
{
    for (int side = 0; side < 4; ++side) {
        const auto [begin, end] = sideRange(side, cornerPositions, loopSize);
        const size_t k = loopPosition < begin ? loopPosition + loopSize : loopPosition;
        if (k >= begin && k < end) return side;
    }
    return 0;
}

}  // namespace ngi
