// ngi offline: area and angle distortion of a parameterization (the quantities the paper's
// Table 1 trades off: OT is area-preserving, Ricci flow angle-preserving). Area distortion
// is |log(A_uv / A_3d)| with both areas normalized to total 1, so a uniform scale is free.
#include "ngi/param/distortion.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi {
namespace {

double cornerAngle(glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

}  // namespace

MapDistortion measureDistortion(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv)
{
    MapDistortion d;
    const auto& p = mesh.positions;
    double total3d = 0.0, totalUv = 0.0;
    std::vector<double> area3d(mesh.triangles.size()), areaUv(mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        area3d[t] = 0.5 * glm::length(glm::cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]));
        const glm::dvec2 a = uv[tri[1]] - uv[tri[0]], b = uv[tri[2]] - uv[tri[0]];
        areaUv[t] = 0.5 * (a.x * b.y - a.y * b.x);
        total3d += area3d[t];
        if (areaUv[t] > 0.0) totalUv += areaUv[t];
    }
    double weighted = 0.0, weight = 0.0, angleSum = 0.0;
    size_t corners = 0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (!(areaUv[t] > 0.0)) {
            ++d.flipped;
            continue;
        }
        const double log = std::abs(std::log((areaUv[t] / totalUv) / (area3d[t] / total3d)));
        d.areaMax = std::max(d.areaMax, log);
        weighted += log * area3d[t];
        weight += area3d[t];
        const glm::uvec3 tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
            const double angle3d = cornerAngle(p[j] - p[i], p[l] - p[i]);
            const double angleUv = cornerAngle(glm::dvec3(uv[j] - uv[i], 0.0), glm::dvec3(uv[l] - uv[i], 0.0));
            const double error = std::abs(angleUv - angle3d);
            d.angleMax = std::max(d.angleMax, error);
            angleSum += error;
            ++corners;
        }
    }
    d.areaMean = weight > 0.0 ? weighted / weight : 0.0;
    d.angleMean = corners > 0 ? angleSum / double(corners) : 0.0;
    return d;
}

std::vector<double> vertexAreas(const TriangleMesh& mesh)
{
    std::vector<double> area(mesh.positions.size(), 0.0);
    for (const glm::uvec3& tri : mesh.triangles) {
        const double a = 0.5 *
            glm::length(glm::cross(mesh.positions[tri[1]] - mesh.positions[tri[0]],
                                   mesh.positions[tri[2]] - mesh.positions[tri[0]]));
        for (int k = 0; k < 3; ++k) area[tri[k]] += a / 3.0;
    }
    return area;
}

}  // namespace ngi
