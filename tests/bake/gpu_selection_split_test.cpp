// The adaptive LoD's selection on the GPU (engine/gpu_tile_selection.h) on a baked multi-chart
// asset: a torus split into matched charts with cross seams, where the balance and the border
// states run across charts. The GPU's tiles, morphs and border states must equal the CPU's
// (ngi/adaptive_lod.h) for cameras near and far and object-space bounds, under validation.
#include "adaptive_views.h"
#include "gpu_selection_compare.h"
#include "vulkan_fixture.h"

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/gpu_tile_selection.h"
#include "ngi/mesh/procedural_meshes.h"

namespace {

using GpuSelectionSplit = VulkanTest;

TEST_F(GpuSelectionSplit, SelectsTheCpusTilesAcrossTheChartsOfASplitTorus)
{
    const ngi::TriangleMesh torus = ngi::makeTorus(32, 16);
    ngi::BakeOptions options;
    options.resolution = 64;
    options.storeResolution = 16;
    options.sourceName = "split torus";
    options.splitPieces = 3;
    const ngi::Asset asset = ngi::bakeMesh(torus, options).asset;
    ASSERT_EQ(asset.charts.size(), 3u);
    ASSERT_FALSE(asset.crossSeams.empty());
    ngi::vk::RestoreOptions restore;
    restore.findNetwork = false;
    ngi::vk::AssetSurface surface(renderer(), asset, restore);
    surface.build();
    const ngi::vk::AdaptiveSurface adaptive(renderer(), surface, asset);

    std::vector<ngi::AdaptiveView> views;
    for (float bound : {0.002f, 0.01f, 0.05f}) {
        ngi::AdaptiveView view;
        view.maxError = bound;
        views.push_back(view);
    }
    for (float yaw : {20.0f, 150.0f, 260.0f})
        for (float distance : {0.6f, 1.6f, 4.0f}) {
            const ngi::vk::OrbitCamera camera = ngi::test::orbitCameraAt(yaw, 30.0f, distance);
            // Object space is the asset's: the adaptive surface maps it to normalized space.
            const glm::mat4 world = glm::inverse(adaptive.objectFromNormalized());
            views.push_back(
                adaptive.view(camera.viewProjection(1.0f), world, camera.eye(), 256.0f, 0.5f, yaw != 150.0f));
        }
    ngi::vk::GpuTileSelection selection(renderer(), adaptive, uint32_t(views.size()));
    std::vector<ngi::vk::GpuSelectionJob> jobs;
    for (const ngi::AdaptiveView& view : views) jobs.push_back({view, glm::mat4(1.0f), 0});
    context().submitAndWait([&](VkCommandBuffer cmd) { selection.recordSelect(cmd, jobs); });
    const auto gpu = selection.readRecords();
    const auto frame = selection.readFrame();
    EXPECT_EQ(frame.overflow, 0u);
    uint64_t fewest = ~0ull, most = 0;
    std::vector<bool> chartsDrawn(asset.charts.size());
    for (uint32_t j = 0; j < views.size(); ++j) {
        SCOPED_TRACE("view " + std::to_string(j));
        const ngi::TileSelection cpu = adaptive.select(views[j]);
        EXPECT_EQ(ngi::test::compareJob(adaptive, gpu, j, cpu), 0u);
        ASSERT_LT(j, frame.jobs.size());
        EXPECT_EQ(frame.jobs[j].triangles, cpu.triangles);
        fewest = std::min<uint64_t>(fewest, cpu.triangles);
        most = std::max<uint64_t>(most, cpu.triangles);
        for (const ngi::SelectedTile& t : cpu.tiles) chartsDrawn[t.chart] = chartsDrawn[t.chart] || !t.culled;
    }
    EXPECT_LT(4 * fewest, most);  // the views select different levels
    for (size_t c = 0; c < chartsDrawn.size(); ++c) EXPECT_TRUE(chartsDrawn[c]) << "chart " << c;
}

}  // namespace
