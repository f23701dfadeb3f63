// ngi offline eval: open edges and crack width of a drawn mesh (see open_edges.h).
#include "ngi/eval/open_edges.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <vector>

namespace ngi {
namespace {

double pointSegmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b)
{
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::distance(p, a + t * ab);
}

}  // namespace

OpenEdgeReport measureOpenEdges(const TriangleMesh& mesh, double tolerance)
{
    std::map<std::tuple<long long, long long, long long>, uint32_t> ids;
    std::vector<uint32_t> welded(mesh.positions.size());
    std::vector<glm::dvec3> position;
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3 q = glm::round(mesh.positions[v] / tolerance);
        const auto [it, inserted] =
            ids.try_emplace({(long long)q.x, (long long)q.y, (long long)q.z}, uint32_t(position.size()));
        if (inserted) position.push_back(mesh.positions[v]);
        welded[v] = it->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const glm::uvec3& t : mesh.triangles) {
        const uint32_t a = welded[t.x], b = welded[t.y], c = welded[t.z];
        if (a == b || b == c || a == c) continue;
        for (auto [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) ++edges[std::minmax(p, q)];
    }
    OpenEdgeReport report;
    std::vector<std::pair<uint32_t, uint32_t>> open;
    std::map<uint32_t, std::vector<uint32_t>> neighbours;  // along the open edges
    for (const auto& [edge, count] : edges) {
        if (count == 1) {
            open.push_back(edge);
            neighbours[edge.first].push_back(edge.second);
            neighbours[edge.second].push_back(edge.first);
        }
        if (count > 2) ++report.nonManifoldEdges;
    }
    report.openEdges = open.size();
    for (const auto& [v, adjacent] : neighbours) {
        std::set<uint32_t> near{v};  // v and everything within two steps along the open edges
        for (uint32_t a : adjacent) {
            near.insert(a);
            for (uint32_t b : neighbours[a]) near.insert(b);
        }
        double nearest = 1e300;
        for (const auto& [a, b] : open)
            if (!near.count(a) && !near.count(b))
                nearest = std::min(nearest, pointSegmentDistance(position[v], position[a], position[b]));
        if (nearest < 1e300) report.largestGap = std::max(report.largestGap, nearest);
    }
    return report;
}

}  // namespace ngi
