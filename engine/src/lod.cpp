// LoD from projected geometric error (see lod.h for the metric and its sources).
#include "ngi/engine/lod.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/printable_text.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace ngi {
namespace {

// The point at (fx, fy) in [0,1]^2 of quad (a, b, c, d) (counter-clockwise from (0,0)) on
// the two triangles the renderer draws: split along the shorter diagonal, ties a-c
// (lod_grid.h). Coarser levels are not geomorphed here: integer levels only.
glm::vec3 onQuad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, float fx, float fy)
{
    const glm::vec3 ac = c - a, bd = d - b;
    if (glm::dot(ac, ac) <= glm::dot(bd, bd))
        return fx >= fy ? a + fx * (b - a) + fy * (c - b) : a + fx * (c - d) + fy * (d - a);
    return fx + fy <= 1.0f ? a + fx * (b - a) + fy * (d - a) : c + (1.0f - fx) * (d - c) + (1.0f - fy) * (b - c);
}

// Largest distance from the stored samples to the triangles of the level `step` times coarser
// (a nested subsample: every step-th sample), normalized units.
float nestedError(const GeometryImage& stored, uint32_t step)
{
    const uint32_t n = stored.size;
    float worst = 0.0f;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t x0 = std::min(x / step * step, n - 1 - step), y0 = std::min(y / step * step, n - 1 - step);
            const float fx = float(x - x0) / float(step), fy = float(y - y0) / float(step);
            const glm::vec3 p = onQuad(stored.at(x0, y0), stored.at(x0 + step, y0), stored.at(x0 + step, y0 + step),
                                       stored.at(x0, y0 + step), fx, fy);
            worst = std::max(worst, glm::length(p - stored.at(x, y)));
        }
    return worst;
}

float meanEdge(const GeometryImage& stored, uint32_t step)
{
    double sum = 0.0;
    size_t count = 0;
    for (uint32_t a = 0; a < stored.size; a += step)
        for (uint32_t b = 0; b + step < stored.size; b += step) {
            sum += glm::length(stored.at(b + step, a) - stored.at(b, a)) +
                glm::length(stored.at(a, b + step) - stored.at(a, b));
            count += 2;
        }
    return count ? float(sum / double(count)) : 0.0f;
}

}  // namespace

AssetLodMetrics measureLodMetrics(const Asset& asset)
{
    if (asset.charts.empty()) throw Error("LoD metrics: asset '" + printableText(asset.sourceName) + "' has no chart");
    AssetLodMetrics m;
    // Uniform de-normalization (asset.h); the largest axis bounds any anisotropic one.
    const float scale = std::max({std::abs(asset.scale.x), std::abs(asset.scale.y), std::abs(asset.scale.z)});
    const uint32_t assetLevels = mipLevelCount(asset.fullResolution() + 1);
    m.geometricError.assign(assetLevels, 0.0f);
    m.edgeLength.assign(assetLevels, 0.0f);
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    const int largest = std::countr_zero(asset.fullResolution());
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        const AssetChart& chart = asset.charts[c];
        const GeometryImage stored = storedPositions(chart);
        for (const glm::vec3& p : stored.texels) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const uint32_t levels = mipLevelCount(chart.fullSize());
        std::vector<float> error(levels, 0.0f), edge(levels, 0.0f);
        for (uint32_t l = chart.storedLevel; l < levels; ++l) {
            const uint32_t step = 1u << (l - chart.storedLevel);
            error[l] = l == chart.storedLevel ? 0.0f : nestedError(stored, step) * scale;
            edge[l] = meanEdge(stored, step) * scale;
        }
        // The stored level and finer ones: the h^2 law from the first measured level (the
        // stored level's own distance to the full resolution is the restoration's detail).
        for (uint32_t l = std::min(chart.storedLevel + 1, levels - 1); l-- > 0;) {
            if (l <= chart.storedLevel) error[l] = error[l + 1] * 0.25f;
            if (l < chart.storedLevel) edge[l] = edge[l + 1] * 0.5f;
        }
        error[0] = 0.0f;  // level 0 is the full resolution
        // Asset level L draws chart level clamp(L - shift) (AssetSurface::recordDraw).
        const int shift = largest - std::countr_zero(chart.fullResolution);
        for (uint32_t L = 0; L < assetLevels; ++L) {
            const uint32_t l = uint32_t(std::clamp(int(L) - shift, 0, int(levels) - 1));
            m.geometricError[L] = std::max(m.geometricError[L], error[l]);
            if (c == 0) m.edgeLength[L] = edge[l];
        }
    }
    // Non-decreasing (a periodic chart's 2x2 level can collapse to one point: edge 0).
    for (size_t L = 1; L < m.geometricError.size(); ++L) {
        m.geometricError[L] = std::max(m.geometricError[L], m.geometricError[L - 1]);
        m.edgeLength[L] = std::max(m.edgeLength[L], m.edgeLength[L - 1]);
    }
    m.boundsMin = asset.offset + asset.scale * lo;
    m.boundsMax = asset.offset + asset.scale * hi;
    return m;
}

