// ngi-bench-render: prints a table of GPU times (timestamps) for the buffer-less grid draw
// at each nested grid size against the same triangles drawn from an ordinary vertex + index
// buffer, the GPU restore + mip-chain build time, and the peak memory of the process.
// A benchmark, not a test: compare the ratios within one run.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/lod_grid.h"
#include "ngi/mip_pyramid.h"
#include "ngi_shared.h"
#include "ngi_shaders/indexed_mesh_vert.h"
#include "ngi_shaders/surface_frag.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr int kRepeats = 5;

struct Timer {
    const ngi::vk::Context& c;
    VkQueryPool pool = VK_NULL_HANDLE;
    explicit Timer(const ngi::vk::Context& context) : c(context)
    {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2;
        NGI_VK_CHECK(vkCreateQueryPool(c.device, &info, nullptr, &pool));
    }
    ~Timer() { vkDestroyQueryPool(c.device, pool, nullptr); }
    void reset(VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, pool, 0, 2); }
    void begin(VkCommandBuffer cmd) { vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool, 0); }
    void end(VkCommandBuffer cmd) { vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, 1); }
    double milliseconds() const
    {
        uint64_t t[2];
        NGI_VK_CHECK(vkGetQueryPoolResults(c.device, pool, 0, 2, sizeof(t), t, sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        return double(t[1] - t[0]) * c.properties.limits.timestampPeriod * 1e-6;
    }
};

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The drawn LoD mesh in ordinary vertex + index buffers (device-local, uploaded once).
struct IndexedMesh {
    ngi::vk::Buffer vertices, indices;
    uint32_t indexCount = 0;
};

IndexedMesh uploadMesh(const ngi::vk::Context& c, const ngi::LodMesh& mesh)
{
    std::vector<float> interleaved;
    interleaved.reserve(mesh.positions.size() * 6);
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        for (const glm::vec3& v : {mesh.positions[i], mesh.normals[i]}) interleaved.insert(interleaved.end(), {v.x, v.y, v.z});
    IndexedMesh m;
    m.indexCount = uint32_t(mesh.triangles.size() * 3);
    const VkDeviceSize vb = interleaved.size() * sizeof(float), ib = VkDeviceSize(m.indexCount) * sizeof(uint32_t);
    m.vertices = ngi::vk::createBuffer(c, vb, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    m.indices = ngi::vk::createBuffer(c, ib, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    ngi::vk::Buffer staging = ngi::vk::createBuffer(c, vb + ib, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    std::memcpy(staging.mapped, interleaved.data(), vb);
    std::memcpy(static_cast<char*>(staging.mapped) + vb, mesh.triangles.data(), ib);
    c.submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy a{0, 0, vb}, b{vb, 0, ib};
        vkCmdCopyBuffer(cmd, staging.buffer, m.vertices.buffer, 1, &a);
        vkCmdCopyBuffer(cmd, staging.buffer, m.indices.buffer, 1, &b);
        ngi::vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                               VK_PIPELINE_STAGE_VERTEX_INPUT_BIT,
                               VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT);
    });
    ngi::vk::destroyBuffer(c, staging);
    return m;
}

} // namespace

