// ngi-bench-sr: GPU time (timestamps) of the super-resolution restore to 1025^2 samples in
// GLSL compute, per op kind, with the achieved GFLOP/s and the peak GPU memory; --sweep
// times the conv kernel shapes (output groups x pixels per invocation) the engine chooses
// between. A benchmark, not a test: compare ratios within one run.
//
//   ngi-bench-sr [--weights FILE.ngiw] [--repeats N] [--sweep] [--micro] [--sizes 33,65,129,257|none]
//                [--micro-shapes GxP,...] [--micro-layers IN-OUT-K-SIZE,...]
//                [--probe] [--cold-start] [--pipeline-cache FILE|none] [--json FILE]
//
// --micro times single conv layers per kernel shape (the numbers behind the engine's choice);
// --micro-shapes / --micro-layers replace its shapes (0x0: the engine's choice) and layers.
// --probe measures the driver's fp32 FMA peak with shaders/sr_fma_probe.comp (the ceiling).
// --cold-start times the network's load (pipeline compilation) and the first restore
// (wall clock), without a pipeline cache and with the on-disk one (--pipeline-cache,
// default ngi::vk::defaultPipelineCachePath; written back at the end).
// --json FILE also writes every figure as one JSON object (the tables still go to stdout).
//
// Without --weights: the default architecture (offline/nn architecture.h) with random
// weights, one model per scale factor (x32, x16, x8, x4 for 33, 65, 129, 257 samples).
#include "ngi/analytic_surfaces.h"
#include "ngi/command_line.h"
#include "ngi/engine/context.h"
#include "ngi/engine/pipeline_cache.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"
#include "ngi/output_files.h"

#include "ngi_shaders/sr_fma_probe_comp.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr uint32_t kFullSize = 1025;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The JSON report (--json): members appended as "key": value text.
struct Json {
    std::vector<std::string> members;
    void add(const std::string& key, const std::string& value) { members.push_back("\"" + key + "\": " + value); }
    static std::string str(const std::string& s)
    {
        std::string r = "\"";
        for (char c : s)
            if (c != '"' && c != '\\' && c >= ' ') r += c;
        return r + "\"";
    }
    static std::string num(double v)
    {
        char b[64];
        std::snprintf(b, sizeof b, "%.4f", v);
        return b;
    }
    static std::string object(const std::vector<std::pair<std::string, std::string>>& kv)
    {
        std::string r = "{";
        for (size_t i = 0; i < kv.size(); ++i) r += (i ? ", \"" : "\"") + kv[i].first + "\": " + kv[i].second;
        return r + "}";
    }
    static std::string array(const std::vector<std::string>& items)
    {
        std::string r = "[";
        for (size_t i = 0; i < items.size(); ++i) r += (i ? ", " : "") + items[i];
        return r + "]";
    }
};

ngi::NetworkWeights defaultNetwork(uint32_t factor)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = factor;
    ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(config, "random x" + std::to_string(factor));
    std::mt19937 rng(factor);
    for (const ngi::NetworkLayer& l : net.layers) {
        if (l.kind != ngi::LayerKind::Conv) continue;
        const uint32_t fanIn = l.inChannels * l.kernelSize * l.kernelSize;
        std::uniform_real_distribution<float> u(-1.0f / std::sqrt(float(fanIn)), 1.0f / std::sqrt(float(fanIn)));
        for (uint32_t k = 0; k < l.outChannels * fanIn + l.outChannels; ++k)
            net.parameters[(k < l.outChannels * fanIn ? l.weightOffset + k
                                                      : l.biasOffset + k - l.outChannels * fanIn)] = u(rng);
    }
    return net;
}

struct RunResult {
    double totalMs = 0.0;
    std::vector<ngi::vk::SrOpTiming> ops;
    uint64_t srBytes = 0, surfaceBytes = 0;
};

