// The GPU seam weld (shaders/seam_weld.comp): after the network's or the bilinear restore,
// every mate pair of every level down to the coarsest watertight one is bitwise equal, as
// the CPU mirror (ngi::weldSeams) makes it; without a seam the network's two sides differ.
#include "vulkan_fixture.h"

#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/mip_pyramid.h"
#include "ngi/seam.h"
#include "tiny_network.h"

#include <cmath>

namespace {

constexpr uint32_t kResolution = 64;

// A cylinder around z: row y = 0 and row y = R are the same circle (the seam), the first
// and last columns its two boundary loops.
void cylinder(ngi::GeometryImage& positions, ngi::GeometryImage& normals) {
    const uint32_t n = kResolution + 1;
    positions = ngi::GeometryImage(n);
    normals = ngi::GeometryImage(n);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const double a = 2.0 * M_PI * double(y % kResolution) / kResolution;
            positions.at(x, y) = {0.5 + 0.4 * std::cos(a), 0.5 + 0.4 * std::sin(a), double(x) / kResolution};
            normals.at(x, y) = {std::cos(a), std::sin(a), 0.0};
        }
}

ngi::ChartSeams cylinderSeam() {
    ngi::ChartSeams seams;
    seams.matched = true;
    seams.coarsestWatertightLevel = 4;
    seams.segments = {{0, 2 * kResolution, kResolution}};  // bottom row forward = top row backward
    return seams;
}

// Mate pairs of `level` whose texels (position bits and packed normal) differ.
size_t unequalMates(const ngi::vk::GeometryImageSurface& surface, uint32_t level) {
    const std::vector<glm::uvec4> texels = surface.readLevel(level, false);
    const uint32_t size = surface.levelSize(level);
    const std::vector<uint32_t> table = ngi::seamWeldTable(cylinderSeam(), kResolution, level);
    size_t unequal = 0;
    for (uint32_t t = 0; t < table.size(); ++t) {
        const glm::uvec2 a = ngi::perimeterSample(size - 1, t), b = ngi::perimeterSample(size - 1, table[t]);
        if (texels[size_t(a.y) * size + a.x] != texels[size_t(b.y) * size + b.x]) ++unequal;
    }
    return unequal;
}

class SeamWeld : public VulkanTest {};

TEST_F(SeamWeld, NetworkRestoreIsWeldedAtEveryDrawnLevel) {
    ngi::GeometryImage positions, normals;
    cylinder(positions, normals);
    const ngi::GeometryImage p2 = ngi::downsampleNested(positions, 2), n2 = ngi::downsampleNested(normals, 2);
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("weld", 11, 0.05f);
    ngi::vk::SuperResolution sr(context(), net);

    ngi::vk::GeometryImageSurface open(renderer(), p2, n2, kResolution + 1);
    context().submitAndWait([&](VkCommandBuffer cmd) { open.recordBuild(cmd, &sr); });
    EXPECT_GT(unequalMates(open, 0), 8u) << "the network's two sides should differ before the weld";
    EXPECT_EQ(open.drawnLevelCount(), open.levelCount());

    ngi::vk::GeometryImageSurface welded(renderer(), p2, n2, kResolution + 1, cylinderSeam());
    context().submitAndWait([&](VkCommandBuffer cmd) { welded.recordBuild(cmd, &sr); });
    EXPECT_EQ(welded.weldedLevelCount(), 2u);  // the restored levels 0, 1 (the network writes 0, 1 is its subsample)
    EXPECT_EQ(welded.drawnLevelCount(), 5u);   // down to the 5 x 5 level
    for (uint32_t level = 0; level < welded.drawnLevelCount(); ++level)
        EXPECT_EQ(unequalMates(welded, level), 0u) << "level " << level;
    // The weld touches the border only: an interior texel equals the unwelded restore's.
    EXPECT_EQ(welded.readLevel(0, false)[size_t(20) * 65 + 30], open.readLevel(0, false)[size_t(20) * 65 + 30]);
}

TEST_F(SeamWeld, BilinearRestoreIsWeldedAtEveryRestoredLevel) {
    ngi::GeometryImage positions, normals;
    cylinder(positions, normals);
    const ngi::GeometryImage p3 = ngi::downsampleNested(positions, 3), n3 = ngi::downsampleNested(normals, 3);
    ngi::vk::GeometryImageSurface welded(renderer(), p3, n3, kResolution + 1, cylinderSeam());
    context().submitAndWait([&](VkCommandBuffer cmd) { welded.recordBuild(cmd, nullptr); });
    EXPECT_EQ(welded.weldedLevelCount(), 3u);  // levels 0, 1, 2 are restored from level 3
    for (uint32_t level = 0; level < welded.drawnLevelCount(); ++level)
        EXPECT_EQ(unequalMates(welded, level), 0u) << "level " << level;
}

} // namespace
