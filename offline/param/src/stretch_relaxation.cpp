// ngi offline: stretch-minimizing fixed-border map (Yoshizawa, Belyaev, Seidel 2004, "A fast
// and simple stretch-minimizing mesh parameterization", SMI; stretch of Sander, Snyder,
// Gortler, Hoppe 2001, "Texture mapping progressive meshes").
//
// Why: OT (optimal_transport.cpp) starts from a map whose sites the power diagram must
// separate. Conformal and harmonic maps shrink a protrusion exponentially in its length over
// its girth (e^40..e^75 on the CGAL camel, dino, man, elephant), and the damped Newton then
// crawls. YBS iterate  w_ij <- w_ij / sigma(v_j)^eta  from the mean-value map: a neighbour whose
// surroundings are shrunk (large stretch sigma = 3D length per uv length) pulls less, so the
// shrunk region spreads out; positive weights keep every iterate an embedding.
#include "ngi/param/stretch_relaxation.h"

#include "ngi/param/distortion.h"
#include "ngi/param/fixed_border_maps.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ngi {
namespace {

// Floater's mean-value weights on the 3D mesh (positive: tan(a/2) >= 0 for a in [0, pi)).
std::vector<DirectedWeight> meanValueWeights3d(const DiskMesh& disk)
{
    const auto& p = disk.mesh.positions;
    std::vector<DirectedWeight> weights;
    weights.reserve(disk.mesh.triangles.size() * 6);
    for (const glm::uvec3& tri : disk.mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
            const glm::dvec3 a = p[j] - p[i], b = p[l] - p[i];
            const double ra = glm::length(a), rb = glm::length(b);
            const double cross = glm::length(glm::cross(a, b));
            const double denom = ra * rb + glm::dot(a, b);
            const double tanHalf = denom > 0.0 ? cross / denom : 1e6;
            // Degenerate 3D triangles (zero-length edges) contribute a tiny positive weight.
            weights.push_back({i, j, ra > 0.0 ? std::max(tanHalf / ra, 1e-12) : 1e-12});
            weights.push_back({i, l, rb > 0.0 ? std::max(tanHalf / rb, 1e-12) : 1e-12});
        }
    }
    return weights;
}

// Per-vertex L2 stretch of the map uv -> 3D (Sander et al. 2001, Eq. 2-3), with uv scaled so
// that the total uv area equals the total 3D area: sigma_t = sqrt((|S_s|^2 + |S_t|^2) / 2),
// sigma(v)^2 = sum_t A3d_t sigma_t^2 / sum_t A3d_t over the triangles at v.
std::vector<double> vertexStretch(const DiskMesh& disk, const std::vector<glm::dvec2>& uv)
{
    const auto& p = disk.mesh.positions;
    const size_t nt = disk.mesh.triangles.size();
    std::vector<double> area3d(nt), areaUv(nt);
    double total3d = 0.0, totalUv = 0.0;
    for (size_t t = 0; t < nt; ++t) {
        const glm::uvec3 tri = disk.mesh.triangles[t];
        area3d[t] = 0.5 * glm::length(glm::cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]));
        const glm::dvec2 a = uv[tri[1]] - uv[tri[0]], b = uv[tri[2]] - uv[tri[0]];
        areaUv[t] = 0.5 * (a.x * b.y - a.y * b.x);
        total3d += area3d[t];
        totalUv += std::max(areaUv[t], 0.0);
    }
    const double scale2 = totalUv / total3d;  // uv area per 3D area of a uniform map
    std::vector<double> sum(p.size(), 0.0), weight(p.size(), 0.0);
    for (size_t t = 0; t < nt; ++t) {
        const glm::uvec3 tri = disk.mesh.triangles[t];
        double sigma2;
        if (!(areaUv[t] > 0.0)) {
            sigma2 = 1e30;
        } else {
            const glm::dvec2 q1 = uv[tri[0]], q2 = uv[tri[1]], q3 = uv[tri[2]];
            const double twice = 2.0 * areaUv[t];
            const glm::dvec3 ss =
                (p[tri[0]] * (q2.y - q3.y) + p[tri[1]] * (q3.y - q1.y) + p[tri[2]] * (q1.y - q2.y)) / twice;
            const glm::dvec3 st =
                (p[tri[0]] * (q3.x - q2.x) + p[tri[1]] * (q1.x - q3.x) + p[tri[2]] * (q2.x - q1.x)) / twice;
            sigma2 = std::min(1e30, 0.5 * (glm::dot(ss, ss) + glm::dot(st, st)) * scale2);
        }
        const double w = std::max(area3d[t], 1e-300);
        for (int k = 0; k < 3; ++k) sum[tri[k]] += w * sigma2, weight[tri[k]] += w;
    }
    std::vector<double> sigma(p.size(), 1.0);
    for (size_t v = 0; v < p.size(); ++v)
        if (weight[v] > 0.0) sigma[v] = std::sqrt(sum[v] / weight[v]);
    return sigma;
}

}  // namespace

std::vector<glm::dvec2> stretchMinimizingMap(const DiskMesh& disk, const DiskTopology& topology,
                                             const std::array<size_t, 4>& cornerPositions,
                                             const StretchRelaxationOptions& options, StretchRelaxationReport* report)
{
    const auto& loop = disk.boundaryLoop;
    std::vector<double> length(loop.size());
    for (size_t k = 0; k < loop.size(); ++k)
        length[k] = glm::distance(disk.mesh.positions[loop[(k + 1) % loop.size()]], disk.mesh.positions[loop[k]]);
    const std::vector<glm::dvec2> boundaryUv = placeBoundaryOnSquare(length, cornerPositions);

    std::vector<DirectedWeight> weights = meanValueWeights3d(disk);
    std::vector<glm::dvec2> uv = solveFixedBorderMap(disk, topology, boundaryUv, weights, false, true);
    StretchRelaxationReport local;
    double best = measureDistortion(disk.mesh, uv).areaMax;
    local.startAreaMax = best;
    std::vector<glm::dvec2> bestUv = uv;
    int sinceBest = 0;
    for (int iteration = 0; iteration < options.maxIterations && sinceBest < 3 && best > options.targetAreaMax;
         ++iteration) {
        const std::vector<double> sigma = vertexStretch(disk, uv);
        for (DirectedWeight& w : weights) w.weight = std::max(w.weight / std::pow(sigma[w.to], options.eta), 1e-280);
        uv = solveFixedBorderMap(disk, topology, boundaryUv, weights, false, false);
        ++local.iterations;
        const MapDistortion d = measureDistortion(disk.mesh, uv);
        if (d.flipped == 0 && d.areaMax < best) {
            best = d.areaMax, bestUv = uv, sinceBest = 0;
        } else {
            ++sinceBest;
        }
    }
    local.areaMax = best;
    if (report) *report = local;
    return bestUv;
}

}  // namespace ngi
