// Rendering the geometry-image grid: analytic silhouette, triangle counts, continuous LoD.
#include "uv_colour.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace {

constexpr uint32_t kSize = 256;
const glm::vec4 kClear{0.0f, 0.0f, 0.0f, 1.0f};

struct Scene {
    ngi::vk::OrbitCamera camera;
    float aspect = 1.0f;
};

ngi::vk::GeometryImageSurface build(const ngi::vk::Renderer& r, const ngi::AnalyticSurface& s)
{
    ngi::vk::GeometryImageSurface surface(r, s.positions, s.normals, s.positions.size);
    r.context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    return surface;
}

std::vector<uint8_t> draw(const ngi::vk::Renderer& r, ngi::vk::OffscreenTarget& target,
                          const ngi::vk::GeometryImageSurface& surface, const ngi::vk::OrbitCamera& camera, float lod,
                          uint32_t grid = 0, ngi::vk::ShadingMode mode = ngi::vk::ShadingMode::Shaded)
{
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.lod = lod;
    p.gridSize = grid;
    p.mode = mode;
    return target.render([&](VkCommandBuffer cmd) { r.recordDraw(cmd, surface, p, target.extent()); }, kClear);
}

size_t coveredPixels(const std::vector<uint8_t>& rgba)
{
    size_t n = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) n += (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
    return n;
}

double meanAbsDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b)
{
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(int(a[i]) - int(b[i]));
    return sum / double(a.size());
}

using Render = VulkanTest;

TEST_F(Render, SphereSilhouetteMatchesAnalyticArea)
{
    // Sphere of radius 0.5 seen from distance d: its silhouette is a circle of angular radius
    // asin(r / d), i.e. tan(asin(r / d)) / tan(fovY / 2) * (H / 2) pixels.
    auto surface = build(renderer(), ngi::sphereGeometryImage(129));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    ngi::vk::OrbitCamera camera;
    camera.target = glm::vec3(0.5f);
    camera.distance = 2.0f;
    camera.yawDegrees = 23.0f;
    camera.pitchDegrees = 17.0f;
    const double alpha = std::asin(0.5 / camera.distance);
    const double radiusPixels = std::tan(alpha) / std::tan(glm::radians(camera.fovYDegrees) * 0.5) * (kSize / 2.0);
    const double expected = M_PI * radiusPixels * radiusPixels;
    // Level 0 (129^2 samples) is within 1% (pixel quantization of the edge); coarser grids are
    // inscribed polyhedra, so the area only shrinks, and stays within 3% down to 33^2 samples.
    const double area0 = double(coveredPixels(draw(renderer(), target, surface, camera, 0.0f)));
    EXPECT_NEAR(area0 / expected, 1.0, 0.01);
    double previous = area0;
    for (float lod : {1.0f, 2.0f}) {
        const double area = double(coveredPixels(draw(renderer(), target, surface, camera, lod)));
        EXPECT_NEAR(area / expected, 1.0, 0.03) << "lod " << lod;
        EXPECT_LE(area, previous * 1.002) << "lod " << lod;
        previous = area;
    }
    // The coarsest grids are far from round: a 3x3 octahedral grid is an octahedron.
    const double octahedron = double(coveredPixels(draw(renderer(), target, surface, camera, 6.0f)));
    EXPECT_LT(octahedron / expected, 0.85);
}

