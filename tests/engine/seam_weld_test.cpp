// The GPU seam weld (shaders/seam_weld.comp): after the network's or the bilinear restore,
// every mate pair of every level down to the coarsest watertight one is bitwise equal, as
// the CPU mirror (ngi::weldSeams) makes it; without a seam the network's two sides differ.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/mip_pyramid.h"
#include "ngi/png_io.h"
#include "ngi/seam.h"
#include "tiny_network.h"

#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace {

constexpr uint32_t kResolution = 64;

// A cylinder around z: row y = 0 and row y = R are the same circle (the seam), the first
// and last columns its two boundary loops.
void cylinder(ngi::GeometryImage& positions, ngi::GeometryImage& normals)
{
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

ngi::ChartSeams cylinderSeam()
{
    ngi::ChartSeams seams;
    seams.matched = true;
    seams.coarsestWatertightLevel = 4;
    seams.segments = {{0, 2 * kResolution, kResolution}};  // bottom row forward = top row backward
    return seams;
}

// Mate pairs of `level` whose texels (position bits and packed normal) differ.
size_t unequalMates(const ngi::vk::GeometryImageSurface& surface, uint32_t level)
{
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

TEST_F(SeamWeld, NetworkRestoreIsWeldedAtEveryDrawnLevel)
{
    ngi::GeometryImage positions, normals;
    cylinder(positions, normals);
    const ngi::GeometryImage p2 = ngi::downsampleNested(positions, 2), n2 = ngi::downsampleNested(normals, 2);
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("weld", 11, 0.05f);
    ngi::vk::SuperResolution sr(context(), net);

    ngi::vk::GeometryImageSurface open(renderer(), p2, n2, kResolution + 1);
    context().submitAndWait([&](VkCommandBuffer cmd) { open.recordBuild(cmd, {&sr}); });
    EXPECT_GT(unequalMates(open, 0), 8u) << "the network's two sides should differ before the weld";

    EXPECT_EQ(open.drawnLevelCount(), open.levelCount());

    ngi::vk::GeometryImageSurface welded(renderer(), p2, n2, kResolution + 1, cylinderSeam());
    context().submitAndWait([&](VkCommandBuffer cmd) { welded.recordBuild(cmd, {&sr}); });
    EXPECT_EQ(welded.weldedLevelCount(), 2u);  // the restored levels 0, 1 (the network writes 0, 1 is its subsample)
    EXPECT_EQ(welded.drawnLevelCount(), 5u);   // down to the 5 x 5 level
    for (uint32_t level = 0; level < welded.drawnLevelCount(); ++level)
        EXPECT_EQ(unequalMates(welded, level), 0u) << "level " << level;
    // The weld touches the border only: an interior texel equals the unwelded restore's.
    EXPECT_EQ(welded.readLevel(0, false)[size_t(20) * 65 + 30], open.readLevel(0, false)[size_t(20) * 65 + 30]);
}

TEST_F(SeamWeld, BilinearRestoreIsWeldedAtEveryRestoredLevel)
{
    ngi::GeometryImage positions, normals;
    cylinder(positions, normals);
    const ngi::GeometryImage p3 = ngi::downsampleNested(positions, 3), n3 = ngi::downsampleNested(normals, 3);
    ngi::vk::GeometryImageSurface welded(renderer(), p3, n3, kResolution + 1, cylinderSeam());
    context().submitAndWait(
        [&](VkCommandBuffer cmd) { welded.recordBuild(cmd, {.withoutNetwork = ngi::vk::Upsampling::bilinear}); });
    EXPECT_EQ(welded.weldedLevelCount(), 3u);  // levels 0, 1, 2 are restored from level 3
    for (uint32_t level = 0; level < welded.drawnLevelCount(); ++level)
        EXPECT_EQ(unequalMates(welded, level), 0u) << "level " << level;
}

// Pixels of a close-up (normals mode) that are not the near surface facing `n`: the white
// background, or the sphere's far inner wall (normals facing away) seen through a crack.
size_t crackPixels(const std::vector<uint8_t>& rgba, glm::vec3 n)
{
    size_t count = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) {
        const bool background = rgba[i] == 255 && rgba[i + 1] == 255 && rgba[i + 2] == 255;
        const glm::vec3 shown = glm::vec3(rgba[i], rgba[i + 1], rgba[i + 2]) / 127.5f - 1.0f;
        count += background || glm::dot(shown, n) < 0.5f;
    }
    return count;
}

TEST_F(SeamWeld, ACloseUpAlongTheSeamShowsNoCrack)
{
    // The octahedral sphere (mates (x, 0) <-> (R - x, 0)), restored by a network whose two
    // sides differ, seen from 0.1 above the seam where they differ most, so that the surface
    // fills the frame: a pixel of background or of the far inner wall (culling is off; the
    // normals mode shows it facing away) is a crack. With the seam dropped from the asset (no
    // weld) the crack shows; with it, none at LoD 0 and at LoD 1.5 (geomorphed).
    const uint32_t r = 128;
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(r + 1);
    const ngi::Asset welded = ngi::makeAnalyticAsset("sphere", sphere, 2);
    ASSERT_TRUE(welded.charts[0].seams.matched);
    ngi::Asset open = welded;
    open.charts[0].seams = {};
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("crack", 5, 0.05f);
    ngi::vk::SuperResolution sr(context(), net);
    ngi::vk::AssetSurface openSurface(renderer(), open, {.network = &sr}),
        weldedSurface(renderer(), welded, {.network = &sr});
    openSurface.build();
    weldedSurface.build();

    // The widest mate pair of the unwelded restore.
    const std::vector<glm::uvec4> texels = openSurface.chart(0).readLevel(0, false);
    auto position = [&](glm::uvec2 s) {
        glm::vec3 q;
        std::memcpy(&q, &texels[size_t(s.y) * (r + 1) + s.x], sizeof q);
        return q;
    };
    const std::vector<uint32_t> table = ngi::seamWeldTable(sphere.seams, r);
    float widest = 0.0f;
    glm::uvec2 at{0, 0}, mate{0, 0};
    for (uint32_t t = 0; t < table.size(); ++t) {
        const glm::uvec2 a = ngi::perimeterSample(r, t), b = ngi::perimeterSample(r, table[t]);
        const float d = glm::distance(position(a), position(b));
        if (d > widest) widest = d, at = a, mate = b;
    }
    ASSERT_GT(widest, 2e-3f) << "the test network should open the seam visibly";
    const glm::vec3 n = sphere.normals.at(at.x, at.y);
    ngi::vk::OrbitCamera camera;
    camera.target = 0.5f * (position(at) + position(mate));
    camera.distance = 0.1f;
    camera.pitchDegrees = glm::degrees(std::asin(n.y));
    camera.yawDegrees = glm::degrees(std::atan2(n.x, n.z));
    camera.nearPlane = 0.001f;
    ngi::vk::OffscreenTarget target(renderer(), 192, 192);
    auto render = [&](const ngi::vk::AssetSurface& surface, float lod) {
        ngi::vk::DrawParams params;
        params.viewProjection = camera.viewProjection(1.0f);
        params.eye = camera.eye();
        params.lod = lod;
        params.mode = ngi::vk::ShadingMode::Normals;
        return target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, params, target.extent()); },
                             glm::vec4(1.0f));
    };
    for (float lod : {0.0f, 1.5f}) {
        SCOPED_TRACE("LoD " + std::to_string(lod));
        const auto a = render(openSurface, lod), b = render(weldedSurface, lod);
        if (const char* dir = std::getenv("NGI_SEAM_PNG_DIR")) {
            const std::string suffix = std::to_string(int(lod * 10)) + ".png";
            ngi::writePng8(std::string(dir) + "/seam_open_lod" + suffix, 192, 192, 4, a.data());
            ngi::writePng8(std::string(dir) + "/seam_welded_lod" + suffix, 192, 192, 4, b.data());
        }
        EXPECT_GT(crackPixels(a, n), 0u) << "without the weld the seam should crack";
        EXPECT_EQ(crackPixels(b, n), 0u);
    }
}

