// The adaptive LoD's selection on the GPU (engine/gpu_tile_selection.h) against the CPU
// definition (ngi/adaptive_lod.h, AdaptiveSurface::select): the same tiles, levels, morphs
// and border states for many views in one frame, the same pixels, its statistics, growth
// past its capacity and its errors, under validation on lavapipe.
#include "gpu_selection_compare.h"
#include "adaptive_views.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/gpu_tile_selection.h"
#include "ngi/engine/offscreen.h"
#include "ngi/error.h"
#include "ngi_shared.h"

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace {

constexpr uint32_t kSize = 160;
const glm::vec4 kClear{0.0f, 0.0f, 0.0f, 1.0f};

using GpuTileSelection = VulkanTest;

struct Scene {
    ngi::Asset asset;
    std::unique_ptr<ngi::vk::AssetSurface> surface;
    std::unique_ptr<ngi::vk::AdaptiveSurface> adaptive;
    Scene(const ngi::vk::Renderer& renderer, const ngi::AnalyticSurface& analytic, bool uploadFinest = true)
        : asset(ngi::makeAnalyticAsset("gpu-selection", analytic, 1))
    {
        surface = std::make_unique<ngi::vk::AssetSurface>(renderer, asset);
        surface->build();
        adaptive = std::make_unique<ngi::vk::AdaptiveSurface>(renderer, *surface, asset, 1u << 15, 1, uploadFinest);
    }
};

using ngi::test::orbitCameraAt;

ngi::AdaptiveView viewOf(const ngi::vk::OrbitCamera& camera, float pixels, bool cull)
{
    return ngi::test::cameraView(camera, float(kSize), pixels, cull);
}

// Every view of `views` selected in one frame on the GPU, each its own job in group job % 2,
// compared with the CPU's selection of it: tiles, morphs, border states and the statistics.
// Returns the CPU's forced splits over all views (the balance's work).
uint32_t expectTheCpuSelection(const ngi::vk::Context& context, const ngi::vk::Renderer& renderer, const Scene& scene,
                               const std::vector<ngi::AdaptiveView>& views)
{
    uint32_t forcedSplits = 0;
    ngi::vk::GpuTileSelection selection(renderer, *scene.adaptive, uint32_t(views.size()), 2);
    std::vector<ngi::vk::GpuSelectionJob> jobs;
    for (size_t j = 0; j < views.size(); ++j) jobs.push_back({views[j], glm::mat4(1.0f), uint32_t(j % 2)});
    context.submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, jobs); });
    const auto frame = selection.readFrame();
    const auto gpu = selection.readRecords();
    EXPECT_EQ(frame.overflow, 0u);
    if (frame.jobs.size() != views.size()) {
        ADD_FAILURE() << "statistics of " << frame.jobs.size() << " jobs for " << views.size();
        return 0;
    }
    for (uint32_t j = 0; j < views.size(); ++j) {
        SCOPED_TRACE("view " + std::to_string(j));
        const ngi::TileSelection cpu = scene.adaptive->select(views[j]);
        forcedSplits += cpu.forcedSplits;
        EXPECT_EQ(ngi::test::compareJob(*scene.adaptive, gpu, j, cpu), 0u);
        for (const auto& t : gpu) {
            if (t.instance == j) {
                EXPECT_EQ(t.group, j % 2);
            }
        }
        EXPECT_EQ(frame.jobs[j].drawnTiles, cpu.tiles.size() - cpu.culledFrustum - cpu.culledBackface);
        EXPECT_EQ(frame.jobs[j].culledFrustum, cpu.culledFrustum);
        EXPECT_EQ(frame.jobs[j].culledBackface, cpu.culledBackface);
        EXPECT_EQ(frame.jobs[j].triangles, cpu.triangles);
    }
    return forcedSplits;
}

