// ngi engine: choosing an instance's level of detail from its projected geometric error.
//
// Once per asset, on the CPU: object-space bounds and, per asset level, an object-space
// geometric error and the mean grid edge length (AssetLodMetrics). Per instance per frame:
// the pixels one object-space unit covers at the instance's nearest point (pixelsPerUnit)
// turn an error budget in pixels into the coarsest continuous LoD whose error stays within
// it (lodForScreenError). The rule is the classic screen-space error metric of view-dependent
// LoD (Lindstrom et al. 1996, "Real-time, continuous level of detail rendering of height
// fields"; Luebke et al. 2003, "Level of Detail for 3D Graphics", ch. 4), with levels
// interpolated log-linearly so the LoD is continuous (geomorphs, lod_grid.h).
// CPU only, no Vulkan: namespace ngi, not ngi::vk.
#pragma once

#include "ngi/asset.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <span>
#include <vector>

namespace ngi {

struct AssetLodMetrics {
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // object space: every chart's stored samples
    // [asset level] object-space bound of the distance from the surface drawn at that level
    // to the full-resolution one, non-decreasing, [0] = 0. Levels coarser than a chart's
    // stored level: the largest distance from a stored sample to the level's triangles at
    // the same uv (the surface drawn, split along the shorter diagonal; measured). The
    // stored level and finer ones differ from the full resolution by the restoration's
    // detail, which the CPU does not see: the first measured error falls by 4 per finer
    // level (the h^2 law of a piecewise-linear approximation of a smooth surface; an
    // assumption, not a measurement). The asset's error at a level is the largest of its
    // charts' at the levels they draw.
    std::vector<float> geometricError;
    // [asset level] mean object-space edge length of chart 0's grid (the largest chart):
    // measured at and coarser than its stored level, halving per finer level; non-decreasing.
    std::vector<float> edgeLength;
};

// Measures the asset on the CPU from its stored levels (about 10 ns per stored sample and
// level; no GPU work). ngi::Error for an asset without charts.
AssetLodMetrics measureLodMetrics(const Asset& asset);

// Pixels covered by one world-space unit, perpendicular to the view, at `worldPoint`, in a
// viewport `viewportHeight` pixels high: 0.5 * height * |row y of viewProjection| / w.
// Perspective and orthographic projections; +infinity at or behind the eye (w <= 0).
float pixelsPerUnit(const glm::mat4& viewProjection, glm::vec3 worldPoint, float viewportHeight);

// The coarsest continuous LoD in [0, levelError.size() - 1] whose error, projected with
// `pixelsPerUnit`, is at most `maxErrorPixels`; between levels the error is interpolated
// log-linearly (linearly from a zero error). `levelError` must be non-decreasing (e.g.
// AssetLodMetrics::geometricError or ::edgeLength, for a "pixels per edge" rule).
float lodForScreenError(std::span<const float> levelError, float pixelsPerUnit, float maxErrorPixels);

// One instance: its object-space bounds' sphere placed by `world` (object -> world), its
// nearest point to the eye (along clip w), and lodForScreenError of `levelError` there.
// LoD 0 when the eye is inside the sphere.
float instanceLod(const AssetLodMetrics& metrics, std::span<const float> levelError, const glm::mat4& viewProjection,
                  const glm::mat4& world, float viewportHeight, float maxErrorPixels);

}  // namespace ngi
