// Streaming an asset into the engine (ngi/asset_prefix.h): the bytes of a format-5 file
// arrive in pieces; at every level that completes, an AssetSurface is built from the prefix
// asset and drawn in place of the previous one, with the validation layer on. A prefix draws
// the very silhouette of the full asset drawn at the prefix's level (the positions are the
// same nested level, bitwise) and nearly its shading (its normals are predicted from the
// coarse positions); once every byte is in, the frame is the full asset's.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/asset_prefix.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/offscreen.h"

#include <cmath>

namespace {

constexpr uint32_t kSize = 128;
const glm::vec4 kClear{0.0f, 0.0f, 0.0f, 1.0f};

std::vector<uint8_t> draw(ngi::vk::OffscreenTarget& target, const ngi::vk::AssetSurface& surface,
                          const ngi::vk::OrbitCamera& camera, float lod)
{
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.lod = lod;
    return target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); }, kClear);
}

ngi::vk::AssetSurface build(const ngi::vk::Renderer& r, const ngi::Asset& asset)
{
    ngi::vk::AssetSurface surface(r, asset);
    surface.build();
    return surface;
}

size_t silhouetteMismatches(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b)
{
    size_t n = 0;
    for (size_t i = 0; i < a.size(); i += 4)
        n += ((a[i] | a[i + 1] | a[i + 2]) != 0) != ((b[i] | b[i + 1] | b[i + 2]) != 0);
    return n;
}

double meanAbsDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b)
{
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(int(a[i]) - int(b[i]));
    return sum / double(a.size());
}

using ProgressiveAsset = VulkanTest;

TEST_F(ProgressiveAsset, CoarseLevelFirstThenRefinedAsBytesArrive)
{
    // The rippled torus at 256 cells, 65^2 stored (7 levels), its seams matched.
    ngi::Asset input = ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(257, 0.08f), 2);
    input.coding.pyramid = true;
    input.coding.positionStep = 16;
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const ngi::Asset fullAsset = ngi::parseAsset(bytes, "torus.ngi");
    const ngi::vk::AssetSurface full = build(renderer(), fullAsset);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(full.boundsMin(), full.boundsMax(), 25, 35, 1.0f);

    ngi::ProgressiveAssetReader reader("torus.ngi");
    uint32_t shown = 0;  // levels of the surface on screen
    std::vector<uint8_t> lastFrame;
    uint32_t compared = 0;
    size_t previousRestored = kSize * kSize;
    for (size_t at = 0; at < bytes.size(); at += 97) {
        if (!reader.append(std::span(bytes).subspan(at, std::min<size_t>(97, bytes.size() - at)))) continue;
        const ngi::AssetPrefix prefix = reader.current();
        ASSERT_GT(prefix.levelsDecoded, shown);
        shown = prefix.levelsDecoded;
        // What a host does on each refinement: a new surface from the prefix, drawn instead.
        const ngi::vk::AssetSurface surface = build(renderer(), prefix.asset);
        const uint32_t level = prefix.asset.charts[0].storedLevel;
        EXPECT_EQ(level, fullAsset.charts[0].storedLevel + prefix.levelCount - prefix.levelsDecoded);
        // Drawn at LoD 0 (restored from its coarse level, bicubically: the library's default),
        // each finer prefix comes no farther from the full asset's frame (silhouette pixels
        // that differ).
        lastFrame = draw(target, surface, camera, 0.0f);
        const size_t restored = silhouetteMismatches(lastFrame, draw(target, full, camera, 0.0f));
        EXPECT_LE(restored, previousRestored) << "level " << level;
        previousRestored = restored;
        if (level >= surface.levelCount()) continue;  // coarser than the seams let the engine draw
        // At the prefix's own level: the full asset's coarse LoD, the same positions, so the
        // same silhouette to the pixel.
        const std::vector<uint8_t> coarse = draw(target, surface, camera, float(level));
        const std::vector<uint8_t> reference = draw(target, full, camera, float(level));
        EXPECT_EQ(silhouetteMismatches(coarse, reference), 0u) << "level " << level;
        // The shading differs only by the normals: predicted from the prefix's level instead
        // of the full asset's subsampled (measured 2.5, 2.2, 1.0, 0.3, 0 grey levels).
        EXPECT_LT(meanAbsDifference(coarse, reference), 4.0) << "level " << level;
        ++compared;
    }
    ASSERT_TRUE(reader.complete());
    EXPECT_EQ(shown, 7u);
    EXPECT_GE(compared, 4u);  // the 5 x 5 to 65 x 65 prefixes (the 2 x 2 and 3 x 3 are coarser than drawn)
    // Every byte in: the full asset's frame, exactly.
    EXPECT_EQ(lastFrame, draw(target, full, camera, 0.0f));
}

}  // namespace