TEST_F(Render, TriangleCountPerGridSize)
{
    if (!context().pipelineStatistics) GTEST_SKIP() << "device has no pipeline statistics queries";
    auto surface = build(renderer(), ngi::rippledTorusGeometryImage(65));
    ngi::vk::OffscreenTarget target(renderer(), 64, 64);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 0, 30, 1.0f);
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    info.queryCount = 1;
    info.pipelineStatistics = VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_PRIMITIVES_BIT;
    VkQueryPool pool = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateQueryPool(context().device, &info, nullptr, &pool));
    for (uint32_t grid : {2u, 3u, 7u, 33u, 50u, 65u}) {
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(1.0f);
        p.eye = camera.eye();
        p.gridSize = grid;
        ngi::vk::DrawStats stats;
        target.render(
            [&](VkCommandBuffer cmd) {
                vkCmdBeginQuery(cmd, pool, 0, 0);
                stats = renderer().recordDraw(cmd, surface, p, target.extent());
                vkCmdEndQuery(cmd, pool, 0);
            },
            kClear, [&](VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, pool, 0, 1); });
        uint64_t primitives = 0;
        NGI_VK_CHECK(vkGetQueryPoolResults(context().device, pool, 0, 1, sizeof(primitives), &primitives,
                                           sizeof(primitives), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        EXPECT_EQ(primitives, 2ull * (grid - 1) * (grid - 1)) << "grid " << grid;
        EXPECT_EQ(stats.triangles, ngi::gridTriangleCount(grid));
    }
    vkDestroyQueryPool(context().device, pool, nullptr);
}

TEST_F(Render, ContinuousLodNeverPops)
{
    auto surface = build(renderer(), ngi::rippledTorusGeometryImage(129, 0.08f));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 20, 35, 1.0f);
    // A whole level step changes the picture visibly; this is the scale a pop would have.
    const double levelStep = meanAbsDifference(draw(renderer(), target, surface, camera, 3.0f),
                                               draw(renderer(), target, surface, camera, 4.0f));
    EXPECT_GT(levelStep, 0.5);
    // Crossing an integer LoD from below (fine grid fully morphed) to the coarse grid itself:
    // the same surface, so the frames agree up to rasterization of sliver triangles.
    for (float level : {1.0f, 3.0f, 4.0f}) {
        const double across = meanAbsDifference(draw(renderer(), target, surface, camera, level - 1e-4f),
                                                draw(renderer(), target, surface, camera, level));
        EXPECT_LT(across, levelStep * 0.05) << "pop at lod " << level;
    }
    // Small LoD steps make small changes, proportional to the step.
    const auto a = draw(renderer(), target, surface, camera, 3.30f);
    const auto b = draw(renderer(), target, surface, camera, 3.32f);
    EXPECT_LT(meanAbsDifference(a, b), levelStep * 0.1);
}

TEST_F(Render, AllShadingModesDrawTheSurface)
{
    auto surface = build(renderer(), ngi::sphereGeometryImage(33));
    ngi::vk::OffscreenTarget target(renderer(), 64, 64);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 0, 0, 1.0f);
    const size_t shaded = coveredPixels(draw(renderer(), target, surface, camera, 0.0f));
    EXPECT_GT(shaded, 64u * 64u / 4);
    for (auto mode : {ngi::vk::ShadingMode::Normals, ngi::vk::ShadingMode::Wireframe, ngi::vk::ShadingMode::Lod})
        EXPECT_NEAR(double(coveredPixels(draw(renderer(), target, surface, camera, 0.0f, 0, mode))), double(shaded),
                    shaded * 0.02);
    EXPECT_THROW(ngi::vk::parseShadingMode("phong"), ngi::Error);
}

// A sphere asset whose base colour tells the uv (uv_colour.h).
ngi::Asset colouredSphere(uint32_t colorLevel)
{
    ngi::Asset asset = ngi::makeAnalyticAsset("coloured", ngi::sphereGeometryImage(129), 1);
    ngi::test::paintUvColour(asset.charts[0], colorLevel);
    return asset;
}

std::vector<uint8_t> drawAsset(const ngi::vk::AssetSurface& surface, ngi::vk::OffscreenTarget& target,
                               const ngi::vk::OrbitCamera& camera, float lod, ngi::vk::ShadingMode mode)
{
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.lod = lod;
    p.mode = mode;
    return target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); }, kClear);
}

