// ngi-bench-adaptive: the adaptive draw at fixed cameras, its tiles selected on the CPU
// (AdaptiveSurface::select, ngi/adaptive_lod.h) and on the GPU (GpuTileSelection), against
// the uniform draw (one LoD per instance, DrawBatch, the level the instance's worst spot
// needs: ngi::instanceLod). N instances of one asset stand in rows before a fixed camera
// (1280x720, 60 degrees), nearest first; per N a table row: the selection's milliseconds (CPU
// wall time over the machine's cores; GPU timestamps of its compute passes), each draw's GPU
// milliseconds, and the triangles each draws. A benchmark, not a test: compare ratios within
// one run (on lavapipe the "GPU" is the CPU too).
//
//   ngi-bench-adaptive [ASSET.ngi] [--instances 1,8,64] [--budget PX] [--repeats N]
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/context.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/gpu_tile_selection.h"
#include "ngi/engine/lod.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: ngi-bench-adaptive [ASSET.ngi] [--instances LIST] [--budget PX] [--repeats N]\n"
    "  The adaptive draw of N instances of ASSET (default assets/default.ngi) before a fixed\n"
    "  camera, for each N of LIST (default 1,8,64), within PX pixels (default 1): the tile\n"
    "  selection's milliseconds on the CPU and on the GPU, the draws' GPU milliseconds and\n"
    "  triangles, against one LoD per instance. Each cell the median of N runs (default 5).\n";

struct Options {
    std::string asset = NGI_DEFAULT_ASSET;
    std::vector<uint32_t> instances = {1, 8, 64};
    float budget = 1.0f;
    int repeats = 5;
};

