// Whole-network parity of the engine's GLSL super-resolution against the libtorch module
// (offline/nn SuperResolutionNet) on the same random weights and input: max abs error
// <= 1e-4 on the [0,1] position scale. Only this test links libtorch; the engine never does.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/torch_network.h"

#include <cmath>
#include <random>

namespace {

using SrTorchParity = VulkanTest;

TEST_F(SrTorchParity, DefaultArchitectureMatchesLibtorchForward)
{
    torch::NoGradGuard noGrad;
    ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork({}, "parity");
    std::mt19937 rng(5);
    for (const ngi::NetworkLayer& l : net.layers) {
        if (l.kind != ngi::LayerKind::Conv) continue;
        const uint32_t fanIn = l.inChannels * l.kernelSize * l.kernelSize;
        std::uniform_real_distribution<float> u(-1.0f / std::sqrt(float(fanIn)), 1.0f / std::sqrt(float(fanIn)));
        for (uint32_t k = 0; k < l.outChannels * fanIn; ++k) net.parameters[l.weightOffset + k] = u(rng);
        for (uint32_t k = 0; k < l.outChannels; ++k) net.parameters[l.biasOffset + k] = 0.1f * u(rng);
    }
    const uint32_t h = 11, w = 17;
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(w, 0.1f);
    ngi::nn::FeatureMap positions(3, h, w), normals = positions;
    for (uint32_t c = 0; c < 3; ++c)
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                positions.data[(c * h + y) * w + x] = torus.positions.at(x, y)[c];
                normals.data[(c * h + y) * w + x] = torus.normals.at(x, y)[c];
            }
    auto toTorch = [&](const ngi::nn::FeatureMap& t) {
        return torch::from_blob(const_cast<float*>(t.data.data()), {1, 3, int64_t(h), int64_t(w)}, torch::kFloat32)
            .clone();
    };
    ngi::nn::SuperResolutionNet module(net, false);
    const torch::Tensor expected = module->forward(toTorch(positions), toTorch(normals)).contiguous();
    ngi::vk::SuperResolution sr(context(), net);
    const ngi::nn::FeatureMap got = sr.run(positions, normals);
    ASSERT_EQ(size_t(expected.numel()), got.data.size());
    const torch::Tensor gpu = torch::from_blob(const_cast<float*>(got.data.data()), expected.sizes(), torch::kFloat32);
    const double error = (gpu - expected).abs().max().item<double>();
    EXPECT_LE(error, 1e-4);
    RecordProperty("max_abs_error", ::testing::PrintToString(error));
}

}  // namespace