float pixelsPerUnit(const glm::mat4& viewProjection, glm::vec3 worldPoint, float viewportHeight)
{
    const float w = (viewProjection * glm::vec4(worldPoint, 1.0f)).w;
    if (!(w > 0.0f)) return std::numeric_limits<float>::infinity();
    const glm::vec3 rowY(viewProjection[0][1], viewProjection[1][1], viewProjection[2][1]);
    return 0.5f * viewportHeight * glm::length(rowY) / w;
}

float lodForScreenError(std::span<const float> levelError, float pixelsPerUnit, float maxErrorPixels)
{
    if (levelError.empty() || !(pixelsPerUnit < std::numeric_limits<float>::infinity())) return 0.0f;
    const float budget = maxErrorPixels / std::max(pixelsPerUnit, 1e-30f);  // object-space error allowed
    if (levelError[0] > budget) return 0.0f;
    size_t l = 0;
    while (l + 1 < levelError.size() && levelError[l + 1] <= budget) ++l;
    if (l + 1 == levelError.size()) return float(l);
    const float e0 = levelError[l], e1 = levelError[l + 1];
    const float t = e0 > 0.0f ? std::log2(budget / e0) / std::log2(e1 / e0) : (budget - e0) / (e1 - e0);
    return float(l) + std::clamp(t, 0.0f, 1.0f);
}

float instanceLod(const AssetLodMetrics& metrics, std::span<const float> levelError, const glm::mat4& viewProjection,
                  const glm::mat4& world, float viewportHeight, float maxErrorPixels)
{
    const glm::vec3 centre = glm::vec3(world * glm::vec4(0.5f * (metrics.boundsMin + metrics.boundsMax), 1.0f));
    const float stretch = std::max(
        {glm::length(glm::vec3(world[0])), glm::length(glm::vec3(world[1])), glm::length(glm::vec3(world[2]))});
    const float radius = 0.5f * glm::length(metrics.boundsMax - metrics.boundsMin) * stretch;
    // Clip w is linear in the world position: its smallest value over the sphere.
    const glm::vec3 gradW(viewProjection[0][3], viewProjection[1][3], viewProjection[2][3]);
    const float wCentre = (viewProjection * glm::vec4(centre, 1.0f)).w;
    const float wNear = wCentre - radius * glm::length(gradW);
    if (!(wNear > 0.0f)) return 0.0f;
    const glm::vec3 rowY(viewProjection[0][1], viewProjection[1][1], viewProjection[2][1]);
    const float perUnit = 0.5f * viewportHeight * glm::length(rowY) / wNear;
    // The error is object-space: a world matrix that scales the instance scales it too.
    return lodForScreenError(levelError, perUnit * stretch, maxErrorPixels);
}

}  // namespace ngi