int main(int argc, char** argv)
{
    try {
        auto context = ngi::vk::Context::create({});
        const ngi::vk::Context& c = *context;
        ngi::vk::Renderer renderer(c, {});
        ngi::vk::RendererOptions nonIndexedOptions;
        nonIndexedOptions.quadIndexBuffer = false;
        ngi::vk::Renderer nonIndexed(c, nonIndexedOptions);  // same set layouts: draws the same surface
        ngi::Asset asset = argc > 1 ? ngi::readAsset(argv[1])
                                    : ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(1025), 3);
        // The largest chart is measured (a multi-part asset draws each chart the same way).
        const ngi::AssetChart& chart = asset.charts.at(0);
        std::printf("device: %s\nasset: %s, chart 0 of %zu, full %u^2 samples, stored %u^2\n\n", c.properties.deviceName,
                    asset.sourceName.c_str(), asset.charts.size(), chart.fullSize(), chart.storedSize());

        // Restore + mip chain + geomorph targets, timed on the GPU.
        std::vector<double> buildTimes;
        for (int i = 0; i < kRepeats; ++i) {
            auto s = ngi::vk::GeometryImageSurface::fromAsset(renderer, asset);
            Timer timer(c);
            c.submitAndWait([&](VkCommandBuffer cmd) {
                timer.reset(cmd);
                timer.begin(cmd);
                s.recordBuild(cmd);
                timer.end(cmd);
            });
            buildTimes.push_back(timer.milliseconds());
        }
        auto surface = ngi::vk::GeometryImageSurface::fromAsset(renderer, asset);
        c.submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
        surface.releaseUpload();
        std::printf("restore %u^2 -> %u^2 + mip chain + geomorph targets: %.2f ms (median of %d), GPU memory %.1f MiB\n\n",
                    chart.storedSize(), chart.fullSize(), median(buildTimes), kRepeats, surface.gpuBytes() / 1048576.0);

        // CPU pyramid of the same restored surface, for the indexed baseline meshes.
        ngi::GeometryImage p = ngi::storedPositions(chart), n = ngi::storedNormals(chart);
        for (uint32_t l = chart.storedLevel; l > 0; --l) {
            p = ngi::upsampleNested(p, false);
            n = ngi::upsampleNested(n, true);
        }
        const ngi::SurfacePyramid pyramid = ngi::buildSurfacePyramid(p, n);

        ngi::vk::GraphicsPipelineDesc desc;
        desc.vertexSpirv = indexed_mesh_vert_spv;
        desc.fragmentSpirv = surface_frag_spv;
        desc.layout = renderer.drawLayout();
        desc.pass = renderer.options().pass();
        desc.vertexBindings = {{0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
        desc.vertexAttributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)}};
        VkPipeline indexedPipeline = ngi::vk::createGraphicsPipeline(c.device, desc);

        ngi::vk::OffscreenTarget target(renderer, 512, 512);
        const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30, 30, 1.0f);
        Timer timer(c);
        std::printf("%-9s %10s %16s %16s %14s %8s %8s\n", "grid N", "triangles", "grid quad-ib ms", "grid 6/quad ms",
                    "mesh VB+IB ms", "ratio ib", "ratio 6");
        for (uint32_t level = 0; level < std::min(8u, surface.levelCount()); ++level) {
            ngi::vk::DrawParams params;
            params.viewProjection = camera.viewProjection(1.0f);
            params.eye = camera.eye();
            params.lod = float(level);
            std::vector<double> grid, grid6, indexed;
            for (int i = 0; i < kRepeats; ++i)
                for (auto* r : {&renderer, &nonIndexed}) {
                    target.render(
                        [&](VkCommandBuffer cmd) {
                            timer.begin(cmd);
                            r->recordDraw(cmd, surface, params, target.extent());
                            timer.end(cmd);
                        },
                        {0, 0, 0, 1}, [&](VkCommandBuffer cmd) { timer.reset(cmd); });
                    (r == &renderer ? grid : grid6).push_back(timer.milliseconds());
                }
            IndexedMesh mesh = uploadMesh(c, ngi::buildLodMesh(pyramid, float(level)));
            for (int i = 0; i < kRepeats; ++i) {
                target.render(
                    [&](VkCommandBuffer cmd) {
                        ngi::gpu::DrawPushConstants pc{};
                        pc.viewProjection = params.viewProjection;
                        pc.eye = glm::vec4(params.eye, 1.0f);
                        const VkViewport viewport{0, 0, 512, 512, 0, 1};
                        const VkRect2D scissor{{0, 0}, {512, 512}};
                        const VkDeviceSize offset = 0;
                        timer.begin(cmd);
                        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, indexedPipeline);
                        vkCmdSetViewport(cmd, 0, 1, &viewport);
                        vkCmdSetScissor(cmd, 0, 1, &scissor);
                        vkCmdPushConstants(cmd, renderer.drawLayout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                           0, sizeof(pc), &pc);
                        vkCmdBindVertexBuffers(cmd, 0, 1, &mesh.vertices.buffer, &offset);
                        vkCmdBindIndexBuffer(cmd, mesh.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
                        vkCmdDrawIndexed(cmd, mesh.indexCount, 1, 0, 0, 0);
                        timer.end(cmd);
                    },
                    {0, 0, 0, 1}, [&](VkCommandBuffer cmd) { timer.reset(cmd); });
                indexed.push_back(timer.milliseconds());
            }
            ngi::vk::destroyBuffer(c, mesh.vertices);
            ngi::vk::destroyBuffer(c, mesh.indices);
            const uint32_t size = surface.levelSize(level);
            const double g = median(grid), g6 = median(grid6), x = median(indexed);
            std::printf("%-9s %10llu %16.2f %16.2f %14.2f %8.2f %8.2f\n", (std::to_string(size) + "^2").c_str(),
                        (unsigned long long)ngi::gridTriangleCount(size), g, g6, x, g / x, g6 / x);
        }
        vkDestroyPipeline(c.device, indexedPipeline, nullptr);
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        std::printf("\npeak resident memory: %.1f MiB (median of %d runs per cell; ratio = grid / mesh VB+IB)\n",
                    usage.ru_maxrss / 1024.0, kRepeats);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-render: error: %s\n", e.what());
        return 1;
    }
}