// Two charts of a split component (format 7): chart 0 is y in [0, 0.5] of a bumpy sheet, chart 1
// y in [0.5, 1]; chart 0's top side is chart 1's bottom side (the cross seam), stored a little
// apart as two codes would leave them. After every restore (bilinear, bicubic, a network) the
// GPU group weld makes the shared samples bitwise equal at every drawn level; without the cross
// seam they differ.
ngi::Asset splitSheet(bool withCrossSeam)
{
    constexpr uint32_t r = 16, level = 2;
    ngi::Asset asset;
    asset.sourceName = "split sheet";
    asset.parameterization = "analytic";
    for (int c = 0; c < 2; ++c) {
        ngi::GeometryImage positions(r + 1), normals(r + 1);
        for (uint32_t y = 0; y <= r; ++y)
            for (uint32_t x = 0; x <= r; ++x) {
                const double u = double(x) / r, v = 0.5 * (c + double(y) / r);
                const double lift = c == 1 && y == 0 ? 0.004 : 0.0;  // the other code's error on the curve
                positions.at(x, y) = glm::dvec3(u, v, 0.5 + 0.2 * std::sin(5.0 * u) * std::cos(4.0 * v) + lift);
                normals.at(x, y) = {0.0, 0.0, 1.0};
            }
        ngi::AssetChart& chart = asset.charts.emplace_back();
        chart.fullResolution = r;
        chart.storedLevel = level;
        ngi::storeGeometryImage(chart, ngi::downsampleNested(positions, level), ngi::downsampleNested(normals, level));
        chart.seams.matched = true;
        chart.seams.coarsestWatertightLevel = level;
    }
    if (withCrossSeam) asset.crossSeams = {{0, 2 * r, 1, 0, r}};
    return asset;
}