// One build of a 1025^2 surface restored by `net` from its stored level; returns the
// profile of the fastest of `repeats` runs (after one warm-up that compiles the pipelines).
RunResult timeRestore(const ngi::vk::Renderer& renderer, const ngi::NetworkWeights& net, uint32_t stored, int repeats,
                      const ngi::vk::SuperResolutionOptions& baseOptions)
{
    const ngi::vk::Context& context = renderer.context();
    static std::map<uint32_t, ngi::AnalyticSurface> levels;
    if (!levels.count(stored)) {
        static const ngi::AnalyticSurface full = ngi::rippledTorusGeometryImage(kFullSize, 0.1f);
        uint32_t steps = 0;
        while (ngi::mipLevelSize(kFullSize, steps) != stored) ++steps;
        levels[stored] = {ngi::downsampleNested(full.positions, steps), ngi::downsampleNested(full.normals, steps)};
    }
    const ngi::AnalyticSurface& level = levels[stored];
    ngi::vk::SuperResolutionOptions options = baseOptions;
    options.profile = true;
    ngi::vk::SuperResolution sr(context, net, options);
    RunResult best;
    for (int r = 0; r <= repeats; ++r) {
        ngi::vk::GeometryImageSurface surface(renderer, level.positions, level.normals, kFullSize);
        context.submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); });
        RunResult result;
        result.ops = sr.profile();
        for (const auto& op : result.ops) result.totalMs += op.milliseconds;
        result.srBytes = sr.gpuBytes();
        result.surfaceBytes = surface.gpuBytes();
        if (r > 0 && (best.ops.empty() || result.totalMs < best.totalMs)) best = result;
    }
    return best;
}

void printTable(const char* title, uint32_t stored, const ngi::NetworkWeights& net, const RunResult& r)
{
    std::printf("\n%s: %u -> %u (x%u), network '%s', %zu parameters (%.1f KiB fp32), %.2f GFLOP\n", title, stored,
                kFullSize, net.scaleFactor, net.name.c_str(), net.parameters.size(),
                net.parameters.size() * 4.0 / 1024.0, 2e-9 * double(ngi::networkMultiplyAdds(net, stored)));
    struct Kind {
        double ms = 0.0;
        uint64_t macs = 0;
        int ops = 0;
    };
    std::map<std::string, Kind> kinds;
    for (const auto& op : r.ops) {
        Kind& k = kinds[op.kind];
        k.ms += op.milliseconds;
        k.macs += op.multiplyAdds;
        ++k.ops;
    }
    std::printf("  %-16s %4s %10s %7s %9s\n", "op kind", "ops", "GPU ms", "share", "GFLOP/s");
    uint64_t macs = 0;
    for (const auto& [name, k] : kinds) {
        macs += k.macs;
        std::printf("  %-16s %4d %10.2f %6.1f%% ", name.c_str(), k.ops, k.ms, 100.0 * k.ms / r.totalMs);
        if (k.macs)
            std::printf("%9.2f\n", 2e-6 * double(k.macs) / k.ms);
        else
            std::printf("%9s\n", "-");
    }
    std::printf("  %-16s %4zu %10.2f %6.1f%% %9.2f\n", "total", r.ops.size(), r.totalMs, 100.0,
                2e-6 * double(macs) / r.totalMs);
    std::printf("  GPU memory: SR weights + tensors %.1f MiB, surface (levels, morph targets, diagonals) %.1f MiB\n",
                r.srBytes / 1048576.0, r.surfaceBytes / 1048576.0);
    std::printf("  per op:\n");
    for (const auto& op : r.ops) {
        std::printf("    %-48s %9.3f ms", op.name.c_str(), op.milliseconds);
        if (op.multiplyAdds) std::printf(" %7.2f GFLOP/s", 2e-6 * double(op.multiplyAdds) / op.milliseconds);
        std::printf("\n");
    }
}

ngi::nn::FeatureMap randomTensor(uint32_t c, uint32_t h, uint32_t w)
{
    ngi::nn::FeatureMap t(c, h, w);
    std::mt19937 rng(c * 7 + h);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& v : t.data) v = u(rng);
    return t;
}

