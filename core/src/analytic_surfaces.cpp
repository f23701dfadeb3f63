// Analytic geometry images: octahedral sphere (Praun & Hoppe 2003, section 4) and a rippled
// torus. Normals come from the exact surface (sphere) or central differences of it (torus).
#include "ngi/analytic_surfaces.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <functional>

namespace ngi {
namespace {

constexpr float kPi = 3.14159265358979f;

glm::vec3 octahedralSphere(float u, float v)
{
    const float ex = 2.0f * u - 1.0f, ey = 2.0f * v - 1.0f;
    glm::vec3 n(ex, ey, 1.0f - std::abs(ex) - std::abs(ey));
    if (n.z < 0.0f) {
        n.x = (1.0f - std::abs(ey)) * (ex >= 0.0f ? 1.0f : -1.0f);
        n.y = (1.0f - std::abs(ex)) * (ey >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::normalize(n);
}

AnalyticSurface sample(uint32_t size, const std::function<glm::vec3(float, float)>& surface, bool periodicNormals)
{
    if (size < 2) throw Error("analytic surface: needs at least 2 samples per side");
    AnalyticSurface s{GeometryImage(size), GeometryImage(size)};
    const float h = 1e-3f;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const float u = float(x) / float(size - 1), v = float(y) / float(size - 1);
            s.positions.at(x, y) = surface(u, v);
            if (periodicNormals) {
                const glm::vec3 du = surface(u + h, v) - surface(u - h, v);
                const glm::vec3 dv = surface(u, v + h) - surface(u, v - h);
                s.normals.at(x, y) = glm::normalize(glm::cross(du, dv));
            }
        }
    return s;
}

// Both images welded to `seams`, drawn down to the 5 x 5 level (coarser grids of a closed
// surface fold onto themselves).
void setSeams(AnalyticSurface& s, std::vector<SeamSegment> segments)
{
    const uint32_t levels = mipLevelCount(s.positions.size);
    s.seams.matched = true;
    s.seams.segments = std::move(segments);
    s.seams.coarsestWatertightLevel = seamAlignedLevel(s.seams.segments, seamLevelLimit(levels));
    const std::vector<uint32_t> table = seamWeldTable(s.seams, s.positions.size - 1);
    weldSeams(s.positions, table);
    weldSeams(s.normals, table);
}

}  // namespace

AnalyticSurface sphereGeometryImage(uint32_t size)
{
    AnalyticSurface s = sample(
        size, [](float u, float v) { return glm::vec3(0.5f) + 0.5f * octahedralSphere(u, v); }, false);
    for (size_t i = 0; i < s.positions.texels.size(); ++i)
        s.normals.texels[i] = glm::normalize(s.positions.texels[i] - glm::vec3(0.5f));
    if (isNestedGridSize(size) && size >= 3) {
        const uint32_t r = size - 1, h = r / 2;
        setSeams(s, {{0, h, h}, {r, r + h, h}, {2 * r, 2 * r + h, h}, {3 * r, 3 * r + h, h}});
    }
    return s;
}

AnalyticSurface rippledTorusGeometryImage(uint32_t size, float ripple)
{
    // Unnormalized torus spans x, z in [-(R + r_max), R + r_max], y in [-r_max, r_max].
    const float major = 1.0f, tube = 0.35f;
    const float extent = major + tube + std::abs(ripple);
    auto torus = [=](float u, float v) {
        const float a = 2.0f * kPi * u, b = 2.0f * kPi * v;
        const float r = tube + ripple * std::sin(5.0f * a) * std::sin(3.0f * b);
        const glm::vec3 p((major + r * std::cos(b)) * std::cos(a), r * std::sin(b),
                          (major + r * std::cos(b)) * std::sin(a));
        // Uniform scale: the longest side (2 * extent) maps to [0, 1], centred.
        return glm::vec3(0.5f) + p / (2.0f * extent);
    };
    AnalyticSurface s = sample(size, torus, true);
    // Outward orientation: the normal at the outer equator must point away from the axis.
    const glm::vec3 p = s.positions.at(0, 0), n = s.normals.at(0, 0);
    if (glm::dot(n, glm::vec3(p.x - 0.5f, 0.0f, p.z - 0.5f)) < 0.0f)
        for (auto& m : s.normals.texels) m = -m;
    if (isNestedGridSize(size) && size >= 2) {
        const uint32_t r = size - 1;
        setSeams(s, {{0, 2 * r, r}, {r, 3 * r, r}});
    }
    return s;
}

Asset makeAnalyticAsset(const std::string& name, const AnalyticSurface& surface, uint32_t storedLevel)
{
    Asset a;
    a.sourceName = "analytic:" + name;
    a.parameterization = "analytic";
    a.metadataJson = "{\"source\":\"analytic:" + name + "\"}";
    AssetChart& chart = a.charts.emplace_back();
    chart.fullResolution = surface.positions.size - 1;
    chart.storedLevel = storedLevel;
    storeGeometryImage(chart, downsampleNested(surface.positions, storedLevel),
                       downsampleNested(surface.normals, storedLevel));
    chart.seams = surface.seams;
    return a;
}

}  // namespace ngi