TEST_F(Render, TheUniformDrawShowsTheBaseColourAtEveryLod)
{
    const ngi::Asset asset = colouredSphere(2);
    ngi::vk::AssetSurface surface(renderer(), asset);
    surface.build();
    ASSERT_TRUE(surface.baseColours());
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 40, 25, 1.0f);
    const auto fine = drawAsset(surface, target, camera, 0.0f, ngi::vk::ShadingMode::BaseColour);
    for (float lod : {0.0f, 3.0f}) {
        const auto frame = drawAsset(surface, target, camera, lod, ngi::vk::ShadingMode::BaseColour);
        size_t covered = 0, differ = 0;
        int lowRed = 255, highRed = 0, lowGreen = 255, highGreen = 0;
        for (size_t i = 0; i < frame.size(); i += 4) {
            if (frame[i] == 0 && frame[i + 1] == 0 && frame[i + 2] == 0) continue;
            ++covered;
            // Unlit: the image's own blue (64; sRGB filtering keeps a constant, up to rounding).
            ASSERT_NEAR(int(frame[i + 2]), 64, 1) << "LoD " << lod << ", pixel " << i / 4;
            lowRed = std::min<int>(lowRed, frame[i]), highRed = std::max<int>(highRed, frame[i]);
            lowGreen = std::min<int>(lowGreen, frame[i + 1]), highGreen = std::max<int>(highGreen, frame[i + 1]);
            differ += std::abs(int(frame[i]) - int(fine[i])) + std::abs(int(frame[i + 1]) - int(fine[i + 1])) > 24;
        }
        ASSERT_GT(covered, size_t(kSize * kSize / 8)) << "LoD " << lod;
        EXPECT_GT(highRed - lowRed, 64) << "LoD " << lod << ": the colour follows u";
        EXPECT_GT(highGreen - lowGreen, 64) << "LoD " << lod << ": and v";
        // The colour is attached to the uv that the coarser grid interpolates: it moves with the
        // silhouette, not across the surface (at most 5% of the pixels change by more than 24).
        EXPECT_LT(double(differ) / double(covered), 0.05) << "LoD " << lod;
    }
    // Lit, the colour shows too: the shaded frame is not the grey one of the same sphere without colour.
    ngi::Asset grey = asset;
    grey.charts[0].baseColor.clear();
    ngi::vk::AssetSurface plain(renderer(), grey);
    plain.build();
    EXPECT_FALSE(plain.baseColours());
    EXPECT_GT(meanAbsDifference(drawAsset(surface, target, camera, 0.0f, ngi::vk::ShadingMode::Shaded),
                                drawAsset(plain, target, camera, 0.0f, ngi::vk::ShadingMode::Shaded)),
              5.0);
    // Without a colour the base colour is ngi's grey (0.78, 0.80, 0.84 as display values).
    const auto greyFrame = drawAsset(plain, target, camera, 0.0f, ngi::vk::ShadingMode::BaseColour);
    for (size_t i = 0; i < greyFrame.size(); i += 4) {
        if (greyFrame[i] == 0 && greyFrame[i + 1] == 0 && greyFrame[i + 2] == 0) continue;
        ASSERT_NEAR(int(greyFrame[i]), 199, 2) << "pixel " << i / 4;
        ASSERT_NEAR(int(greyFrame[i + 2]), 214, 2) << "pixel " << i / 4;
    }
}