// One conv layer alone, `repeats` times in one submission: median GPU ms.
double timeConv(const ngi::vk::Context& context, uint32_t in, uint32_t out, uint32_t kernel, uint32_t size,
                ngi::vk::SrConvShape shape, int repeats)
{
    ngi::NetworkLayer l;
    l.kind = ngi::LayerKind::Conv;
    l.inChannels = in;
    l.outChannels = out;
    l.kernelSize = kernel;
    l.padding = kernel == 3 ? ngi::Padding::Replicate : ngi::Padding::Zero;
    l.activation = ngi::Activation::LeakyReLU;
    l.activationSlope = 0.1f;
    std::vector<float> params(size_t(out) * in * kernel * kernel + out, 0.01f);
    l.biasOffset = uint32_t(params.size()) - out;
    const ngi::nn::FeatureMap inputs[1] = {randomTensor(in, size, size)};
    ngi::vk::SuperResolutionOptions options;
    options.conv3x3 = options.conv1x1 = shape;
    std::vector<double> ms(static_cast<size_t>(repeats));
    ngi::vk::runSuperResolutionLayer(context, l, params, inputs, size, size, options, &ms);
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

struct MicroLayer {
    uint32_t in, out, kernel, size;
};

// "A-B-C-D,..." -> rows of N unsigned numbers ("32-32-3-129" or "2x4").
std::vector<std::vector<uint32_t>> parseTuples(const std::string& list, char sep, size_t n, const std::string& option)
{
    std::vector<std::vector<uint32_t>> rows;
    for (size_t at = 0; at < list.size();) {
        const size_t comma = std::min(list.find(',', at), list.size());
        const std::string item = list.substr(at, comma - at);
        std::vector<uint32_t> row;
        for (size_t b = 0; b <= item.size();) {
            const size_t e = std::min(item.find(sep, b), item.size());
            try {
                row.push_back(uint32_t(ngi::parseIntegerOptionInRange(option, item.substr(b, e - b), 0, 1u << 20)));
            } catch (const std::exception&) {
                throw ngi::Error(option + ": '" + item + "' is not " + std::to_string(n) + " numbers separated by '" +
                                 sep + "'");
            }
            b = e + 1;
        }
        if (row.size() != n)
            throw ngi::Error(option + ": '" + item + "' is not " + std::to_string(n) + " numbers separated by '" + sep +
                             "'");
        rows.push_back(row);
        at = comma + 1;
    }
    return rows;
}

void microbenchmarks(const ngi::vk::Context& context, int repeats, std::vector<std::array<uint32_t, 2>> shapes,
                     std::vector<MicroLayer> layers)
{
    using Layer = MicroLayer;
    if (layers.empty())
        layers = {{32, 32, 3, 129}, {16, 192, 3, 129}, {32, 32, 1, 129}, {3, 32, 3, 129}, {3, 3, 3, 1025}};
    if (shapes.empty()) shapes = {{1, 1}, {1, 2}, {1, 3}, {1, 4}, {2, 1}, {2, 2}, {2, 4}, {4, 1}, {4, 2}};
    std::printf("\nconv microbenchmarks (one layer, median of %d, LeakyReLU): ms and GFLOP/s per kernel shape\n",
                repeats);
    std::printf("  %-22s", "groups x pixels");
    for (const Layer& l : layers) std::printf(" %4u->%-3u k%u %4u^2 ", l.in, l.out, l.kernel, l.size);
    std::printf("\n");
    for (const auto& s : shapes) {
        std::printf("  %-22s", (std::to_string(s[0]) + " x " + std::to_string(s[1])).c_str());
        for (const Layer& l : layers) {
            const double ms = timeConv(context, l.in, l.out, l.kernel, l.size, {s[0], s[1]}, repeats);
            const double flop = 2.0 * l.in * l.out * l.kernel * l.kernel * double(l.size) * l.size;
            std::printf(" %7.2f ms %6.2f GF/s", ms, flop * 1e-6 / ms);
            std::fflush(stdout);
        }
        std::printf("\n");
    }
}

// The driver's fp32 FMA peak: sr_fma_probe.comp over `invocations` with `iterations` rounds
// (64 FLOP each); the best GFLOP/s of `repeats` timed dispatches.
double fmaPeak(const ngi::vk::Context& context, int repeats)
{
    const VkDevice device = context.device;
    const uint32_t invocations = 64 * 1024, iterations = 4096;
    ngi::vk::Buffer out =
        ngi::vk::createBuffer(context, VkDeviceSize(invocations) * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT,
                                               nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 1;
    setInfo.pBindings = &binding;
    VkDescriptorSetLayout setLayout;
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout));
    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, 8};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &setLayout;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VkPipelineLayout layout;
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout));
    const VkPipeline pipeline = ngi::vk::createComputePipeline(device, layout, sr_fma_probe_comp_spv);
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    VkDescriptorPool pool;
    NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool));
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &setLayout;
    VkDescriptorSet set;
    NGI_VK_CHECK(vkAllocateDescriptorSets(device, &alloc, &set));
    const VkDescriptorBufferInfo info{out.buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(device, 1, &w, 0, nullptr);
    double best = 0.0;
    for (int r = 0; r <= repeats; ++r) {
        const auto start = Clock::now();
        context.submitAndWait([&](VkCommandBuffer cmd) {
            struct {
                uint32_t iterations;
                float seed;
            } pc{iterations, 0.5f};
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
            vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
            vkCmdDispatch(cmd, invocations / 64, 1, 1);
        });
        const double ms = msSince(start);
        if (r > 0) best = std::max(best, 64.0 * iterations * invocations * 1e-6 / ms);
    }
    vkDestroyDescriptorPool(device, pool, nullptr);
    vkDestroyPipeline(device, pipeline, nullptr);
    vkDestroyPipelineLayout(device, layout, nullptr);
    vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
    ngi::vk::destroyBuffer(context, out);
    return best;
}

