// ngi-bench-sr: GPU time (timestamps) of the super-resolution restore to 1025^2 samples in
// GLSL compute, per op kind, with the achieved GFLOP/s and the peak GPU memory; --sweep
// times the conv kernel shapes (output groups x pixels per invocation) the engine chooses
// between. A benchmark, not a test: compare ratios within one run.
//
//   ngi-bench-sr [--weights FILE.ngiw] [--repeats N] [--sweep] [--micro] [--sizes 65,129,257|none]
//
// --micro times single conv layers per kernel shape (the numbers behind the engine's choice).
//
// Without --weights: the default architecture (offline/nn architecture.h) with random
// weights, one model per scale factor (x16, x8, x4 for 65, 129, 257 samples).
#include "ngi/analytic_surfaces.h"
#include "ngi/engine/context.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr uint32_t kFullSize = 1025;

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
            net.parameters[(k < l.outChannels * fanIn ? l.weightOffset + k : l.biasOffset + k - l.outChannels * fanIn)] = u(rng);
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
        context.submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, &sr); });
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
                kFullSize, net.scaleFactor, net.name.c_str(), net.parameters.size(), net.parameters.size() * 4.0 / 1024.0,
                2e-9 * double(ngi::networkMultiplyAdds(net, stored)));
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
        if (k.macs) std::printf("%9.2f\n", 2e-6 * double(k.macs) / k.ms);
        else std::printf("%9s\n", "-");
    }
    std::printf("  %-16s %4zu %10.2f %6.1f%% %9.2f\n", "total", r.ops.size(), r.totalMs, 100.0, 2e-6 * double(macs) / r.totalMs);
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

void microbenchmarks(const ngi::vk::Context& context, int repeats)
{
    struct Layer {
        uint32_t in, out, kernel, size;
    };
    const Layer layers[] = {{32, 32, 3, 129}, {16, 192, 3, 129}, {32, 32, 1, 129}, {3, 32, 3, 129}, {3, 3, 3, 1025}};
    const uint32_t shapes[][2] = {{1, 1}, {1, 2}, {1, 3}, {1, 4}, {2, 1}, {2, 2}, {2, 4}, {4, 1}, {4, 2}};
    std::printf("\nconv microbenchmarks (one layer, median of %d, LeakyReLU): ms and GFLOP/s per kernel shape\n", repeats);
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

} // namespace

int main(int argc, char** argv)
{
    try {
        std::optional<std::string> weightsPath;
        int repeats = 3;
        bool sweep = false, micro = false;
        std::vector<uint32_t> sizes{65, 129, 257};
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            auto value = [&]() -> std::string {
                if (i + 1 >= argc) throw ngi::Error(a + " needs a value");
                return argv[++i];
            };
            if (a == "--weights") weightsPath = value();
            else if (a == "--repeats") repeats = std::max(1, std::stoi(value()));
            else if (a == "--sweep") sweep = true;
            else if (a == "--micro") micro = true;
            else if (a == "--sizes") {
                sizes.clear();
                std::string list = value();
                if (list == "none") continue;
                for (size_t at = 0; at < list.size();) {
                    const size_t comma = std::min(list.find(',', at), list.size());
                    sizes.push_back(uint32_t(std::stoul(list.substr(at, comma - at))));
                    at = comma + 1;
                }
            } else if (a == "--help" || a == "-h") {
                std::printf("usage: ngi-bench-sr [--weights FILE.ngiw] [--repeats N] [--sweep] [--micro] [--sizes 65,129,257|none]\n");
                return 0;
            } else throw ngi::Error("unknown argument '" + a + "' (see --help)");
        }
        auto context = ngi::vk::Context::create();
        ngi::vk::Renderer renderer(*context);
        std::printf("ngi-bench-sr on %s; GPU times from timestamps, best of %d runs after a warm-up\n",
                    context->properties.deviceName, repeats);

        if (micro) {
            microbenchmarks(*context, std::max(repeats, 3));
            if (!sweep && sizes.empty()) return 0;
        }
        std::optional<ngi::NetworkWeights> shipped;
        if (weightsPath) shipped = ngi::readNetworkWeights(*weightsPath);
        if (sweep) {
            // Conv kernel shapes on the x8 network at 129 -> 1025 (3x3 and 1x1 convs separately).
            const ngi::NetworkWeights net = shipped ? *shipped : defaultNetwork(8);
            const uint32_t stored = (kFullSize - 1) / net.scaleFactor + 1;
            std::printf("\nconv kernel sweep (%u -> %u): output groups of 4 x pixels per invocation\n", stored, kFullSize);
            std::printf("  %-8s %-6s %12s %10s %12s %10s\n", "groups", "pixels", "conv3x3 ms", "GFLOP/s", "conv1x1 ms", "GFLOP/s");
            const uint32_t shapes[][2] = {{1, 1}, {1, 4}, {2, 1}, {2, 2}, {2, 4}, {2, 8}, {4, 2}, {4, 4}, {8, 1}, {8, 2}};
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
        for (uint32_t stored : sizes) {
            if (!ngi::isNestedGridSize(stored) || stored >= kFullSize)
                throw ngi::Error("--sizes: " + std::to_string(stored) + " is not a nested level of 1025");
            const uint32_t factor = (kFullSize - 1) / (stored - 1);
            if (shipped && shipped->scaleFactor != factor) continue;
            const ngi::NetworkWeights net = shipped ? *shipped : defaultNetwork(factor);
            const RunResult r = timeRestore(renderer, net, stored, repeats, {});
            printTable(shipped ? "shipped weights" : "default architecture, random weights", stored, net, r);
            std::fflush(stdout);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-sr: %s\n", e.what());
        return 1;
    }
}