TEST_F(Render, TheBaseColoursAlphaCutsTheSurfaceOut)
{
    ngi::Asset asset = colouredSphere(2);
    ngi::vk::AssetSurface opaque(renderer(), asset);
    opaque.build();
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(opaque.boundsMin(), opaque.boundsMax(), 40, 25, 1.0f);
    const auto opaqueFrame = drawAsset(opaque, target, camera, 0.0f, ngi::vk::ShadingMode::BaseColour);
    const size_t whole = coveredPixels(opaqueFrame);
    ASSERT_GT(whole, size_t(kSize * kSize / 8));
    // The cut: alpha 0 where u is below the median u the frame shows (red = 255 u).
    std::vector<int> reds;
    for (size_t i = 0; i < opaqueFrame.size(); i += 4)
        if (opaqueFrame[i] | opaqueFrame[i + 1] | opaqueFrame[i + 2]) reds.push_back(opaqueFrame[i]);
    std::nth_element(reds.begin(), reds.begin() + reds.size() / 2, reds.end());
    const int cut = reds[reds.size() / 2];
    ASSERT_GT(cut, 40);
    ngi::test::setUvAlpha(asset.charts[0], [&](double u, double) { return 255.0 * u < cut ? 0 : 255; });
    // No pixel left shows u below the cut (but for the band of one texel, 1/32 of u, where the
    // filter blends the two): where the front is cut out, the back of the sphere or nothing shows.
    ngi::vk::AssetSurface masked(renderer(), asset);
    masked.build();
    // Only the cut-out surface is drawn with the alpha test.
    EXPECT_FALSE(opaque.chart(0).cutsOut());
    EXPECT_TRUE(masked.chart(0).cutsOut());
    std::vector<uint8_t> lod0;
    for (float lod : {0.0f, 3.0f}) {
        const auto frame = drawAsset(masked, target, camera, lod, ngi::vk::ShadingMode::BaseColour);
        if (lod == 0.0f) lod0 = frame;
        size_t covered = 0, below = 0;
        for (size_t i = 0; i < frame.size(); i += 4) {
            if (frame[i] == 0 && frame[i + 1] == 0 && frame[i + 2] == 0) continue;
            ++covered, below += frame[i] < cut - 10;
        }
        // As in the adaptive draw's test: at most 1 in 1000 where the silhouette samples a
        // coarse mip of the colour (measured: none).
        EXPECT_LE(below, covered / 1000) << "LoD " << lod;
        EXPECT_LT(covered, whole) << "LoD " << lod;
    }
    // Batched with an opaque instance (off screen), the cut-out one draws the same pixels: the
    // batch switches to the alpha test for it.
    ngi::vk::DrawBatch batch(renderer(), 4);
    batch.add(opaque, glm::translate(glm::mat4(1.0f), glm::vec3(100.0f, 0.0f, 0.0f)), 0.0f);
    batch.add(masked, glm::mat4(1.0f), 0.0f);
    const auto batched = target.render(
        [&](VkCommandBuffer cmd) {
            ngi::vk::BatchParams bp;
            bp.viewProjection = camera.viewProjection(1.0f);
            bp.eye = camera.eye();
            bp.mode = ngi::vk::ShadingMode::BaseColour;
            batch.record(cmd, bp, target.extent());
        },
        kClear);
    EXPECT_EQ(batched, lod0);
    // Alpha 1/2 everywhere covers half the pixels (hashed), within 10% of the sphere's.
    ngi::test::setUvAlpha(asset.charts[0], [](double, double) { return 128; });
    ngi::vk::AssetSurface half(renderer(), asset);
    half.build();
    const size_t halfCovered = coveredPixels(drawAsset(half, target, camera, 0.0f, ngi::vk::ShadingMode::Shaded));
    EXPECT_NEAR(double(halfCovered) / double(whole), 0.5, 0.1);
}

TEST_F(Render, ABaseColourNeedsASurfaceForTheUniformDraw)
{
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(33);
    ngi::vk::GeometryImageSurface adaptiveOnly(renderer(), sphere.positions, sphere.normals, 33, {},
                                               ngi::vk::SurfaceDraws::adaptiveOnly);
    ngi::vk::GeometryImageSurface uniform(renderer(), sphere.positions, sphere.normals, 33);
    EXPECT_THROW(adaptiveOnly.setBaseColour(VK_NULL_HANDLE, renderer().texelSampler()), ngi::Error);
    EXPECT_THROW(uniform.setBaseColour(VK_NULL_HANDLE, renderer().texelSampler()), ngi::Error);
}

TEST_F(Render, UnknownDeviceIsAClearError)
{
    try {
        ngi::vk::Context::create({.device = "no-such-gpu-xyz"});
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("Vulkan device 'no-such-gpu-xyz' not found"), std::string::npos)
            << e.what();
    }
}

}  // namespace