size_t unequalAcross(const ngi::vk::AssetSurface& surface, uint32_t level)
{
    const std::vector<glm::uvec4> a = surface.chart(0).readLevel(level, false),
                                  b = surface.chart(1).readLevel(level, false);
    const uint32_t n = surface.chart(0).levelSize(level);
    size_t unequal = 0;
    for (uint32_t x = 0; x < n; ++x)
        unequal += a[size_t(n - 1) * n + x] != b[x];  // chart 0's top row, chart 1's bottom row
    return unequal;
}

TEST_F(SeamWeld, ChartsOfASplitComponentAreWeldedAcrossChartsAtEveryLevel)
{
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("split", 5, 0.05f);  // x4: 5^2 -> 17^2
    ngi::vk::SuperResolution sr(context(), net);
    for (int restore = 0; restore < 3; ++restore) {
        SCOPED_TRACE("restore " + std::to_string(restore));
        auto build = [&](const ngi::Asset& asset) {
            ngi::vk::RestoreOptions options;
            options.network = restore == 2 ? &sr : nullptr;
            options.findNetwork = false;
            options.withoutNetwork = restore == 0 ? ngi::vk::Upsampling::bilinear : ngi::vk::Upsampling::bicubic;
            auto surface = std::make_unique<ngi::vk::AssetSurface>(renderer(), asset, options);
            surface->build();
            return surface;
        };
        const auto welded = build(splitSheet(true));
        ASSERT_EQ(welded->chart(0).drawnLevelCount(), 3u);
        for (uint32_t level = 0; level < 3; ++level) EXPECT_EQ(unequalAcross(*welded, level), 0u) << "level " << level;
        const auto open = build(splitSheet(false));
        EXPECT_GT(unequalAcross(*open, 0), 0u) << "the check can fail: unwelded, the restores differ";
    }
}

}  // namespace
