// The LoD helper (ngi/engine/lod.h): per-level error of an asset, projected pixels per unit,
// the LoD for an error budget, and the viewer's "pixels per edge" rule as a special case.
#include "ngi/analytic_surfaces.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/lod.h"

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

// ngi-view's rule before the helper (engine/viewer/loaded_asset.cpp, autoLod): a grid of
// N vertices at LoD F has (full - 1) / 2^F cells across the surface's span.
float viewerRule(float span, uint32_t fullSize, uint32_t levels, float distance, float fovY, float height, float ppe)
{
    const float pixelsPerUnit = height / (2.0f * distance * std::tan(glm::radians(fovY) * 0.5f));
    const float cells = span * pixelsPerUnit / ppe;
    return std::clamp(std::log2(float(fullSize - 1) / cells), 0.0f, float(levels - 1));
}

TEST(Lod, PixelsPerEdgeRuleMatchesTheViewers)
{
    const uint32_t full = 1025, levels = 10;
    const float span = 0.8f;
    std::vector<float> edges(levels);
    for (uint32_t l = 0; l < levels; ++l) edges[l] = span * float(1u << l) / float(full - 1);
    ngi::vk::OrbitCamera camera;
    for (float distance : {0.05f, 0.3f, 1.0f, 2.5f, 9.0f, 80.0f})
        for (float ppe : {1.0f, 4.0f, 12.0f}) {
            camera.distance = distance;
            const float ppu = ngi::pixelsPerUnit(camera.viewProjection(1.5f), camera.target, 720.0f);
            EXPECT_NEAR(ppu, 720.0f / (2.0f * distance * std::tan(glm::radians(camera.fovYDegrees) * 0.5f)),
                        ppu * 1e-5f);
            EXPECT_NEAR(ngi::lodForScreenError(edges, ppu, ppe),
                        viewerRule(span, full, levels, distance, camera.fovYDegrees, 720.0f, ppe), 1e-4f)
                << "distance " << distance << " ppe " << ppe;
        }
}

TEST(Lod, SphereErrorFollowsTheSagitta)
{
    // A sphere of radius 0.5 normalized, scaled to radius 2 in object space: a level of edge
    // h deviates from the sphere by about the sagitta h^2 / (8 R), quadrupling per level.
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(257), 2);
    asset.scale = glm::vec3(4.0f);
    asset.offset = glm::vec3(1.0f, 2.0f, 3.0f);
    const ngi::AssetLodMetrics m = ngi::measureLodMetrics(asset);
    ASSERT_EQ(m.geometricError.size(), 9u);
    EXPECT_NEAR(m.boundsMin.x, 1.0f, 1e-3f);
    EXPECT_NEAR(m.boundsMax.z, 7.0f, 1e-3f);
    EXPECT_EQ(m.geometricError[0], 0.0f);
    for (size_t l = 1; l < m.geometricError.size(); ++l) EXPECT_GE(m.geometricError[l], m.geometricError[l - 1]);
    for (uint32_t l = 3; l <= 5; ++l) {
        const float ratio = m.geometricError[l + 1] / m.geometricError[l];
        EXPECT_GT(ratio, 2.5f) << l;
        EXPECT_LT(ratio, 5.5f) << l;
        const float sagitta = m.edgeLength[l] * m.edgeLength[l] / (8.0f * 2.0f);
        EXPECT_GT(m.geometricError[l], 0.5f * sagitta) << l;
        EXPECT_LT(m.geometricError[l], 6.0f * sagitta) << l;
    }
    // At and below the stored level (2) the error is extrapolated (h^2), the edges halve.
    EXPECT_FLOAT_EQ(m.geometricError[2], m.geometricError[3] * 0.25f);
    EXPECT_FLOAT_EQ(m.geometricError[1], m.geometricError[2] * 0.25f);
    EXPECT_GT(m.geometricError[1], 0.0f);
    EXPECT_FLOAT_EQ(m.edgeLength[1], m.edgeLength[2] * 0.5f);
}

TEST(Lod, InstanceLodIsInvariantUnderScaleAndDistance)
{
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(129), 2);
    const ngi::AssetLodMetrics m = ngi::measureLodMetrics(asset);
    ngi::vk::OrbitCamera camera;
    camera.target = glm::vec3(0.0f);
    camera.distance = 1.0f;
    camera.nearPlane = 0.01f;
    const glm::mat4 vp = camera.viewProjection(1.0f);
    auto lodAt = [&](float z, float scale) {
        const glm::mat4 world = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -z)), glm::vec3(scale));
        return ngi::instanceLod(m, m.geometricError, vp, world, 720.0f, 1.0f);
    };
    float previous = -1.0f;
    for (float z : {1.0f, 3.0f, 8.0f, 30.0f}) {
        const float lod = lodAt(z, 1.0f);
        EXPECT_GE(lod, previous) << z;  // further: coarser
        previous = lod;
    }
    EXPECT_GT(previous, 1.0f);
    // Twice as large, twice as far (nearest point too): the same LoD.
    EXPECT_NEAR(lodAt(8.0f, 1.0f), lodAt(16.0f + 1.0f, 2.0f), 0.03f);
    EXPECT_EQ(lodAt(-1.0f, 1.0f), 0.0f);  // the eye inside the bounds
    // An error budget twice as large: one level coarser at most, never finer.
    const glm::mat4 world = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -8));
    const float a = ngi::instanceLod(m, m.geometricError, vp, world, 720.0f, 1.0f);
    const float b = ngi::instanceLod(m, m.geometricError, vp, world, 720.0f, 2.0f);
    EXPECT_GE(b, a);
    EXPECT_LE(b, a + 1.0f);
}

}  // namespace
