// Pooled GPU memory: a surface's ~3L images (levels, geomorph targets, quad diagonals) share
// few VkDeviceMemory allocations (ImagePool), so a host can hold thousands of charts within
// Vulkan's guaranteed 4096 live allocations.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

namespace {

using HostMemoryTest = VulkanTest;

TEST_F(HostMemoryTest, ASurfaceHoldsFewAllocations)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(129);
    ngi::vk::GeometryImageSurface surface(renderer(), s.positions, s.normals, s.positions.size);
    const uint32_t levels = surface.levelCount();
    ASSERT_EQ(levels, ngi::mipLevelCount(129));
    // 3L - 1 images in two allocations (level 0's apart), plus the upload until it is released.
    EXPECT_LE(surface.deviceAllocationCount(), 3u);
    context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    EXPECT_LE(surface.deviceAllocationCount(), 2u);
    // The allocation holds at least every image's texels (16 bytes each).
    VkDeviceSize texels = 0;
    for (uint32_t l = 0; l < levels; ++l) {
        const VkDeviceSize n = surface.levelSize(l);
        texels += n * n + (l + 1 < levels ? n * n : 0) + (n - 1) * (n - 1);
    }
    EXPECT_GE(surface.gpuBytes(), 16 * texels);
    EXPECT_LT(surface.gpuBytes(), 2 * 16 * texels);
    // The images bound at offsets are distinct memory: a level and the coarsest level read
    // back what the build wrote (the stored level's samples are exact).
    const auto texelsAt0 = surface.readLevel(0, false);
    ASSERT_EQ(texelsAt0.size(), size_t(129) * 129);
    const auto coarsest = surface.readLevel(levels - 1, false);
    ASSERT_EQ(coarsest.size(), size_t(surface.levelSize(levels - 1)) * surface.levelSize(levels - 1));
    // Corner (0, 0) is the same sample at every nested level.
    EXPECT_EQ(texelsAt0[0], coarsest[0]);
    EXPECT_NE(texelsAt0[0], texelsAt0[129 * 64 + 64]);
}

TEST_F(HostMemoryTest, AnAssetHoldsFewAllocationsPerChart)
{
    const ngi::Asset asset = ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(129), 2);
    ngi::vk::AssetSurface surface(renderer(), asset);
    surface.build();
    // Two for the images, one for the seam's weld pairs.
    for (size_t c = 0; c < surface.chartCount(); ++c) EXPECT_LE(surface.chart(c).deviceAllocationCount(), 3u) << c;
}

TEST_F(HostMemoryTest, ReleasingTheFinestLevelFreesMostMemoryAndDrawsLevelOne)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(129);
    ngi::vk::GeometryImageSurface surface(renderer(), s.positions, s.normals, s.positions.size);
    EXPECT_THROW(surface.releaseFinestLevel(), ngi::Error);  // not built yet
    context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30, 20, 1.0f);
    ngi::vk::OffscreenTarget target(renderer(), 96, 96);
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.mode = ngi::vk::ShadingMode::Lod;
    auto frame = [&](float lod, bool batched) {
        p.lod = lod;
        ngi::vk::DrawBatch batch(renderer(), 1);
        batch.add(surface, glm::mat4(1.0f), lod);
        ngi::vk::BatchParams bp;
        bp.viewProjection = p.viewProjection;
        bp.eye = p.eye;
        bp.mode = p.mode;
        return target.render(
            [&](VkCommandBuffer cmd) {
                if (batched)
                    batch.record(cmd, bp, target.extent());
                else
                    renderer().recordDraw(cmd, surface, p, target.extent());
            },
            {0, 0, 0, 1});
    };
    const auto levelOne = frame(1.0f, false), levelZero = frame(0.0f, false);
    ASSERT_NE(levelOne, levelZero);
    const VkDeviceSize before = surface.gpuBytes();
    surface.releaseFinestLevel();
    EXPECT_EQ(surface.finestLevel(), 1u);
    // Level 0 of a 129^2 surface holds 129^2 + 129^2 + 128^2 of the 3L - 1 images' texels (~74%).
    EXPECT_LT(surface.gpuBytes(), before * 3 / 10);
    EXPECT_EQ(surface.deviceAllocationCount(), 1u);
    EXPECT_THROW(surface.readLevel(0, false), ngi::Error);
    EXPECT_EQ(surface.readLevel(1, false).size(), size_t(65) * 65);
    // LoD 0 now draws level 1, single or batched; coarser LoDs are unchanged.
    EXPECT_EQ(frame(0.0f, false), levelOne);
    EXPECT_EQ(frame(0.0f, true), levelOne);
    EXPECT_EQ(frame(1.0f, false), levelOne);
    ngi::vk::DrawParams grid = p;
    grid.gridSize = 129;
    EXPECT_THROW(target.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, grid, target.extent()); },
                               {0, 0, 0, 1}),
                 ngi::Error);
}

}  // namespace
