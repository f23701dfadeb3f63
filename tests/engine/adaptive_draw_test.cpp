// The adaptive LoD draw on the GPU (engine/adaptive_draw.h) against the uniform draw and the
// CPU selection: no cracks, culling invisible, the CPU's triangle count, under validation.
#include "adaptive_views.h"
#include "uv_colour.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/offscreen.h"
#include "ngi/error.h"

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <tuple>

namespace {

constexpr uint32_t kSize = 192;
const glm::vec4 kClear{0.0f, 0.0f, 0.0f, 1.0f};

using AdaptiveDraw = VulkanTest;

struct Scene {
    ngi::Asset asset;
    std::unique_ptr<ngi::vk::AssetSurface> surface;
    std::unique_ptr<ngi::vk::AdaptiveSurface> adaptive;

    Scene(const ngi::vk::Renderer& renderer, const ngi::AnalyticSurface& analytic,
          ngi::vk::SurfaceDraws draws = ngi::vk::SurfaceDraws::uniformAndAdaptive, uint32_t colorLevel = ~0u,
          bool uploadFinest = true, uint32_t tileCapacity = 1u << 15,
          const std::function<int(double u, double v)>& alpha = {})
        : asset(ngi::makeAnalyticAsset("adaptive", analytic, 1))
    {
        if (colorLevel != ~0u) ngi::test::paintUvColour(asset.charts[0], colorLevel);
        if (alpha) ngi::test::setUvAlpha(asset.charts[0], alpha);
        surface = std::make_unique<ngi::vk::AssetSurface>(renderer, asset, ngi::vk::RestoreOptions{}, draws);
        surface->build();
        adaptive = std::make_unique<ngi::vk::AdaptiveSurface>(renderer, *surface, asset, tileCapacity, 1, uploadFinest);
    }
};

using ngi::test::orbitCameraAt;

ngi::AdaptiveView viewOf(const ngi::vk::OrbitCamera& camera, float pixels, bool cull)
{
    return ngi::test::cameraView(camera, float(kSize), pixels, cull);
}

std::vector<uint8_t> drawAdaptive(ngi::vk::OffscreenTarget& target, Scene& scene, const ngi::vk::OrbitCamera& camera,
                                  const ngi::TileSelection& selection, ngi::vk::ShadingMode mode,
                                  ngi::vk::AdaptiveDrawStats* stats = nullptr)
{
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.mode = mode;
    scene.adaptive->clear();
    ngi::vk::AdaptiveDrawStats s;
    std::vector<uint8_t> pixels = target.render(
        [&](VkCommandBuffer cmd) { s = scene.adaptive->recordDraw(cmd, selection, p, target.extent()); }, kClear);
    if (stats) *stats = s;
    return pixels;
}

std::vector<uint8_t> drawUniform(ngi::vk::OffscreenTarget& target, const Scene& scene,
                                 const ngi::vk::OrbitCamera& camera, ngi::vk::ShadingMode mode)
{
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.mode = mode;
    return target.render([&](VkCommandBuffer cmd) { scene.surface->recordDraw(cmd, p, target.extent()); }, kClear);
}

bool covered(const std::vector<uint8_t>& rgba, int x, int y)
{
    const size_t i = (size_t(y) * kSize + size_t(x)) * 4;
    return (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
}

// Pixels the uniform full-resolution frame covers, farther than `margin` pixels from its
// silhouette (where the adaptive surface may lie up to its budget away), that the adaptive frame
// leaves empty: a crack shows the clear colour there.
size_t holesInside(const std::vector<uint8_t>& uniform, const std::vector<uint8_t>& adaptive, int margin)
{
    size_t holes = 0;
    for (int y = margin; y + margin < int(kSize); ++y)
        for (int x = margin; x + margin < int(kSize); ++x) {
            bool interior = true;
            for (int dy = -margin; dy <= margin && interior; ++dy)
                for (int dx = -margin; dx <= margin; ++dx) interior = interior && covered(uniform, x + dx, y + dy);
            holes += interior && !covered(adaptive, x, y);
        }
    return holes;
}

TEST_F(AdaptiveDraw, ClosedSurfacesShowNoCrackFromAnyCamera)
{
    for (const ngi::AnalyticSurface& analytic :
         {ngi::sphereGeometryImage(129), ngi::rippledTorusGeometryImage(129, 0.08f)}) {
        Scene scene(renderer(), analytic);
        ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
        for (int i = 0; i < 5; ++i) {
            const ngi::vk::OrbitCamera camera =
                orbitCameraAt(37.0f + 71.0f * float(i), -50.0f + 23.0f * float(i), 1.2f + 0.6f * float(i));
            const auto uniform = drawUniform(target, scene, camera, ngi::vk::ShadingMode::Normals);
            for (float pixels : {0.5f, 3.0f}) {
                const ngi::TileSelection selection = scene.adaptive->select(viewOf(camera, pixels, true));
                ngi::vk::AdaptiveDrawStats stats;
                const auto adaptive =
                    drawAdaptive(target, scene, camera, selection, ngi::vk::ShadingMode::Normals, &stats);
                EXPECT_EQ(holesInside(uniform, adaptive, int(std::ceil(pixels)) + 1), 0u)
                    << analytic.positions.size << " camera " << i << ", " << pixels << " px";
                EXPECT_EQ(stats.triangles, selection.triangles);
                EXPECT_GT(stats.drawnTiles, 0u);
            }
        }
    }
}

TEST_F(AdaptiveDraw, CullingNeverRemovesAVisiblePixel)
{
    Scene scene(renderer(), ngi::rippledTorusGeometryImage(129, 0.08f));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    uint32_t culledTiles = 0;
    for (float distance : {0.7f, 2.5f}) {
        const ngi::vk::OrbitCamera camera = orbitCameraAt(20.0f, 35.0f, distance);
        const ngi::TileSelection all = scene.adaptive->select(viewOf(camera, 1.0f, false));
        const ngi::TileSelection culled = scene.adaptive->select(viewOf(camera, 1.0f, true));
        culledTiles += culled.culledBackface + culled.culledFrustum;
        EXPECT_EQ(drawAdaptive(target, scene, camera, all, ngi::vk::ShadingMode::Shaded),
                  drawAdaptive(target, scene, camera, culled, ngi::vk::ShadingMode::Shaded))
            << "distance " << distance;
    }
    EXPECT_GT(culledTiles, 0u);  // the near camera sees only part of the torus
}

TEST_F(AdaptiveDraw, WithinHalfAPixelItLooksLikeTheFullResolution)
{
    Scene scene(renderer(), ngi::rippledTorusGeometryImage(129, 0.08f));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(30.0f, 40.0f, 2.0f);
    const auto uniform = drawUniform(target, scene, camera, ngi::vk::ShadingMode::Shaded);
    const ngi::TileSelection selection = scene.adaptive->select(viewOf(camera, 0.5f, true));
    const auto adaptive = drawAdaptive(target, scene, camera, selection, ngi::vk::ShadingMode::Shaded);
    size_t differ = 0;
    for (size_t i = 0; i < uniform.size(); i += 4)
        differ += std::abs(int(uniform[i]) - int(adaptive[i])) + std::abs(int(uniform[i + 1]) - int(adaptive[i + 1])) +
                std::abs(int(uniform[i + 2]) - int(adaptive[i + 2])) >
            48;
    // Silhouette pixels may flip where the surface moves by up to half a pixel.
    EXPECT_LT(double(differ) / double(kSize * kSize), 0.01);
    EXPECT_LT(selection.triangles, ngi::gridTriangleCount(129));
}

TEST_F(AdaptiveDraw, ASurfaceBuiltForItAloneDrawsTheSamePixelsInAThirdOfTheMemory)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene both(renderer(), torus), alone(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(25.0f, 30.0f, 1.6f);
    const ngi::TileSelection selection = both.adaptive->select(viewOf(camera, 1.0f, true));
    EXPECT_EQ(drawAdaptive(target, both, camera, selection, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, alone, camera, alone.adaptive->select(viewOf(camera, 1.0f, true)),
                           ngi::vk::ShadingMode::Shaded));
    EXPECT_LT(3 * alone.surface->gpuBytes(), both.surface->gpuBytes() * 1.1);
    // Its uniform draw is one clear error, before anything is recorded.
    ngi::vk::DrawParams p;
    EXPECT_THROW(
        target.render([&](VkCommandBuffer cmd) { alone.surface->recordDraw(cmd, p, target.extent()); }, kClear),
        ngi::Error);
}

TEST_F(AdaptiveDraw, KeepsItsOwnCompactLevelsInHalfTheRestoresBytes)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene scene(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(-35.0f, 20.0f, 1.5f);
    const ngi::TileSelection selection = scene.adaptive->select(viewOf(camera, 1.0f, true));
    const auto before = drawAdaptive(target, scene, camera, selection, ngi::vk::ShadingMode::Shaded);
    // 8 bytes per sample against the restore's 16 (each image's alignment aside).
    const VkDeviceSize restored = scene.surface->gpuBytes(), compact = scene.adaptive->levelBytes();
    EXPECT_GT(compact, 0u);
    EXPECT_LT(double(compact), 0.55 * double(restored));
    // The surface is not read again: without it the draw is the same, pixel for pixel.
    scene.surface.reset();
    EXPECT_EQ(drawAdaptive(target, scene, camera, selection, ngi::vk::ShadingMode::Shaded), before);
    EXPECT_EQ(scene.adaptive->gpuBytes(),
              scene.adaptive->levelBytes() + scene.adaptive->colorBytes() + scene.adaptive->recordBytes());
}

bool drawsLevel0(const ngi::TileSelection& selection)
{
    for (const ngi::SelectedTile& t : selection.tiles)
        if (!t.culled && t.level == 0) return true;
    return false;
}

TEST_F(AdaptiveDraw, GivesLevel0BackWhenNoTileDrawsItAndUploadsItAgainWhenOneDoes)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene scene(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly),
        fresh(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera far = orbitCameraAt(25.0f, 30.0f, 3.0f), near = orbitCameraAt(25.0f, 30.0f, 0.9f);
    const ngi::TileSelection farTiles = scene.adaptive->select(viewOf(far, 2.0f, true));
    const ngi::TileSelection nearTiles = scene.adaptive->select(viewOf(near, 0.25f, true));
    ASSERT_FALSE(drawsLevel0(farTiles));
    ASSERT_TRUE(drawsLevel0(nearTiles));
    const auto farBefore = drawAdaptive(target, scene, far, farTiles, ngi::vk::ShadingMode::Shaded);
    const VkDeviceSize allLevels = scene.adaptive->levelBytes();

    // Far frames: level 0 goes back after idleFrames frames (2 here), not before.
    const ngi::TileSelection* farOnly[1] = {&farTiles};
    uint32_t uploads = 0;
    for (uint64_t frame = 1; frame <= 3; ++frame) {
        renderer().context().submitAndWait(
            [&](VkCommandBuffer cmd) { uploads += scene.adaptive->recordResidency(cmd, farOnly, frame, 2); });
        EXPECT_EQ(scene.adaptive->residentFinestCount(), frame < 2 ? 1u : 0u) << "frame " << frame;
    }
    EXPECT_EQ(uploads, 0u);
    // Level 0 is three quarters of a 129^2 chart's levels (4/3 of it in all).
    EXPECT_LT(double(scene.adaptive->levelBytes()), 0.3 * double(allLevels));
    EXPECT_EQ(drawAdaptive(target, scene, far, farTiles, ngi::vk::ShadingMode::Shaded), farBefore);
    // A near view needs it: drawing without making it resident is one clear error ...
    ngi::vk::DrawParams p;
    p.viewProjection = near.viewProjection(1.0f);
    p.eye = near.eye();
    scene.adaptive->clear();
    EXPECT_THROW(
        target.render([&](VkCommandBuffer cmd) { scene.adaptive->recordDraw(cmd, nearTiles, p, target.extent()); },
                      kClear),
        ngi::Error);
    // ... and after its upload the frame is the one an object that never gave it back draws.
    const ngi::TileSelection* nearOnly[1] = {&nearTiles};
    renderer().context().submitAndWait(
        [&](VkCommandBuffer cmd) { uploads += scene.adaptive->recordResidency(cmd, nearOnly, 4, 2); });
    EXPECT_EQ(uploads, 1u);
    EXPECT_EQ(scene.adaptive->residentFinestCount(), 1u);
    EXPECT_EQ(scene.adaptive->levelBytes(), allLevels);
    EXPECT_EQ(drawAdaptive(target, scene, near, nearTiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, fresh, near, nearTiles, ngi::vk::ShadingMode::Shaded));
    // Frames are numbered forward only.
    EXPECT_THROW(renderer().context().submitAndWait(
                     [&](VkCommandBuffer cmd) { scene.adaptive->recordResidency(cmd, nearOnly, 3, 2); }),
                 ngi::Error);
}

// A surface told to leave level 0 on the host holds a quarter of the levels' memory from the
// start, draws far views as one that uploaded everything, refuses a near one until
// recordResidency uploads level 0 for it, and then draws it the same too.
TEST_F(AdaptiveDraw, AGivenBackLevel0IsFreedOnlyOnceTheFramesInFlightHaveFinished)
{
    // Two frames in flight: a frame still running when level 0 is given back may draw it (a GPU
    // selection reports its draws frames late), so it is freed two frames later, and a selection
    // that needs it before takes it back without an upload.
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene scene(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly),
        fresh(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    scene.adaptive = std::make_unique<ngi::vk::AdaptiveSurface>(renderer(), *scene.surface, scene.asset, 1u << 15, 2);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera far = orbitCameraAt(25.0f, 30.0f, 3.0f), near = orbitCameraAt(25.0f, 30.0f, 0.9f);
    const ngi::TileSelection farTiles = scene.adaptive->select(viewOf(far, 2.0f, true));
    const ngi::TileSelection nearTiles = scene.adaptive->select(viewOf(near, 0.25f, true));
    ASSERT_TRUE(drawsLevel0(nearTiles));
    ASSERT_FALSE(drawsLevel0(farTiles));
    const VkDeviceSize allLevels = scene.adaptive->levelBytes();
    const ngi::TileSelection* farOnly[1] = {&farTiles};
    const ngi::TileSelection* nearOnly[1] = {&nearTiles};
    uint32_t uploads = 0;
    auto residency = [&](std::span<const ngi::TileSelection* const> selections, uint64_t frame) {
        renderer().context().submitAndWait(
            [&](VkCommandBuffer cmd) { uploads += scene.adaptive->recordResidency(cmd, selections, frame, 2); });
    };
    residency(farOnly, 1);
    residency(farOnly, 2);  // idle for 2 frames: given back
    EXPECT_EQ(scene.adaptive->residentFinestCount(), 0u);
    EXPECT_EQ(scene.adaptive->levelBytes(), allLevels) << "frame 1, still in flight, may draw it";
    residency(nearOnly, 3);  // needed again before it is freed: taken back
    EXPECT_EQ(uploads, 0u);
    EXPECT_EQ(scene.adaptive->residentFinestCount(), 1u);
    EXPECT_EQ(drawAdaptive(target, scene, near, nearTiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, fresh, near, nearTiles, ngi::vk::ShadingMode::Shaded));
    residency(farOnly, 5);  // given back again at frame 5 ...
    residency(farOnly, 6);
    EXPECT_EQ(scene.adaptive->levelBytes(), allLevels);
    residency(farOnly, 7);  // ... and freed two frames later
    EXPECT_LT(double(scene.adaptive->levelBytes()), 0.3 * double(allLevels));
    residency(nearOnly, 8);  // then it is uploaded from the host copy
    EXPECT_EQ(uploads, 1u);
    EXPECT_EQ(drawAdaptive(target, scene, near, nearTiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, fresh, near, nearTiles, ngi::vk::ShadingMode::Shaded));
}

TEST_F(AdaptiveDraw, ALevel0LeftOnTheHostIsUploadedWhenATileFirstDrawsIt)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene lazy(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly, ~0u, false),
        eager(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    EXPECT_EQ(lazy.adaptive->residentFinestCount(), 0u);
    EXPECT_EQ(eager.adaptive->residentFinestCount(), 1u);
    EXPECT_LT(double(lazy.adaptive->levelBytes()), 0.3 * double(eager.adaptive->levelBytes()));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera far = orbitCameraAt(25.0f, 30.0f, 3.0f), near = orbitCameraAt(25.0f, 30.0f, 0.9f);
    const ngi::TileSelection farTiles = lazy.adaptive->select(viewOf(far, 2.0f, true));
    const ngi::TileSelection nearTiles = lazy.adaptive->select(viewOf(near, 0.25f, true));
    ASSERT_FALSE(drawsLevel0(farTiles));
    ASSERT_TRUE(drawsLevel0(nearTiles));
    EXPECT_EQ(drawAdaptive(target, lazy, far, farTiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, eager, far, farTiles, ngi::vk::ShadingMode::Shaded));
    ngi::vk::DrawParams p;
    p.viewProjection = near.viewProjection(1.0f);
    p.eye = near.eye();
    lazy.adaptive->clear();
    EXPECT_THROW(
        target.render([&](VkCommandBuffer cmd) { lazy.adaptive->recordDraw(cmd, nearTiles, p, target.extent()); },
                      kClear),
        ngi::Error);
    const ngi::TileSelection* nearOnly[1] = {&nearTiles};
    uint32_t uploads = 0;
    renderer().context().submitAndWait(
        [&](VkCommandBuffer cmd) { uploads = lazy.adaptive->recordResidency(cmd, nearOnly, 1, 2); });
    EXPECT_EQ(uploads, 1u);
    EXPECT_EQ(lazy.adaptive->levelBytes(), eager.adaptive->levelBytes());
    EXPECT_EQ(drawAdaptive(target, lazy, near, nearTiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, eager, near, nearTiles, ngi::vk::ShadingMode::Shaded));
}

// Tile records grow to what a frame draws: a surface whose first block holds 16 tiles draws a
// view of hundreds, and three instances of it in one frame, as one with room for 32,768; the
// blocks it adds stay for later frames, which add none.
TEST_F(AdaptiveDraw, TileRecordsGrowToWhatAFrameDraws)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(129, 0.08f);
    Scene small(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly, ~0u, true, 16),
        large(renderer(), torus, ngi::vk::SurfaceDraws::adaptiveOnly);
    const VkDeviceSize before = small.adaptive->recordBytes();
    EXPECT_LT(20 * before, large.adaptive->recordBytes());
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(25.0f, 30.0f, 1.2f);
    const ngi::TileSelection tiles = small.adaptive->select(viewOf(camera, 0.5f, true));
    ASSERT_GT(tiles.tiles.size() - tiles.culledFrustum - tiles.culledBackface, 100u);
    EXPECT_EQ(drawAdaptive(target, small, camera, tiles, ngi::vk::ShadingMode::Shaded),
              drawAdaptive(target, large, camera, tiles, ngi::vk::ShadingMode::Shaded));
    const VkDeviceSize grown = small.adaptive->recordBytes();
    EXPECT_GT(grown, before);
    // Three instances side by side in one frame: blocks are filled in turn.
    auto threeInstances = [&](Scene& scene) {
        scene.adaptive->clear();
        return target.render(
            [&](VkCommandBuffer cmd) {
                for (float dx : {-0.6f, 0.0f, 0.6f}) {
                    const glm::mat4 world = glm::translate(glm::mat4(1.0f), glm::vec3(dx, 0.0f, 0.0f));
                    ngi::vk::DrawParams p;
                    p.viewProjection = camera.viewProjection(1.0f);
                    p.world = world;
                    p.eye = camera.eye();
                    scene.adaptive->recordDraw(cmd, tiles, p, target.extent());
                }
            },
            kClear);
    };
    EXPECT_EQ(threeInstances(small), threeInstances(large));
    const VkDeviceSize most = small.adaptive->recordBytes();
    EXPECT_EQ(threeInstances(small), threeInstances(large));
    EXPECT_EQ(small.adaptive->recordBytes(), most) << "a later frame of the same draws adds no block";
    EXPECT_LT(most, large.adaptive->recordBytes());
}

TEST_F(AdaptiveDraw, TheBaseColourStaysOnTheSurfaceAtEveryLevel)
{
    Scene scene(renderer(), ngi::sphereGeometryImage(129), ngi::vk::SurfaceDraws::adaptiveOnly, 2);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(40.0f, 25.0f, 1.8f);
    const auto fine = drawAdaptive(target, scene, camera, scene.adaptive->select(viewOf(camera, 0.5f, true)),
                                   ngi::vk::ShadingMode::BaseColour);
    ngi::vk::AdaptiveDrawStats coarseStats;
    const ngi::TileSelection coarseSelection = scene.adaptive->select(viewOf(camera, 3.0f, true));
    const auto coarse =
        drawAdaptive(target, scene, camera, coarseSelection, ngi::vk::ShadingMode::BaseColour, &coarseStats);
    size_t covered = 0, differ = 0;
    int lowRed = 255, highRed = 0, lowGreen = 255, highGreen = 0;
    for (size_t i = 0; i < fine.size(); i += 4) {
        if (fine[i] == 0 && fine[i + 1] == 0 && fine[i + 2] == 0) continue;
        ++covered;
        // Unlit: the image's own blue (64, sRGB filtering keeps a constant exactly, up to rounding).
        EXPECT_NEAR(int(fine[i + 2]), 64, 1) << "pixel " << i / 4;
        lowRed = std::min<int>(lowRed, fine[i]), highRed = std::max<int>(highRed, fine[i]);
        lowGreen = std::min<int>(lowGreen, fine[i + 1]), highGreen = std::max<int>(highGreen, fine[i + 1]);
        differ += std::abs(int(fine[i]) - int(coarse[i])) + std::abs(int(fine[i + 1]) - int(coarse[i + 1])) > 24;
    }
    ASSERT_GT(covered, size_t(kSize * kSize / 8));
    EXPECT_GT(highRed - lowRed, 64) << "the colour follows u across the visible half";
    EXPECT_GT(highGreen - lowGreen, 64) << "and v";
    // Within 3 px the surface moves by up to 3 px (a third of the triangles), and the colour,
    // attached to the uv the coarser level interpolates, moves with it: a colour gradient of
    // ~2.5 levels per pixel changes by more than 24 on 1.2% of the pixels (measured).
    EXPECT_LT(coarseSelection.triangles, scene.adaptive->select(viewOf(camera, 0.5f, true)).triangles / 2);
    EXPECT_LT(double(differ) / double(covered), 0.03);
}

TEST_F(AdaptiveDraw, TheBaseColoursAlphaCutsTheSurfaceOut)
{
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(129);
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const ngi::vk::OrbitCamera camera = orbitCameraAt(40.0f, 25.0f, 1.8f);
    // Covered pixels, those that show u below `cut` (red = 255 u), and the median red.
    auto coveredAt = [&](Scene& scene, float pixels, int cut) {
        const auto frame = drawAdaptive(target, scene, camera, scene.adaptive->select(viewOf(camera, pixels, true)),
                                        ngi::vk::ShadingMode::BaseColour);
        size_t n = 0, below = 0;
        std::vector<int> reds;
        for (size_t i = 0; i < frame.size(); i += 4) {
            if (frame[i] == 0 && frame[i + 1] == 0 && frame[i + 2] == 0) continue;
            ++n, below += frame[i] < cut;
            reds.push_back(frame[i]);
        }
        std::nth_element(reds.begin(), reds.begin() + reds.size() / 2, reds.end());
        return std::tuple{n, below, reds.empty() ? 0 : reds[reds.size() / 2]};
    };
    Scene opaque(renderer(), sphere, ngi::vk::SurfaceDraws::adaptiveOnly, 2);
    const auto [whole, none, cut] = coveredAt(opaque, 0.5f, 0);
    ASSERT_GT(whole, size_t(kSize * kSize / 8));
    ASSERT_GT(cut, 40);
    // Alpha 0 where u is below the median u the frame shows: no pixel shows u below it any more
    // (but for the band of one texel, 1/32 of u, where the filter blends the two), at a fine and
    // a coarse selection; where the front is cut out, the back of the sphere or nothing shows.
    // At most 1 in 1000 pixels do, at the silhouette: there a coarse mip of the colour (alpha
    // blended over several texels) is sampled (measured: 2 pixels at 3 px).
    const int at = cut;
    Scene masked(renderer(), sphere, ngi::vk::SurfaceDraws::adaptiveOnly, 2, true, 1u << 15,
                 [at](double u, double) { return 255.0 * u < at ? 0 : 255; });
    for (float pixels : {0.5f, 3.0f}) {
        const auto [n, below, median] = coveredAt(masked, pixels, cut - 10);
        EXPECT_LE(below, n / 1000) << pixels << " px";
        EXPECT_LT(n, whole) << pixels << " px";
    }
}

TEST_F(AdaptiveDraw, AZeroTileCapacityIsAClearError)
{
    Scene scene(renderer(), ngi::sphereGeometryImage(33));
    EXPECT_THROW(ngi::vk::AdaptiveSurface(renderer(), *scene.surface, scene.asset, 0), ngi::Error);
}

}  // namespace