struct ColdStart {
    std::string mode;
    double loadMs = 0.0, firstRestoreMs = 0.0, secondRestoreMs = 0.0;
    size_t pipelines = 0;
};

// Wall-clock time of loading `net` (weights upload + every pipeline compiled) and of its
// first and second 1025^2 restore (surface build, submit and wait), through `cache`.
ColdStart coldStart(const ngi::vk::Renderer& renderer, const ngi::NetworkWeights& net, const std::string& mode,
                    VkPipelineCache cache)
{
    const ngi::vk::Context& context = renderer.context();
    static const ngi::AnalyticSurface full = ngi::rippledTorusGeometryImage(kFullSize, 0.1f);
    const uint32_t stored = (kFullSize - 1) / net.scaleFactor + 1;
    uint32_t steps = 0;
    while (ngi::mipLevelSize(kFullSize, steps) != stored) ++steps;
    const ngi::GeometryImage p = ngi::downsampleNested(full.positions, steps),
                             n = ngi::downsampleNested(full.normals, steps);
    ColdStart r;
    r.mode = mode;
    auto start = Clock::now();
    ngi::vk::SuperResolutionOptions options;
    options.pipelineCache = cache;
    ngi::vk::SuperResolution sr(context, net, options);
    r.loadMs = msSince(start);
    r.pipelines = sr.pipelineCount();
    for (double* ms : {&r.firstRestoreMs, &r.secondRestoreMs}) {
        ngi::vk::GeometryImageSurface surface(renderer, p, n, kFullSize);
        start = Clock::now();
        context.submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); });
        sr.checkRestores();
        *ms = msSince(start);
    }
    return r;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        std::optional<std::string> weightsPath;
        int repeats = 3;
        bool sweep = false, micro = false, probe = false, cold = false;
        std::optional<std::string> cachePath, jsonPath;
        std::vector<uint32_t> sizes{33, 65, 129, 257};
        std::vector<std::array<uint32_t, 2>> microShapes;
        std::vector<MicroLayer> microLayers;
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            const std::string& a = args.flag();
            if (args.is("--weights"))
                weightsPath = args.value();
            else if (args.is("--repeats"))
                repeats = int(ngi::parseIntegerOptionInRange(a, args.value(), 1, 100000));
            else if (args.is("--sweep"))
                sweep = true;
            else if (args.is("--micro"))
                micro = true;
            else if (args.is("--micro-shapes"))
                for (const auto& r : parseTuples(args.value(), 'x', 2, a)) microShapes.push_back({r[0], r[1]});
            else if (args.is("--micro-layers"))
                for (const auto& r : parseTuples(args.value(), '-', 4, a))
                    microLayers.push_back({r[0], r[1], r[2], r[3]});
            else if (args.is("--probe"))
                probe = true;
            else if (args.is("--cold-start"))
                cold = true;
            else if (args.is("--pipeline-cache"))
                cachePath = args.value();
            else if (args.is("--json"))
                jsonPath = args.value();
            else if (args.is("--sizes")) {
                sizes.clear();
                std::string list = args.value();
                if (list == "none") continue;
                for (size_t at = 0; at < list.size();) {
                    const size_t comma = std::min(list.find(',', at), list.size());
                    sizes.push_back(
                        uint32_t(ngi::parseIntegerOptionInRange(a, list.substr(at, comma - at), 2, 1u << 16)));
                    at = comma + 1;
                }
            } else if (args.is("--help", "-h")) {
                std::printf(
                    "usage: ngi-bench-sr [--weights FILE.ngiw] [--repeats N] [--sweep] [--micro] [--sizes "
                    "33,65,129,257|none]\n"
                    "                    [--micro-shapes GxP,...] [--micro-layers IN-OUT-K-SIZE,...]\n"
                    "                    [--probe] [--cold-start] [--pipeline-cache FILE|none] [--json FILE]\n");
                return 0;
            } else
                throw args.unknown();
        }
        auto context = ngi::vk::Context::create();
        ngi::vk::Renderer renderer(*context);
        std::printf("ngi-bench-sr on %s; GPU times from timestamps, best of %d runs after a warm-up\n",
                    context->properties.deviceName, repeats);
        Json json;
        json.add("tool", Json::str("ngi-bench-sr"));
        json.add("device", Json::str(context->properties.deviceName));
        json.add("repeats", std::to_string(repeats));
        std::optional<ngi::NetworkWeights> shipped;
        if (weightsPath) shipped = ngi::readNetworkWeights(*weightsPath);
        if (cold) {
            // First: no cache at all (what every start paid before). Then the disk cache.
            const ngi::NetworkWeights net = shipped ? *shipped : defaultNetwork(8);
            std::vector<ColdStart> rows{coldStart(renderer, net, "no pipeline cache", VK_NULL_HANDLE)};
            const std::filesystem::path path = cachePath
                ? (*cachePath == "none" ? std::filesystem::path() : std::filesystem::path(*cachePath))
                : ngi::vk::defaultPipelineCachePath(*context);
            ngi::vk::PipelineCacheFile cache(*context, path);
            rows.push_back(coldStart(renderer, net,
                                     cache.loaded() ? "disk cache (loaded)" : "disk cache (" + cache.reason() + ")",
                                     cache.handle()));
            rows.push_back(coldStart(renderer, net, "same cache, warm", cache.handle()));
            const size_t bytes = cache.save();
            std::printf("\ncold start (wall clock, %u -> %u): network load = weights upload + %zu pipelines compiled;\n"
                        "pipeline cache %s (%zu bytes written)\n",
                        (kFullSize - 1) / net.scaleFactor + 1, kFullSize, rows[0].pipelines,
                        path.empty() ? "in memory" : path.c_str(), bytes);
            std::printf("  %-36s %10s %16s %16s %16s\n", "", "load ms", "1st restore ms", "2nd restore ms",
                        "load + 1st ms");
            std::vector<std::string> items;
            for (const ColdStart& r : rows) {
                std::printf("  %-36s %10.1f %16.1f %16.1f %16.1f\n", r.mode.c_str(), r.loadMs, r.firstRestoreMs,
                            r.secondRestoreMs, r.loadMs + r.firstRestoreMs);
                items.push_back(Json::object({{"mode", Json::str(r.mode)},
                                              {"load_ms", Json::num(r.loadMs)},
                                              {"first_restore_ms", Json::num(r.firstRestoreMs)},
                                              {"second_restore_ms", Json::num(r.secondRestoreMs)},
                                              {"pipelines", std::to_string(r.pipelines)}}));
            }
            json.add("cold_start", Json::array(items));
            std::fflush(stdout);
        }
        if (probe) {
            const double peak = fmaPeak(*context, std::max(repeats, 3));
            std::printf("\nFMA probe (shaders/sr_fma_probe.comp, 8 independent vec4 chains): %.1f GFLOP/s\n", peak);
            json.add("fma_peak_gflops", Json::num(peak));
            std::fflush(stdout);
        }

        if (micro) microbenchmarks(*context, std::max(repeats, 3), microShapes, microLayers);
        if (sweep) {
            // Conv kernel shapes on the x8 network at 129 -> 1025 (3x3 and 1x1 convs separately).
            const ngi::NetworkWeights net = shipped ? *shipped : defaultNetwork(8);
            const uint32_t stored = (kFullSize - 1) / net.scaleFactor + 1;
            std::printf("\nconv kernel sweep (%u -> %u): output groups of 4 x pixels per invocation\n", stored,
                        kFullSize);
            std::printf("  %-8s %-6s %12s %10s %12s %10s\n", "groups", "pixels", "conv3x3 ms", "GFLOP/s", "conv1x1 ms",
                        "GFLOP/s");
            const uint32_t shapes[][2] = {{1, 1}, {1, 4}, {2, 1}, {2, 2}, {2, 4},
                                          {2, 8}, {4, 2}, {4, 4}, {8, 1}, {8, 2}};
            for (const auto& s : shapes) {
                ngi::vk::SuperResolutionOptions options;
                options.conv3x3 = options.conv1x1 = {s[0], s[1]};
                const RunResult r = timeRestore(renderer, net, stored, repeats, options);
                double ms3 = 0, ms1 = 0;
                uint64_t mac3 = 0, mac1 = 0;
                for (const auto& op : r.ops) {
                    if (op.kind == "conv3x3") ms3 += op.milliseconds, mac3 += op.multiplyAdds;
                    if (op.kind == "conv1x1") ms1 += op.milliseconds, mac1 += op.multiplyAdds;
                }
                std::printf("  %-8u %-6u %12.2f %10.2f %12.2f %10.2f\n", s[0], s[1], ms3, 2e-6 * mac3 / ms3, ms1,
                            2e-6 * mac1 / ms1);
                std::fflush(stdout);
            }
        }
        std::vector<std::string> restores;
        for (uint32_t stored : sizes) {
            if (!ngi::isNestedGridSize(stored) || stored >= kFullSize)
                throw ngi::Error("--sizes: " + std::to_string(stored) + " is not a nested level of 1025");
            const uint32_t factor = (kFullSize - 1) / (stored - 1);
            if (shipped && shipped->scaleFactor != factor) continue;
            const ngi::NetworkWeights net = shipped ? *shipped : defaultNetwork(factor);
            const RunResult r = timeRestore(renderer, net, stored, repeats, {});
            printTable(shipped ? "shipped weights" : "default architecture, random weights", stored, net, r);
            std::fflush(stdout);
            std::vector<std::string> ops;
            for (const auto& op : r.ops)
                ops.push_back(Json::object({{"name", Json::str(op.name)},
                                            {"kind", Json::str(op.kind)},
                                            {"ms", Json::num(op.milliseconds)},
                                            {"multiply_adds", std::to_string(op.multiplyAdds)}}));
            restores.push_back(Json::object({{"network", Json::str(net.name)},
                                             {"stored", std::to_string(stored)},
                                             {"full", std::to_string(kFullSize)},
                                             {"gflop", Json::num(2e-9 * double(ngi::networkMultiplyAdds(net, stored)))},
                                             {"total_ms", Json::num(r.totalMs)},
                                             {"sr_bytes", std::to_string(r.srBytes)},
                                             {"surface_bytes", std::to_string(r.surfaceBytes)},
                                             {"ops", Json::array(ops)}}));
        }
        json.add("restores", Json::array(restores));
        if (jsonPath) {
            std::string text = "{";
            for (size_t i = 0; i < json.members.size(); ++i) text += (i ? ", " : "") + json.members[i];
            text += "}\n";
            ngi::writeFileAtomic(*jsonPath, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-sr: %s\n", e.what());
        return 1;
    }
}
