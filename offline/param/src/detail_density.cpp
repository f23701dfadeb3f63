// ngi offline: the detail-following OT target measure (paper section 3.1, Eq. 3: nu_i is any
// positive measure). The integrated mean curvature of an edge is
// |theta_e| * |e| / 2 (theta_e its dihedral angle), half to each end: the discrete mean
// curvature of polyhedral surfaces (Meyer et al. 2003, Cohen-Steiner & Morvan 2003).
#include "ngi/param/detail_density.h"

#include "ngi/error.h"
#include "ngi/param/distortion.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ngi {

std::vector<double> detailDensityTargets(const DiskMesh& disk, double strength)
{
    if (!std::isfinite(strength) || strength < 0.0)
        throw Error("detail density: the strength must be a finite number >= 0");
    const TriangleMesh& mesh = disk.mesh;
    std::vector<double> area = vertexAreas(mesh);
    const size_t n = mesh.positions.size();
    auto normalized = [](std::vector<double> nu) {
        double total = 0.0;
        for (double a : nu) total += a;
        for (double& a : nu) a /= total;
        return nu;
    };
    if (strength == 0.0 || n == 0) return normalized(std::move(area));

    // Vertices of the uncut surface: the two copies of a cut vertex are one.
    const bool joined = disk.originalVertex.size() == n;
    uint32_t surfaceCount = 0;
    for (size_t v = 0; v < n; ++v)
        surfaceCount = std::max(surfaceCount, (joined ? disk.originalVertex[v] : uint32_t(v)) + 1);
    auto surfaceVertex = [&](uint32_t v) { return joined ? disk.originalVertex[v] : v; };

    // Each undirected surface edge: the first face's normal, then the dihedral when the second comes.
    std::vector<double> integrated(surfaceCount, 0.0), surfaceArea(surfaceCount, 0.0);
    for (size_t v = 0; v < n; ++v) surfaceArea[surfaceVertex(uint32_t(v))] += area[v];
    std::unordered_map<uint64_t, glm::dvec3> firstNormal;
    firstNormal.reserve(mesh.triangles.size() * 2);
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec3 c =
            glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
        const double len = glm::length(c);
        if (!(len > 0.0)) continue;
        const glm::dvec3 normal = c / len;
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = surfaceVertex(t[k]), b = surfaceVertex(t[(k + 1) % 3]);
            if (a == b) continue;
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            const auto [it, inserted] = firstNormal.try_emplace(key, normal);
            if (inserted) continue;
            // atan2, not acos: acos of a dot near 1 turns rounding into angles of 1e-8.
            const double theta = std::atan2(glm::length(glm::cross(it->second, normal)), glm::dot(it->second, normal));
            const double h = 0.5 * theta * glm::length(mesh.positions[t[k]] - mesh.positions[t[(k + 1) % 3]]);
            integrated[a] += 0.5 * h;
            integrated[b] += 0.5 * h;
        }
    }
    // Pointwise |H| = integrated / area, smoothed over two rings (area-weighted) so the
    // density does not follow the remesh's own noise.
    std::vector<double> k(surfaceCount, 0.0);
    for (uint32_t v = 0; v < surfaceCount; ++v) k[v] = surfaceArea[v] > 0.0 ? integrated[v] / surfaceArea[v] : 0.0;
    std::vector<std::vector<uint32_t>> ring(surfaceCount);
    for (const auto& [key, normal] : firstNormal) {
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
        ring[a].push_back(b);
        ring[b].push_back(a);
    }
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double> next(surfaceCount);
        for (uint32_t v = 0; v < surfaceCount; ++v) {
            double sum = k[v] * surfaceArea[v], weight = surfaceArea[v];
            for (uint32_t w : ring[v]) sum += k[w] * surfaceArea[w], weight += surfaceArea[w];
            next[v] = weight > 0.0 ? sum / weight : 0.0;
        }
        k = std::move(next);
    }
    double mean = 0.0, total = 0.0;
    for (uint32_t v = 0; v < surfaceCount; ++v) mean += k[v] * surfaceArea[v], total += surfaceArea[v];
    mean = total > 0.0 ? mean / total : 0.0;
    if (!(mean > 0.0)) return normalized(std::move(area));  // flat: nothing to follow
    for (size_t v = 0; v < n; ++v)
        area[v] *= 1.0 + strength * std::min(k[surfaceVertex(uint32_t(v))] / mean, kMaxDetailRatio);
    return normalized(std::move(area));
}

}  // namespace ngi
