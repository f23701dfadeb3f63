// Pooled GPU memory: a surface's ~3L images (levels, geomorph targets, quad diagonals) share
// few VkDeviceMemory allocations (ImagePool), so a host can hold thousands of charts within
// Vulkan's guaranteed 4096 live allocations.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/surface.h"
#include "ngi/mip_pyramid.h"

namespace {

using HostMemoryTest = VulkanTest;

TEST_F(HostMemoryTest, ASurfaceHoldsFewAllocations)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(129);
    ngi::vk::GeometryImageSurface surface(renderer(), s.positions, s.normals, s.positions.size);
    const uint32_t levels = surface.levelCount();
    ASSERT_EQ(levels, ngi::mipLevelCount(129));
    // 3L - 1 images, one allocation for all of them, plus the upload until it is released.
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
    for (size_t c = 0; c < surface.chartCount(); ++c) EXPECT_LE(surface.chart(c).deviceAllocationCount(), 2u) << c;
}

} // namespace
