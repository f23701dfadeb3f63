// ngi-nn-bench: cost of the super-resolution network (paper section 3.2) per restore to
// 1024^2: parameters, bytes, GFLOP and the libtorch CPU forward time (median of --runs)
// for x4 (257 -> 1025), x8 (129 -> 1025), x16 (65 -> 1025) and x32 (33 -> 1025), plus the per-layer
// multiply-adds of the x8 network. A benchmark, not a test: times are noisy on a shared
// machine; compare ratios within one run.
//
//   ngi-nn-bench [--threads 2] [--runs 5] [--reference] [--weights FILE.ngiw] [--json FILE]
//
// --json FILE also writes the figures as one JSON object (the tables still go to stdout):
// {"tool", "threads", "runs", "networks": [{"name", "scale", "input", "parameters",
// "gflop", "libtorch_ms", "reference_ms" (null without --reference)}]}.
#include "ngi/error.h"
#include "ngi/command_line.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/nn/torch_network.h"
#include "ngi/output_files.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

const char* kindName(ngi::LayerKind k)
{
    switch (k) {
    case ngi::LayerKind::Conv: return "conv";
    case ngi::LayerKind::NeighborhoodCrossAttention: return "attention";
    case ngi::LayerKind::PixelShuffle: return "pixel shuffle";
    case ngi::LayerKind::BilinearSkip: return "bilinear skip";
    case ngi::LayerKind::CubicSkip: return "cubic skip";
    case ngi::LayerKind::HermiteSkip: return "hermite skip";
    }
    return "?";
}

const char* kUsage = "usage: ngi-nn-bench [--threads N] [--runs N] [--reference] [--weights FILE] [--json FILE]\n";

}  // namespace

