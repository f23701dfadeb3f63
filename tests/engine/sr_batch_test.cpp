// Several super-resolution restores by one SuperResolution in ONE command buffer (a regression:
// two surfaces restored in the same command buffer gave 1,842 validation errors and a wrong
// surface, because record() rewrote the descriptor sets the earlier restore had bound and
// replaced the tensors it was still using). Each restore now has its own descriptor sets and
// non-finite counter, tensors are kept per input size, and consecutive restores are ordered
// by a barrier. The validation layer is on (a message fails the test).
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/architecture.h"

#include <cmath>
#include <random>
#include <vector>

namespace {

ngi::NetworkWeights smallNetwork(uint32_t seed)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 4;
    config.features = 8;
    config.attentionHeads = 2;
    config.attentionWindow = 3;
    config.resBlocks = 1;
    config.upsampleFeatures = 4;
    ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(config, "batch");
    std::mt19937 rng(seed);
    for (const ngi::NetworkLayer& l : net.layers) {
        if (l.kind != ngi::LayerKind::Conv) continue;
        const uint32_t fanIn = l.inChannels * l.kernelSize * l.kernelSize;
        std::uniform_real_distribution<float> u(-0.5f / std::sqrt(float(fanIn)), 0.5f / std::sqrt(float(fanIn)));
        for (uint32_t k = 0; k < l.outChannels * fanIn; ++k) net.parameters[l.weightOffset + k] = u(rng);
        for (uint32_t k = 0; k < l.outChannels; ++k) net.parameters[l.biasOffset + k] = 0.1f * u(rng);
    }
    return net;
}

struct Input {
    ngi::GeometryImage positions, normals;
    uint32_t fullSize;
};

// The stored level of an analytic surface of `full` samples, two levels down (x4).
Input sphereInput(uint32_t full)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(full);
    return {ngi::downsampleNested(s.positions, 2), ngi::downsampleNested(s.normals, 2), full};
}

Input torusInput(uint32_t full)
{
    const ngi::AnalyticSurface s = ngi::rippledTorusGeometryImage(full, 0.1f);
    return {ngi::downsampleNested(s.positions, 2), ngi::downsampleNested(s.normals, 2), full};
}

using SrBatch = VulkanTest;

// Three restores (two input sizes, two of the same size with different inputs) recorded
// into one command buffer equal, bit for bit, the same restores each in its own submission
// by a fresh SuperResolution.
TEST_F(SrBatch, SeveralRestoresInOneCommandBufferEqualSeparateRestores)
{
    const ngi::NetworkWeights net = smallNetwork(7);
    const std::vector<Input> inputs = {sphereInput(65), torusInput(33), torusInput(65)};

    std::vector<std::vector<glm::uvec4>> separate;
    for (const Input& in : inputs) {
        ngi::vk::SuperResolution sr(context(), net);
        ngi::vk::GeometryImageSurface surface(renderer(), in.positions, in.normals, in.fullSize);
        context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); });
        sr.checkRestores();
        separate.push_back(surface.readLevel(0, false));
    }

    ngi::vk::SuperResolution sr(context(), net);
    std::vector<ngi::vk::GeometryImageSurface> surfaces;
    for (const Input& in : inputs) surfaces.emplace_back(renderer(), in.positions, in.normals, in.fullSize);
    context().submitAndWait([&](VkCommandBuffer cmd) {
        for (auto& s : surfaces) s.recordBuild(cmd, {&sr});
    });
    EXPECT_NO_THROW(sr.checkRestores());
    for (size_t i = 0; i < inputs.size(); ++i) {
        const std::vector<glm::uvec4> got = surfaces[i].readLevel(0, false);
        ASSERT_EQ(got.size(), separate[i].size()) << "restore " << i;
        size_t differing = 0;
        for (size_t t = 0; t < got.size(); ++t) differing += got[t] != separate[i][t];
        EXPECT_EQ(differing, 0u) << "restore " << i << ": texels differing from its own submission";
    }
    // The tensors of both input sizes are held until released.
    const VkDeviceSize withTensors = sr.gpuBytes();
    sr.releaseTensors();
    EXPECT_LT(sr.gpuBytes(), withTensors);

    // The object stays usable: a second batch after the check reuses the per-restore state.
    std::vector<ngi::vk::GeometryImageSurface> again;
    for (const Input& in : inputs) again.emplace_back(renderer(), in.positions, in.normals, in.fullSize);
    context().submitAndWait([&](VkCommandBuffer cmd) {
        for (auto& s : again) s.recordBuild(cmd, {&sr});
    });
    sr.checkRestores();
    for (size_t i = 0; i < inputs.size(); ++i) EXPECT_EQ(again[i].readLevel(0, false), separate[i]) << "restore " << i;
}

// A batch where one restore overflows: the check names the network and counts that
// restore's samples, whichever restore of the batch it was.
TEST_F(SrBatch, TheCheckCoversEveryRestoreOfTheBatch)
{
    ngi::NetworkWeights hostile = smallNetwork(9);
    for (float& p : hostile.parameters) p = p < 0.0f ? -3e38f : 3e38f;
    hostile.source = "hostile.ngiw";
    ngi::vk::SuperResolution sr(context(), hostile);
    const std::vector<Input> inputs = {sphereInput(65), torusInput(33)};
    std::vector<ngi::vk::GeometryImageSurface> surfaces;
    for (const Input& in : inputs) surfaces.emplace_back(renderer(), in.positions, in.normals, in.fullSize);
    context().submitAndWait([&](VkCommandBuffer cmd) {
        for (auto& s : surfaces) s.recordBuild(cmd, {&sr});
    });
    try {
        sr.checkRestores();
        FAIL() << "no error";
    } catch (const ngi::Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("hostile.ngiw: the restore produced non-finite values (", 0), 0u) << message;
    }
    EXPECT_NO_THROW(sr.checkRestores());  // checked once: the batch is done
}

}  // namespace