Options parse(int argc, char** argv)
{
    Options o;
    bool assetGiven = false;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        if (args.is("--instances")) {
            const std::string flag = args.flag(), list = args.value();
            o.instances.clear();
            for (size_t start = 0; start <= list.size();) {
                const size_t comma = std::min(list.find(',', start), list.size());
                o.instances.push_back(
                    uint32_t(ngi::parseIntegerOptionInRange(flag, list.substr(start, comma - start), 1, 4096)));
                start = comma + 1;
            }
        } else if (args.is("--budget"))
            o.budget = ngi::parseFloatOptionInRange(args.flag(), args.value(), 0.05, 1e4, "pixels");
        else if (args.is("--repeats"))
            o.repeats = int(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 1, 1000));
        else if (args.is("--help", "-h")) {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (args.positional() && !assetGiven) {
            o.asset = args.flag();
            assetGiven = true;
        } else
            throw args.unknown();
    }
    return o;
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Four timestamps: (0, 1) around the selection, (2, 3) around the draw.
struct Timestamps {
    const ngi::vk::Context& c;
    ngi::vk::UniqueQueryPool pool;
    explicit Timestamps(const ngi::vk::Context& context) : c(context), pool(context.device)
    {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 4;
        NGI_VK_CHECK(vkCreateQueryPool(c.device, &info, nullptr, pool.out()));
    }
    void write(VkCommandBuffer cmd, uint32_t k, VkPipelineStageFlagBits stage)
    {
        vkCmdWriteTimestamp(cmd, stage, pool.get(), k);
    }
    double milliseconds(uint32_t first) const
    {
        uint64_t t[2];
        NGI_VK_CHECK(vkGetQueryPoolResults(c.device, pool.get(), first, 2, sizeof t, t, sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        return double(t[1] - t[0]) * c.properties.limits.timestampPeriod * 1e-6;
    }
};

int run(const Options& o)
{
    auto context = ngi::vk::Context::create({});
    const ngi::vk::Context& c = *context;
    ngi::vk::Renderer renderer(c);
    const ngi::Asset asset = ngi::readAsset(o.asset);
    ngi::vk::AssetSurface surface(renderer, asset);
    surface.build();
    ngi::vk::AdaptiveSurface adaptive(renderer, surface, asset);
    const ngi::AssetLodMetrics metrics = ngi::measureLodMetrics(asset);
    constexpr uint32_t width = 1280, height = 720;
    ngi::vk::OffscreenTarget target(renderer, width, height);
    // Instances one unit wide (the asset's longest side), 8 to a row, rows 1.5 units apart
    // from 2 units before the camera; the camera at the origin looking down -z.
    const glm::vec3 centre = asset.offset + 0.5f * asset.scale;
    const float size = std::max({asset.scale.x, asset.scale.y, asset.scale.z});
    const glm::mat4 viewProjection = glm::perspectiveRH_ZO(glm::radians(60.0f), float(width) / height, 0.05f, 500.0f) *
        glm::lookAtRH(glm::vec3(0.0f), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    Timestamps timestamps(c);
    std::printf("device: %s\nasset: %s, %zu chart(s), budget %.2f px, %ux%u, median of %d runs\n\n",
                c.properties.deviceName, asset.sourceName.c_str(), asset.charts.size(), o.budget, width, height,
                o.repeats);
    std::printf("| instances | select CPU ms | select GPU ms | draw ms (CPU-selected) | draw ms (GPU-selected) | "
                "adaptive triangles (CPU / GPU) | one LoD per instance: draw ms | triangles |\n"
                "|---|---|---|---|---|---|---|---|\n");
    for (const uint32_t n : o.instances) {
        std::vector<glm::mat4> worlds;
        for (uint32_t k = 0; k < n; ++k) {
            const glm::vec3 at(1.3f * (float(k % 8) - 0.5f * float(std::min(n, 8u) - 1)), -0.3f,
                               -2.0f - 1.5f * float(k / 8));
            worlds.push_back(glm::translate(glm::mat4(1.0f), at) * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / size)) *
                             glm::translate(glm::mat4(1.0f), -centre));
        }
        std::vector<ngi::SelectionRequest> requests;
        std::vector<ngi::vk::GpuSelectionJob> jobs;
        for (const glm::mat4& world : worlds) {
            const ngi::AdaptiveView view =
                adaptive.view(viewProjection, world, glm::vec3(0.0f), float(height), o.budget);
            requests.push_back({&adaptive.charts(), &adaptive.mates(), view});
            jobs.push_back({view, world, 0});
        }
        ngi::vk::GpuTileSelection gpuSelection(renderer, adaptive, n, 1, 1u << 18);
        ngi::vk::DrawBatch batch(renderer, uint32_t(n * asset.charts.size()));
        ngi::vk::DrawParams params;
        params.viewProjection = viewProjection;
        std::vector<double> cpuSelect, gpuSelect, cpuDraw, gpuDraw, uniformDraw;
        uint64_t cpuTriangles = 0, gpuTriangles = 0, uniformTriangles = 0;
        for (int r = 0; r < o.repeats; ++r) {
            const auto start = std::chrono::steady_clock::now();
            const std::vector<ngi::TileSelection> selections = ngi::selectTilesInParallel(requests);
            cpuSelect.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            cpuTriangles = 0;
            for (const auto& s : selections) cpuTriangles += s.triangles;
            adaptive.clear();
            target.render(
                [&](VkCommandBuffer cmd) {
                    timestamps.write(cmd, 2, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
                    for (size_t k = 0; k < n; ++k) {
                        params.world = worlds[k];
                        adaptive.recordDraw(cmd, selections[k], params, target.extent());
                    }
                    timestamps.write(cmd, 3, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
                },
                {0, 0, 0, 1}, [&](VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, timestamps.pool.get(), 0, 4); });
            cpuDraw.push_back(timestamps.milliseconds(2));
            params.world.reset();
            target.render(
                [&](VkCommandBuffer cmd) {
                    timestamps.write(cmd, 2, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
                    gpuSelection.recordDraw(cmd, 0, params, target.extent());
                    timestamps.write(cmd, 3, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
                },
                {0, 0, 0, 1},
                [&](VkCommandBuffer cmd) {
                    vkCmdResetQueryPool(cmd, timestamps.pool.get(), 0, 4);
                    timestamps.write(cmd, 0, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
                    gpuSelection.recordSelect(cmd, jobs);
                    timestamps.write(cmd, 1, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
                });
            gpuSelect.push_back(timestamps.milliseconds(0));
            gpuDraw.push_back(timestamps.milliseconds(2));
            gpuTriangles = 0;
            for (const auto& j : gpuSelection.readFrame().jobs) gpuTriangles += j.triangles;
            batch.clear();
            for (const glm::mat4& world : worlds)
                batch.add(
                    surface, world,
                    ngi::instanceLod(metrics, metrics.geometricError, viewProjection, world, float(height), o.budget));
            ngi::vk::BatchParams batchParams;
            batchParams.viewProjection = viewProjection;
            ngi::vk::BatchStats uniform;
            target.render(
                [&](VkCommandBuffer cmd) {
                    timestamps.write(cmd, 2, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT);
                    uniform = batch.record(cmd, batchParams, target.extent());
                    timestamps.write(cmd, 3, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
                },
                {0, 0, 0, 1},
                [&](VkCommandBuffer cmd) {
                    vkCmdResetQueryPool(cmd, timestamps.pool.get(), 0, 4);
                    batch.recordGridExpansion(cmd);
                });
            uniformDraw.push_back(timestamps.milliseconds(2));
            uniformTriangles = uniform.triangles;
        }
        std::printf("| %u | %.2f | %.2f | %.2f | %.2f | %llu / %llu | %.2f | %llu |\n", n, median(cpuSelect),
                    median(gpuSelect), median(cpuDraw), median(gpuDraw), (unsigned long long)cpuTriangles,
                    (unsigned long long)gpuTriangles, median(uniformDraw), (unsigned long long)uniformTriangles);
        std::fflush(stdout);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        return run(parse(argc, argv));
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-bench-adaptive: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-adaptive: error: %s\n", e.what());
        return 1;
    }
}