TEST_F(GpuTileSelection, SelectsTheCpusTilesMorphsAndBorderStatesOnATorus)
{
    const Scene scene(renderer(), ngi::rippledTorusGeometryImage(129));
    std::vector<ngi::AdaptiveView> views;
    for (float yaw : {0.0f, 70.0f, 200.0f})
        for (float distance : {0.9f, 2.5f})
            for (float pixels : {0.5f, 2.0f})
                views.push_back(viewOf(orbitCameraAt(yaw, 25.0f, distance), pixels, yaw != 0.0f));
    for (float bound : {0.002f, 0.02f}) {
        ngi::AdaptiveView view;
        view.maxError = bound;
        views.push_back(view);
    }
    expectTheCpuSelection(context(), renderer(), scene, views);
}

// Detail on one side of a seam only: a torus ripples next to the square's left side, its mates
// on the right side are smooth, so the CPU's balance splits tiles within the chart and across
// the seam; the GPU's closure must split the same.
TEST_F(GpuTileSelection, BalancesWithinTheChartAndAcrossItsSeamAsTheCpuDoes)
{
    ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(257, 0.0f);
    const uint32_t r = 256;
    for (uint32_t y = 0; y <= r; ++y)
        for (uint32_t x = 1; x < r / 8; ++x) {
            const float u = float(x) / float(r / 8), v = float(y) / float(r);
            torus.positions.at(x, y) +=
                0.015f * std::sin(3.14159265f * u) * std::sin(2.0f * 3.14159265f * 16.0f * v) * torus.normals.at(x, y);
        }
    const Scene scene(renderer(), torus);
    std::vector<ngi::AdaptiveView> views;
    for (float yaw : {0.0f, 70.0f, 180.0f})
        for (float distance : {0.5f, 1.2f})
            for (float pixels : {0.5f, 2.0f})
                views.push_back(viewOf(orbitCameraAt(yaw, 10.0f, distance), pixels, true));
    for (float bound : {0.0005f, 0.002f, 0.004f}) {
        ngi::AdaptiveView view;
        view.maxError = bound;
        views.push_back(view);
    }
    EXPECT_GE(expectTheCpuSelection(context(), renderer(), scene, views), 5u);
}

TEST_F(GpuTileSelection, SelectsTheCpusTilesOnASphereFromInsideAndOutside)
{
    const Scene scene(renderer(), ngi::sphereGeometryImage(129));
    std::vector<ngi::AdaptiveView> views;
    for (float distance : {0.2f, 0.7f, 3.0f})
        views.push_back(viewOf(orbitCameraAt(30.0f, -40.0f, distance), 1.0f, true));
    expectTheCpuSelection(context(), renderer(), scene, views);
}

TEST_F(GpuTileSelection, DrawsTheCpusPixels)
{
    Scene scene(renderer(), ngi::rippledTorusGeometryImage(129));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    ngi::vk::GpuTileSelection selection(renderer(), *scene.adaptive, 1);
    for (const auto& camera : {orbitCameraAt(40.0f, 30.0f, 1.0f), orbitCameraAt(250.0f, -20.0f, 2.2f)}) {
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(1.0f);
        p.eye = camera.eye();
        p.mode = ngi::vk::ShadingMode::Wireframe;
        const ngi::AdaptiveView view = viewOf(camera, 1.0f, true);
        scene.adaptive->clear();
        const ngi::TileSelection cpu = scene.adaptive->select(view);
        const auto cpuPixels = target.render(
            [&](VkCommandBuffer cmd) { scene.adaptive->recordDraw(cmd, cpu, p, target.extent()); }, kClear);
        const ngi::vk::GpuSelectionJob job{view, glm::mat4(1.0f), 0};
        uint32_t draws = 0;
        const auto gpuPixels =
            target.render([&](VkCommandBuffer cmd) { draws = selection.recordDraw(cmd, 0, p, target.extent()); },
                          kClear, [&](VkCommandBuffer cmd) { selection.recordSelect(cmd, std::span(&job, 1)); });
        EXPECT_GT(draws, 0u);
        size_t differ = 0, covered = 0;
        for (size_t i = 0; i < cpuPixels.size(); i += 4) {
            differ += cpuPixels[i] != gpuPixels[i] || cpuPixels[i + 1] != gpuPixels[i + 1] ||
                cpuPixels[i + 2] != gpuPixels[i + 2];
            covered += (cpuPixels[i] | cpuPixels[i + 1] | cpuPixels[i + 2]) != 0;
        }
        EXPECT_GT(covered, 1000u);
        EXPECT_EQ(differ, 0u);
    }
}

