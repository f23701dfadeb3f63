// ngi offline: validation of disk meshes and the square border shared by every map
// (paper section 3.1: "four boundary vertices are fixed to the corners of a square").
// Corners: the cut's corner hints when it has them (genus >= 1: the polygon schema's
// corners), else equal 3D arc length along the boundary loop, so each side of the square
// receives a quarter of the boundary; the boundary between two corners goes on a straight side.
#include "ngi/param/disk_topology.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
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
    // An "ear" (boundary vertex of a single triangle) that is not a corner gets a degenerate
    // triangle on a straight side; prefer ears within 1/16 of the boundary of each quarter.
    std::vector<int> triangleCount(p.size(), 0);
    for (const glm::uvec3& tri : disk.mesh.triangles)
        for (int k = 0; k < 3; ++k) ++triangleCount[tri[k]];
    const double window = arc[m] / 16.0;
    auto pick = [&](size_t first, size_t last, double target) {  // positions in [first, last]
        size_t best = first;
        bool bestEar = false;
        for (size_t k = first; k <= last; ++k) {
            const bool ear = triangleCount[loop[k % m]] == 1 && std::abs(arc[k] - target) <= window;
            const bool closer = std::abs(arc[k] - target) < std::abs(arc[best] - target);
            if ((ear && !bestEar) || (ear == bestEar && closer)) {
                best = k;
                bestEar = ear;
            }
        }
        return best;
    };
    // Corner 0 may move off position 0 (rotating the loop) when an ear is near the start.
    size_t first = pick(0, m - 1, 0.0);
    if (std::abs(arc[first]) > window && std::abs(arc[m] - arc[first]) > window) first = 0;
    std::array<size_t, 4> corners{first, 0, 0, 0};
    for (int c = 1; c < 4; ++c) {
        const double target = arc[first] + arc[m] * c / 4.0;
        const size_t lo = corners[c - 1] + 1, hi = first + m - (4 - c);
        // Arc length beyond the loop's end wraps around.
        size_t best = lo;
        bool bestEar = false;
        for (size_t k = lo; k <= hi; ++k) {
            const double a = k < m ? arc[k] : arc[m] + arc[k - m];
            const double b = best < m ? arc[best] : arc[m] + arc[best - m];
            const bool ear = triangleCount[loop[k % m]] == 1 && std::abs(a - target) <= window;
            const bool closer = std::abs(a - target) < std::abs(b - target);
            if ((ear && !bestEar) || (ear == bestEar && closer)) {
                best = k;
                bestEar = ear;
            }
        }
        corners[c] = best;
    }
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