int main(int argc, char** argv)
{
    try {
        int threads = 2, runs = 5;
        bool reference = false;
        std::string weightsPath, jsonPath;
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            const std::string& flag = args.flag();
            if (args.is("--reference"))
                reference = true;
            else if (args.is("--threads"))
                threads = int(ngi::parseIntegerOptionInRange(flag, args.value(), 1, 256));
            else if (args.is("--runs"))
                runs = int(ngi::parseIntegerOptionInRange(flag, args.value(), 1, 100000));
            else if (args.is("--weights"))
                weightsPath = args.value();
            else if (args.is("--json"))
                jsonPath = args.value();
            else if (args.is("-h", "--help")) {
                std::fputs(kUsage, stdout);
                return 0;
            } else
                throw args.unknown();
        }
        torch::set_num_threads(threads);
        std::printf(
            "libtorch CPU forward, %d thread(s), median of %d runs; GFLOP = 2 x multiply-adds (conv + attention)\n\n",
            threads, runs);
        std::printf("%-6s %-12s %9s %10s %8s %12s %14s\n", "scale", "restore", "params", "bytes", "GFLOP",
                    "libtorch ms", "reference ms");
        std::vector<ngi::NetworkWeights> networks;
        if (!weightsPath.empty())
            networks.push_back(ngi::readNetworkWeights(weightsPath));
        else
            for (uint32_t f : {4u, 8u, 16u, 32u}) {
                ngi::nn::SuperResolutionConfig c;
                c.scaleFactor = f;
                networks.push_back(ngi::nn::buildSuperResolutionNetwork(c, "bench-x" + std::to_string(f)));
            }
        std::string json = "{\"tool\": \"ngi-nn-bench\", \"threads\": " + std::to_string(threads) +
            ", \"runs\": " + std::to_string(runs) + ", \"networks\": [";
        for (const ngi::NetworkWeights& layout : networks) {
            const uint32_t f = layout.scaleFactor, n = 1024 / f + 1;
            ngi::nn::SuperResolutionNet net(layout, weightsPath.empty(), 1);
            net->eval();
            torch::NoGradGuard noGrad;
            const torch::Tensor positions = torch::rand({1, 3, n, n}), normals = torch::rand({1, 3, n, n});
            net->forward(positions, normals);  // warm-up
            std::vector<double> times;
            for (int r = 0; r < runs; ++r) {
                const auto start = Clock::now();
                const torch::Tensor out = net->forward(positions, normals);
                times.push_back(millisecondsSince(start));
                if (out.size(2) != 1025) throw ngi::Error("unexpected output size");
            }
            std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
            char referenceMs[32] = "-";
            if (reference) {
                const ngi::NetworkWeights weights = net->exportWeights();
                ngi::nn::FeatureMap p(3, n, n), q(3, n, n);
                std::copy(positions.data_ptr<float>(), positions.data_ptr<float>() + p.data.size(), p.data.begin());
                std::copy(normals.data_ptr<float>(), normals.data_ptr<float>() + q.data.size(), q.data.begin());
                const auto start = Clock::now();
                ngi::nn::referenceForward(weights, p, q);
                std::snprintf(referenceMs, sizeof referenceMs, "%.0f", millisecondsSince(start));
            }
            char restore[32];
            std::snprintf(restore, sizeof restore, "%u->1025", n);
            const double gflop = 2e-9 * double(ngi::networkMultiplyAdds(layout, n));
            std::printf("x%-5u %-12s %9zu %10zu %8.2f %12.1f %14s\n", f, restore, layout.parameters.size(),
                        layout.parameters.size() * sizeof(float), gflop, times[times.size() / 2], referenceMs);
            char entry[512];
            std::string name;
            for (char c : layout.name)
                if (c != '"' && c != '\\' && c >= ' ') name += c;
            std::snprintf(entry, sizeof entry,
                          "%s{\"name\": \"%s\", \"scale\": %u, \"input\": %u, \"parameters\": %zu, \"gflop\": %.4f, "
                          "\"libtorch_ms\": %.3f, \"reference_ms\": %s}",
                          &layout == &networks.front() ? "" : ", ", name.c_str(), f, n, layout.parameters.size(), gflop,
                          times[times.size() / 2], reference ? referenceMs : "null");
            json += entry;
        }
        json += "]}\n";
        if (!jsonPath.empty())
            ngi::writeFileAtomic(jsonPath, {reinterpret_cast<const uint8_t*>(json.data()), json.size()});

        const ngi::NetworkWeights& x8 = networks.size() > 1 ? networks[1] : networks[0];
        const uint32_t n = 1024 / x8.scaleFactor + 1;
        std::printf("\nlayers of %s (%s), input %u^2:\n", x8.name.c_str(), x8.metadata.c_str(), n);
        std::printf("%-4s %-14s %6s %6s %3s %10s %8s\n", "#", "op", "in", "out", "k", "grid", "GFLOP");
        const std::vector<ngi::TensorShape> shapes = ngi::validateNetwork(x8, x8.name);
        for (size_t i = 0; i < x8.layers.size(); ++i) {
            ngi::NetworkWeights one = x8;
            const ngi::NetworkLayer& l = x8.layers[i];
            const uint32_t side = (n - 1) * shapes[l.inputs[0]].gridFactor + 1;
            const uint64_t pixels = uint64_t(side) * side;
            uint64_t macs = 0;
            if (l.kind == ngi::LayerKind::Conv)
                macs = pixels * l.inChannels * l.outChannels * l.kernelSize * l.kernelSize;
            if (l.kind == ngi::LayerKind::NeighborhoodCrossAttention)
                macs = pixels * 2ull * l.inChannels * l.kernelSize * l.kernelSize;
            char grid[16];
            std::snprintf(grid, sizeof grid, "%u^2", side);
            std::printf("%-4zu %-14s %6u %6u %3u %10s %8.3f\n", i, kindName(l.kind), l.inChannels, l.outChannels,
                        l.kernelSize, grid, 2e-9 * double(macs));
        }
        return 0;
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-nn-bench: %s\n%s", e.what(), kUsage);
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-nn-bench: %s\n", e.what());
        return 1;
    }
}