TEST_F(GpuTileSelection, RecordsPastItsCapacityAreReportedAndTheNextFrameGrows)
{
    const Scene scene(renderer(), ngi::rippledTorusGeometryImage(129));
    ngi::vk::GpuTileSelection selection(renderer(), *scene.adaptive, 1, 1, 8);
    ngi::AdaptiveView view;
    view.maxError = 0.002f;
    const size_t expected = scene.adaptive->select(view).tiles.size();
    ASSERT_GT(expected, 16u);
    const ngi::vk::GpuSelectionJob job{view, glm::mat4(1.0f), 0};
    context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, std::span(&job, 1)); });
    EXPECT_EQ(selection.readRecords().size(), 8u);
    EXPECT_EQ(selection.readFrame().overflow, expected - 8);
    context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, std::span(&job, 1)); });
    EXPECT_EQ(selection.readFrame().overflow, 0u);
    EXPECT_EQ(selection.readRecords().size(), expected);
}

// A level 0 left on the host: the first frame draws level 1 at the finest and reports the
// chart; once the report has made it resident, the next frame selects the CPU's tiles.
TEST_F(GpuTileSelection, ReportsTheLevel0ItNeedsAndDrawsItOnceResident)
{
    Scene scene(renderer(), ngi::rippledTorusGeometryImage(129), false);
    ASSERT_FALSE(scene.adaptive->finestResident(0));
    ngi::vk::GpuTileSelection selection(renderer(), *scene.adaptive, 1);
    ngi::AdaptiveView view;
    view.maxError = 0.0005f;
    const ngi::TileSelection cpu = scene.adaptive->select(view);
    ASSERT_TRUE(std::any_of(cpu.tiles.begin(), cpu.tiles.end(), [](const auto& t) { return t.level == 0; }));
    const ngi::vk::GpuSelectionJob job{view, glm::mat4(1.0f), 0};
    context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, std::span(&job, 1)); });
    const auto first = selection.readRecords();
    EXPECT_TRUE(std::none_of(first.begin(), first.end(), [](const auto& t) { return t.level == 0; }));
    const auto report = selection.readFrame().finestCharts;
    ASSERT_EQ(report, std::vector<size_t>{0});
    context().submitAndWait([&](VkCommandBuffer cmd) {
        EXPECT_EQ(scene.adaptive->recordResidency(cmd, std::span<const size_t>(report), 1), 1u);
        selection.recordSelect(cmd, std::span(&job, 1));
    });
    EXPECT_TRUE(scene.adaptive->finestResident(0));
    EXPECT_EQ(ngi::test::compareJob(*scene.adaptive, selection.readRecords(), 0, cpu), 0u);
    EXPECT_EQ(selection.readFrame().finestCharts, std::vector<size_t>{0});  // drawn now
}

