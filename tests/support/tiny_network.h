// Test support: the smallest super-resolution network of the weights format.
#pragma once

#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>

namespace ngi::test {

// The smallest network of the weights format that restores x`factor`: a 1x1 conv of the
// positions to 3 f^2 channels (all weights `w`), pixel shuffle, plus the bilinear upsampling
// of the positions. With w = 0 it reproduces bilinear restoration exactly.
inline ngi::NetworkWeights tinyNetwork(uint32_t factor, float w)
{
    ngi::NetworkWeights net;
    net.name = "tiny-x" + std::to_string(factor);
    net.scaleFactor = factor;
    const uint32_t channels = 3 * factor * factor;
    ngi::NetworkLayer conv;
    conv.kind = ngi::LayerKind::Conv;
    conv.inputs = {ngi::kPositionInputTensor, ngi::kNoTensor, ngi::kNoTensor};
    conv.output = 2;
    conv.inChannels = 3;
    conv.outChannels = channels;
    conv.kernelSize = 1;
    conv.weightOffset = 0;
    conv.biasOffset = 3 * channels;
    ngi::NetworkLayer shuffle;
    shuffle.kind = ngi::LayerKind::PixelShuffle;
    shuffle.inputs = {2, ngi::kNoTensor, ngi::kNoTensor};
    shuffle.output = 3;
    shuffle.inChannels = channels;
    shuffle.outChannels = 3;
    shuffle.factor = factor;
    ngi::NetworkLayer skip;
    skip.kind = ngi::LayerKind::BilinearSkip;
    skip.inputs = {ngi::kPositionInputTensor, 3, ngi::kNoTensor};
    skip.output = 4;
    skip.inChannels = 3;
    skip.outChannels = 3;
    skip.factor = factor;
    net.layers = {conv, shuffle, skip};
    net.tensorCount = 5;
    net.outputTensor = 4;
    net.parameters.assign(4 * channels, 0.0f);
    std::fill(net.parameters.begin(), net.parameters.begin() + 3 * channels, w);
    return net;
}

// The default architecture at its smallest that still has every op kind (x4, 4 features,
// one branch conv, 2 attention heads, one residual block), every parameter uniform in
// [-amplitude, amplitude] from `seed`.
// The default architecture at test size (4 features, one conv per branch, one res block).
inline ngi::nn::SuperResolutionConfig smallDefaultConfig(uint32_t factor = 4)
{
    ngi::nn::SuperResolutionConfig c;
    c.scaleFactor = factor;
    c.features = 4;
    c.branchConvs = 1;
    c.attentionHeads = 2;
    c.resBlocks = 1;
    c.upsampleFeatures = 2;
    return c;
}

inline ngi::NetworkWeights smallDefaultNetwork(const std::string& name, uint32_t seed, float amplitude)
{
    ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(smallDefaultConfig(), name);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-amplitude, amplitude);
    for (float& p : net.parameters) p = u(rng);
    return net;
}

}  // namespace ngi::test
