// ngi-bench-render: prints a table of GPU times (timestamps) for the grid draw at each
// nested grid size -- per quad with no index data (the shared quad index buffer, or 6
// vertices per quad), and with shared vertices through the level's index buffer expanded
// at run time (the expansion's own time, the draw alone with the expansion cached, the two
// in one frame, and frames whose LoD moves every frame: a geomorphing level, expanded and
// drawn each frame) -- against the same triangles drawn from an ordinary vertex + index
// buffer, the GPU restore + mip-chain build time, and the peak memory of the process.
// A benchmark, not a test: compare the ratios within one run. --json PATH writes the same
// figures for scripts.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/lod_grid.h"
#include "ngi/mip_pyramid.h"
#include "ngi/output_files.h"
#include "ngi_shared.h"
#include "ngi_shaders/indexed_mesh_vert.h"
#include "ngi_shaders/surface_frag.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// Timestamp pairs: span k is timed by begin(cmd, k) .. end(cmd, k).
struct Timer {
    const ngi::vk::Context& c;
    static constexpr uint32_t kSpans = 2;
    VkQueryPool pool = VK_NULL_HANDLE;
    explicit Timer(const ngi::vk::Context& context) : c(context)
    {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2 * kSpans;
        NGI_VK_CHECK(vkCreateQueryPool(c.device, &info, nullptr, &pool));
    }
    ~Timer() { vkDestroyQueryPool(c.device, pool, nullptr); }
    void reset(VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, pool, 0, 2 * kSpans); }
    void begin(VkCommandBuffer cmd, uint32_t span = 0)
    {
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool, 2 * span);
    }
    void end(VkCommandBuffer cmd, uint32_t span = 0)
    {
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, 2 * span + 1);
    }
    double milliseconds(uint32_t span = 0) const
    {
        uint64_t t[2];
        NGI_VK_CHECK(vkGetQueryPoolResults(c.device, pool, 2 * span, 2, sizeof(t), t, sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        return double(t[1] - t[0]) * c.properties.limits.timestampPeriod * 1e-6;
    }
};

// CPU time of the whole process so far (ms): every thread's, lavapipe's rasterizer included.
double cpuMilliseconds()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

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
        for (const glm::vec3& v : {mesh.positions[i], mesh.normals[i]})
            interleaved.insert(interleaved.end(), {v.x, v.y, v.z});
    IndexedMesh m;
    m.indexCount = uint32_t(mesh.triangles.size() * 3);
    const VkDeviceSize vb = interleaved.size() * sizeof(float), ib = VkDeviceSize(m.indexCount) * sizeof(uint32_t);
    m.vertices = ngi::vk::createBuffer(c, vb, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    m.indices = ngi::vk::createBuffer(c, ib, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    ngi::vk::Buffer staging =
        ngi::vk::createBuffer(c, vb + ib, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
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

// ngi-bench-render [asset.ngi] [--repeats N] [--best] [--cpu] [--level L]... [--json PATH]:
// N runs per cell (default 5), the median of each (or with --best the fastest: on a machine
// shared with other jobs, a burst of load only ever slows a run down); with --cpu each cell
// is the process's CPU time for the frame less an empty frame's, not the GPU timestamps (on
// a software device, the work done, which the other jobs' load does not stretch; expand is
// then exp+shr - shared); only the levels L given (default: the 8 finest drawn); the table
// also as JSON in PATH.
struct Options {
    std::string asset;
    int repeats = 5;
    std::vector<uint32_t> levels;
    std::string json;
    bool best = false;
    bool cpu = false;
};

// One row of the table (ms, medians or best).
struct Row {
    uint32_t gridSize = 0;
    uint64_t triangles = 0;
    double quadIndexed = 0, nonIndexed = 0, expand = 0, shared = 0, expandShared = 0, mesh = 0;
    double moving = -1, movingExpand = -1;  // < 0: not measured (the coarsest drawn level does not geomorph)
};

// `text` as a JSON string's contents (quotes, backslashes and control characters escaped).
std::string jsonEscaped(const std::string& text)
{
    std::string out;
    for (const char ch : text) {
        if (ch == '"' || ch == '\\') out += '\\';
        if (static_cast<unsigned char>(ch) < 0x20) {
            char code[8];
            std::snprintf(code, sizeof(code), "\\u%04x", unsigned(ch));
            out += code;
        } else {
            out += ch;
        }
    }
    return out;
}

// printf into `out`.
template <class... Args> void appendFormatted(std::string& out, const char* format, Args... args)
{
    const int n = std::snprintf(nullptr, 0, format, args...);
    if (n <= 0) return;
    const size_t at = out.size();
    out.resize(at + size_t(n) + 1);
    std::snprintf(out.data() + at, size_t(n) + 1, format, args...);
    out.resize(at + size_t(n));
}

// Written through the one output stager (ngi/output_files.h), like every tool's outputs.
void writeJson(const std::string& path, const std::string& device, const std::string& asset, double buildMs,
               int repeats, bool best, bool cpu, const std::vector<Row>& rows)
{
    std::string json;
    appendFormatted(json,
                    "{\n  \"device\": \"%s\",\n  \"asset\": \"%s\",\n  \"repeats\": %d,\n  \"statistic\": \"%s\",\n"
                    "  \"time\": \"%s\",\n  \"buildMs\": %.3f,\n  \"grids\": [",
                    jsonEscaped(device).c_str(), jsonEscaped(asset).c_str(), repeats, best ? "best" : "median",
                    cpu ? "process CPU" : "GPU timestamps", buildMs);
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        appendFormatted(
            json,
            "%s\n    {\"gridSize\": %u, \"triangles\": %llu, \"quadIndexedMs\": %.3f, \"nonIndexedMs\": %.3f, "
            "\"expandMs\": %.3f, \"sharedMs\": %.3f, \"expandSharedMs\": %.3f, \"movingLodExpandMs\": %s, "
            "\"movingLodMs\": %s, \"meshMs\": %.3f}",
            i ? "," : "", r.gridSize, (unsigned long long)r.triangles, r.quadIndexed, r.nonIndexed, r.expand, r.shared,
            r.expandShared, r.movingExpand < 0 ? "null" : std::to_string(r.movingExpand).c_str(),
            r.moving < 0 ? "null" : std::to_string(r.moving).c_str(), r.mesh);
    }
    json += "\n  ]\n}\n";
    ngi::writeFileAtomic(path, {reinterpret_cast<const uint8_t*>(json.data()), json.size()});
}

const char* kUsage =
    "usage: ngi-bench-render [ASSET.ngi] [--repeats N] [--level L]... [--best] [--cpu] [--json PATH]\n"
    "Without ASSET: an analytic rippled torus. --level L: time level L (repeatable; default every\n"
    "level drawn); --best: the best run, not the median; --cpu: process CPU time, not GPU timestamps.\n";

// The command line; UsageError for anything malformed. --help prints kUsage and exits 0.
Options parseOptions(int argc, char** argv)
{
    Options o;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--repeats"))
            o.repeats = int(ngi::parseIntegerOptionInRange(a, args.value(), 1, 1000));
        else if (args.is("--best"))
            o.best = true;
        else if (args.is("--cpu"))
            o.cpu = true;
        else if (args.is("--level"))
            o.levels.push_back(uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 31)));
        else if (args.is("--json"))
            o.json = args.value();
        else if (args.is("-h", "--help")) {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (args.positional() && o.asset.empty())
            o.asset = a;
        else if (args.positional())
            throw ngi::UsageError("more than one asset: " + o.asset + ", " + a);
        else
            throw args.unknown();
    }
    return o;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        const Options options = parseOptions(argc, argv);
        const int repeats = options.repeats;
        auto context = ngi::vk::Context::create({});
        const ngi::vk::Context& c = *context;
        ngi::vk::Renderer renderer(c, {});
        ngi::vk::RendererOptions nonIndexedOptions;
        nonIndexedOptions.quadIndexBuffer = false;
        nonIndexedOptions.gridExpansion = false;
        ngi::vk::Renderer nonIndexed(c, nonIndexedOptions);  // same set layouts: draws the same surface
        ngi::Asset asset = !options.asset.empty()
            ? ngi::readAsset(options.asset)
            : ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(1025), 3);
        // The largest chart is measured (a multi-part asset draws each chart the same way).
        const ngi::AssetChart& chart = asset.charts.at(0);
        std::printf("device: %s\nasset: %s, chart 0 of %zu, full %u^2 samples, stored %u^2\n\n",
                    c.properties.deviceName, asset.sourceName.c_str(), asset.charts.size(), chart.fullSize(),
                    chart.storedSize());

        // Restore + mip chain + geomorph targets, timed on the GPU.
        std::vector<double> buildTimes;
        for (int i = 0; i < repeats; ++i) {
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
        std::printf("restore %u^2 -> %u^2 (bicubic) + mip chain + geomorph targets: %.2f ms (median of %d), GPU memory "
                    "%.1f MiB\n\n",
                    chart.storedSize(), chart.fullSize(), median(buildTimes), repeats, surface.gpuBytes() / 1048576.0);

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
        desc.vertexAttributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                 {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)}};
        VkPipeline indexedPipeline = ngi::vk::createGraphicsPipeline(c.device, desc);

        ngi::vk::OffscreenTarget target(renderer, 512, 512);
        const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30, 30, 1.0f);
        Timer timer(c);
        std::vector<Row> rows;
        std::printf("%-7s %9s | %8s %8s | %8s %8s %8s %8s %8s | %8s | %6s %6s %6s %6s %6s\n", "grid N", "triangles",
                    "quad-ib", "6/quad", "expand", "shared", "exp+shr", "m-exp", "moving", "mesh", "r ib", "r 6",
                    "r shr", "r e+s", "r mov");
        // Only the levels a draw shows (drawnLevelCount: a coarser LoD draws the coarsest of them).
        for (uint32_t level = 0; level < std::min(8u, surface.drawnLevelCount()); ++level) {
            if (!options.levels.empty() &&
                std::find(options.levels.begin(), options.levels.end(), level) == options.levels.end())
                continue;
            ngi::vk::DrawParams params;
            params.viewProjection = camera.viewProjection(1.0f);
            params.eye = camera.eye();
            params.lod = float(level);
            // Per quad: the renderer's own with no expansion recorded, and the non-indexed one.
            std::vector<double> grid, grid6, expand, shared, expandShared, moving, movingExpand, indexed;
            const bool geomorphs = level + 1 < surface.drawnLevelCount();
            // --cpu: the process's CPU time of a frame (lavapipe's threads are the process's)
            // less that of an empty frame of the same round (the same clear and read-back).
            double emptyCpu = 0.0;
            auto cpuOf = [&](auto&& frame) {
                const double t0 = cpuMilliseconds();
                frame();
                return cpuMilliseconds() - t0 - emptyCpu;
            };
            auto timedDraw = [&](const ngi::vk::Renderer& r) {
                const double cpu = cpuOf([&] {
                    target.render(
                        [&](VkCommandBuffer cmd) {
                            timer.begin(cmd);
                            const ngi::vk::DrawStats stats = r.recordDraw(cmd, surface, params, target.extent());
                            timer.end(cmd);
                            if (stats.sharedVertices) throw std::runtime_error("a per-quad draw drew shared vertices");
                        },
                        {0, 0, 0, 1}, [&](VkCommandBuffer cmd) { timer.reset(cmd); });
                });
                return options.cpu ? cpu : timer.milliseconds();
            };
            IndexedMesh mesh = uploadMesh(c, ngi::buildLodMesh(pyramid, float(level)));
            // Every way once per round, so that a burst of load on the shared machine falls on
            // all of them alike.
            for (int i = 0; i < repeats; ++i) {
                emptyCpu = 0.0;
                emptyCpu = cpuOf([&] { target.render([](VkCommandBuffer) {}, {0, 0, 0, 1}); });
                surface.releaseGridExpansions();  // nothing expanded: per quad
                grid.push_back(timedDraw(renderer));
                grid6.push_back(timedDraw(nonIndexed));
                // Shared vertices: a frame that expands the level (none cached) and draws it,
                // then a frame with the expansion cached (the draw alone).
                const double expandSharedCpu = cpuOf([&] {
                    target.render(
                        [&](VkCommandBuffer cmd) {
                            timer.begin(cmd, 1);
                            const ngi::vk::DrawStats stats = renderer.recordDraw(cmd, surface, params, target.extent());
                            timer.end(cmd, 1);
                            if (!stats.sharedVertices) throw std::runtime_error("the expanded draw is not shared");
                        },
                        {0, 0, 0, 1},
                        [&](VkCommandBuffer cmd) {
                            timer.reset(cmd);
                            timer.begin(cmd, 0);
                            if (renderer.recordGridExpansion(cmd, surface, params) != 1)
                                throw std::runtime_error("no grid expansion was recorded");
                            timer.end(cmd, 0);
                        });
                });
                const double expandMs = timer.milliseconds(0),
                             expandSharedMs = timer.milliseconds(0) + timer.milliseconds(1);
                const double sharedCpu = cpuOf([&] {
                    target.render(
                        [&](VkCommandBuffer cmd) {
                            timer.begin(cmd);
                            const ngi::vk::DrawStats stats = renderer.recordDraw(cmd, surface, params, target.extent());
                            timer.end(cmd);
                            if (!stats.sharedVertices) throw std::runtime_error("the cached draw is not shared");
                        },
                        {0, 0, 0, 1},
                        [&](VkCommandBuffer cmd) {
                            timer.reset(cmd);
                            if (renderer.recordGridExpansion(cmd, surface, params) != 0)
                                throw std::runtime_error("the cached expansion was recorded again");
                        });
                });
                shared.push_back(options.cpu ? sharedCpu : timer.milliseconds());
                expand.push_back(options.cpu ? expandSharedCpu - sharedCpu : expandMs);
                expandShared.push_back(options.cpu ? expandSharedCpu : expandSharedMs);
                // The LoD moves every frame: a geomorphing level (factor 0.25 .. 0.75, a new one
                // each round), expanded and drawn in a frame; then the frame timed, the LoD
                // 0.01 further on (a zoom over 100 frames per level), expanded and drawn. The
                // coarsest drawn level has nothing to geomorph to.
                ngi::vk::DrawParams movingParams = params;
                const float movingLod = float(level) + 0.25f + 0.5f * float(i + 1) / float(repeats + 1);
                double movingCpu = 0.0;
                for (const float lod : {movingLod, movingLod + 0.01f}) {
                    movingParams.lod = lod;
                    movingCpu = !geomorphs ? 0.0 : cpuOf([&] {
                        target.render(
                            [&](VkCommandBuffer cmd) {
                                timer.begin(cmd, 1);
                                const ngi::vk::DrawStats stats =
                                    renderer.recordDraw(cmd, surface, movingParams, target.extent());
                                timer.end(cmd, 1);
                                if (!stats.sharedVertices || stats.morph <= 0.0f)
                                    throw std::runtime_error("the moving-LoD draw is not a shared geomorphing one");
                            },
                            {0, 0, 0, 1},
                            [&](VkCommandBuffer cmd) {
                                timer.reset(cmd);
                                timer.begin(cmd, 0);
                                if (renderer.recordGridExpansion(cmd, surface, movingParams) != 1)
                                    throw std::runtime_error("the moving LoD was not expanded");
                                timer.end(cmd, 0);
                            });
                    });
                }
                if (geomorphs) {
                    moving.push_back(options.cpu ? movingCpu : timer.milliseconds(0) + timer.milliseconds(1));
                    movingExpand.push_back(timer.milliseconds(0));  // GPU time in both modes
                }
                const double meshCpu = cpuOf([&] {
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
                            vkCmdPushConstants(cmd, renderer.drawLayout(),
                                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(pc),
                                               &pc);
                            vkCmdBindVertexBuffers(cmd, 0, 1, &mesh.vertices.buffer, &offset);
                            vkCmdBindIndexBuffer(cmd, mesh.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
                            vkCmdDrawIndexed(cmd, mesh.indexCount, 1, 0, 0, 0);
                            timer.end(cmd);
                        },
                        {0, 0, 0, 1}, [&](VkCommandBuffer cmd) { timer.reset(cmd); });
                });
                indexed.push_back(options.cpu ? meshCpu : timer.milliseconds());
            }
            surface.releaseGridExpansions();
            ngi::vk::destroyBuffer(c, mesh.vertices);
            ngi::vk::destroyBuffer(c, mesh.indices);
            const uint32_t size = surface.levelSize(level);
            auto cell = [&](const std::vector<double>& v) {
                return options.best ? *std::min_element(v.begin(), v.end()) : median(v);
            };
            const double g = cell(grid), g6 = cell(grid6), e = cell(expand), sh = cell(shared), es = cell(expandShared),
                         mv = geomorphs ? cell(moving) : -1.0, me = geomorphs ? cell(movingExpand) : -1.0,
                         x = cell(indexed);
            char movingCell[32] = "       -        -", movingRatio[16] = "     -";
            if (geomorphs) {
                std::snprintf(movingCell, sizeof(movingCell), "%8.2f %8.2f", me, mv);
                std::snprintf(movingRatio, sizeof(movingRatio), "%6.2f", mv / x);
            }
            std::printf("%-7s %9llu | %8.2f %8.2f | %8.2f %8.2f %8.2f %s | %8.2f | %6.2f %6.2f %6.2f %6.2f %s\n",
                        (std::to_string(size) + "^2").c_str(), (unsigned long long)ngi::gridTriangleCount(size), g, g6,
                        e, sh, es, movingCell, x, g / x, g6 / x, sh / x, es / x, movingRatio);
            std::fflush(stdout);
            Row row{size, ngi::gridTriangleCount(size), g, g6, e, sh, es, x};
            row.moving = mv;
            row.movingExpand = me;
            rows.push_back(row);
        }
        vkDestroyPipeline(c.device, indexedPipeline, nullptr);
        rusage usage{};
        getrusage(RUSAGE_SELF, &usage);
        std::printf("\nms %s, %s of %d runs per cell, 512x512 target. quad-ib: per quad\n"
                    "through the shared quad index buffer (4 vertices per quad); 6/quad: per quad, non-indexed;\n"
                    "expand: the grid expansion alone (compute: the level's index buffer with the diagonals);\n"
                    "shared: the shared-vertex draw with the expansion cached (a still LoD); exp+shr: expansion and\n"
                    "draw in one frame (the LoD changed, a new buffer); moving: the same at a geomorphing LoD 0.01\n"
                    "on from the previous frame's (level + 0.25 .. 0.75; the same buffer rewritten), m-exp its\n"
                    "expansion (GPU time); - at the coarsest drawn level, which does not geomorph;\n"
                    "mesh: the same triangles from an ordinary vertex + index buffer, uploaded once. r x = x / mesh.\n"
                    "peak resident memory: %.1f MiB\n",
                    options.cpu ? "of process CPU time (--cpu)" : "on the GPU (timestamps)",
                    options.best ? "best" : "median", repeats, usage.ru_maxrss / 1024.0);
        if (!options.json.empty())
            writeJson(options.json, c.properties.deviceName, asset.sourceName, median(buildTimes), repeats,
                      options.best, options.cpu, rows);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-render: error: %s\n", e.what());
        return 1;
    }
}