TEST_F(GpuTileSelection, FramesInFlightKeepTheirOwnSelections)
{
    // Two frames selected in one submission, as a host with two frames in flight records them
    // before the first has run: each frame's buffers hold its own view's selection, and drawing
    // frame 0 after frame 1 was selected draws frame 0's tiles.
    Scene scene(renderer(), ngi::rippledTorusGeometryImage(129));
    scene.adaptive = std::make_unique<ngi::vk::AdaptiveSurface>(renderer(), *scene.surface, scene.asset, 1u << 15, 2);
    ngi::vk::GpuTileSelection single(renderer(), *scene.adaptive, 1, 1, 4096);
    ngi::vk::GpuTileSelection selection(renderer(), *scene.adaptive, 1, 1, 4096, 2);
    EXPECT_EQ(selection.staticBytes(), single.staticBytes());  // the tile data is shared
    EXPECT_EQ(selection.frameBytes(), 2 * single.frameBytes());
    const ngi::vk::OrbitCamera nearCamera = orbitCameraAt(20.0f, 30.0f, 0.6f),
                               farCamera = orbitCameraAt(200.0f, -10.0f, 4.0f);
    const ngi::AdaptiveView near = viewOf(nearCamera, 1.0f, true), far = viewOf(farCamera, 2.0f, true);
    const std::vector<ngi::vk::GpuSelectionJob> first{{near, glm::mat4(1.0f), 0}}, second{{far, glm::mat4(1.0f), 0}};
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    ngi::vk::DrawParams p;
    p.viewProjection = nearCamera.viewProjection(1.0f);
    p.eye = nearCamera.eye();
    p.mode = ngi::vk::ShadingMode::Wireframe;
    const auto twoFrames = target.render(
        [&](VkCommandBuffer cmd) { selection.recordDraw(cmd, 0, p, target.extent(), nullptr, 0); }, kClear,
        [&](VkCommandBuffer cmd) {
            selection.recordSelect(cmd, first, 0);
            selection.recordSelect(cmd, second, 1);
        });
    const auto oneFrame = target.render([&](VkCommandBuffer cmd) { single.recordDraw(cmd, 0, p, target.extent()); },
                                        kClear, [&](VkCommandBuffer cmd) { single.recordSelect(cmd, first); });
    EXPECT_EQ(twoFrames, oneFrame) << "frame 0 draws its own selection after frame 1's";
    const ngi::TileSelection cpuNear = scene.adaptive->select(near), cpuFar = scene.adaptive->select(far);
    ASSERT_NE(cpuNear.tiles.size(), cpuFar.tiles.size());  // two selections that tell the frames apart
    EXPECT_EQ(ngi::test::compareJob(*scene.adaptive, selection.readRecords(0), 0, cpuNear), 0u);
    EXPECT_EQ(ngi::test::compareJob(*scene.adaptive, selection.readRecords(1), 0, cpuFar), 0u);
    EXPECT_EQ(selection.readFrame(0).jobs.at(0).triangles, cpuNear.triangles);
    EXPECT_EQ(selection.readFrame(1).jobs.at(0).triangles, cpuFar.triangles);
    // A frame past those in flight is a clear error, and so are 0 frames or more than the
    // adaptive surface was made for.
    EXPECT_THROW(context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, first, 2); }),
                 ngi::Error);
    EXPECT_THROW(context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordDraw(cmd, 0, p, {}, nullptr, 2); }),
                 ngi::Error);
    EXPECT_THROW(selection.readFrame(2), ngi::Error);
    EXPECT_THROW(ngi::vk::GpuTileSelection(renderer(), *scene.adaptive, 1, 1, 4096, 0), ngi::Error);
    EXPECT_THROW(ngi::vk::GpuTileSelection(renderer(), *scene.adaptive, 1, 1, 4096, 3), ngi::Error);
}

TEST_F(GpuTileSelection, BadJobsAreClearErrors)
{
    const Scene scene(renderer(), ngi::sphereGeometryImage(65));
    EXPECT_THROW(ngi::vk::GpuTileSelection(renderer(), *scene.adaptive, 0), ngi::Error);
    ngi::vk::GpuTileSelection selection(renderer(), *scene.adaptive, 2, 1);
    // Nothing selected yet: no draw (its indirect commands hold nothing).
    context().submitAndWait([&](VkCommandBuffer cmd) { EXPECT_EQ(selection.recordDraw(cmd, 0, {}), 0u); });
    EXPECT_THROW(ngi::vk::GpuTileSelection(renderer(), *scene.adaptive, 1u << 30), ngi::Error);
    ngi::AdaptiveView view;
    std::vector<ngi::vk::GpuSelectionJob> jobs(3, {view, glm::mat4(1.0f), 0});
    auto record = [&](std::span<const ngi::vk::GpuSelectionJob> j) {
        context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, j); });
    };
    try {
        record(jobs);
        ADD_FAILURE() << "three jobs for two";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("3 jobs"), std::string::npos) << e.what();
    }
    EXPECT_THROW(record(std::span(jobs.data(), 0)), ngi::Error);
    jobs[0].group = 1;
    EXPECT_THROW(record(std::span(jobs.data(), 1)), ngi::Error);
    jobs[0].group = 0;
    jobs[0].view.maxError = std::nanf("");
    EXPECT_THROW(record(std::span(jobs.data(), 1)), ngi::Error);
}

}  // namespace
