// The default super-resolution network as an op list. Paper: "Neural Geometry Image-Based
// Representations with Optimal Transport", section 3.2 and "Implementation Details"; the
// layer-by-layer description is in ngi/nn/architecture.h.
#include "ngi/nn/architecture.h"

#include "ngi/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ngi::nn {
namespace {

struct Builder {
    NetworkWeights net;
    uint32_t newTensor() { return net.tensorCount++; }

    uint32_t conv(uint32_t input, uint32_t in, uint32_t out, uint32_t kernel, Activation act, float slope,
                  uint32_t residual = kNoTensor)
    {
        NetworkLayer l;
        l.kind = LayerKind::Conv;
        l.inputs = {input, residual, kNoTensor};
        l.output = newTensor();
        l.inChannels = in;
        l.outChannels = out;
        l.kernelSize = kernel;
        l.padding = kernel == 3 ? Padding::Replicate : Padding::Zero;
        l.activation = act;
        l.activationSlope = act == Activation::LeakyReLU ? slope : 0.0f;
        l.weightOffset = uint32_t(net.parameters.size());
        net.parameters.resize(net.parameters.size() + size_t(out) * in * kernel * kernel);
        l.biasOffset = uint32_t(net.parameters.size());
        net.parameters.resize(net.parameters.size() + out);
        net.layers.push_back(l);
        return l.output;
    }
};

}  // namespace

NetworkWeights buildSuperResolutionNetwork(const SuperResolutionConfig& c, const std::string& name)
{
    const uint32_t f = c.scaleFactor;
    if (f < 2 || f > 64 || (f & (f - 1)))
        throw Error("network config: scale factor " + std::to_string(f) + " is not a power of two in [2, 64]");
    if (c.features == 0 || c.branchConvs == 0 || c.upsampleFeatures == 0 || c.attentionHeads == 0 ||
        c.features % c.attentionHeads != 0 || c.attentionWindow % 2 == 0 || !isSkip(c.skip))
        throw Error("network config: sizes must be positive, heads must divide features, the window must be odd, the "
                    "skip must be a skip kind");

    Builder b;
    b.net.name = name;
    b.net.metadata = "{\"architecture\":\"" + describe(c) + "\"}";
    b.net.scaleFactor = f;
    b.net.tensorCount = 2;
    const Activation act = c.activation;
    const float slope = c.activationSlope;
    const uint32_t F = c.features;

    auto branch = [&](uint32_t input) {
        uint32_t t = b.conv(input, 3, F, 3, act, slope);
        for (uint32_t i = 1; i < c.branchConvs; ++i) t = b.conv(t, F, F, 3, act, slope);
        return t;
    };
    const uint32_t P = branch(kPositionInputTensor);
    const uint32_t N = branch(kNormalInputTensor);

    const uint32_t q = b.conv(P, F, F, 1, Activation::None, 0.0f);
    const uint32_t k = b.conv(N, F, F, 1, Activation::None, 0.0f);
    const uint32_t v = b.conv(N, F, F, 1, Activation::None, 0.0f);
    NetworkLayer attention;
    attention.kind = LayerKind::NeighborhoodCrossAttention;
    attention.inputs = {q, k, v};
    attention.output = b.newTensor();
    attention.inChannels = attention.outChannels = F;
    attention.kernelSize = c.attentionWindow;
    attention.heads = c.attentionHeads;
    attention.attentionScale = 1.0f / std::sqrt(float(F / c.attentionHeads));
    b.net.layers.push_back(attention);
    uint32_t x = b.conv(attention.output, F, F, 1, Activation::None, 0.0f, P);

    for (uint32_t i = 0; i < c.resBlocks; ++i) {
        const uint32_t h = b.conv(x, F, F, 3, act, slope);
        x = b.conv(h, F, F, 3, Activation::None, 0.0f, x);
    }

    auto pixelShuffle = [&](uint32_t input, uint32_t outChannels, uint32_t factor) {
        NetworkLayer shuffle;
        shuffle.kind = LayerKind::PixelShuffle;
        shuffle.inputs = {input, kNoTensor, kNoTensor};
        shuffle.output = b.newTensor();
        shuffle.inChannels = outChannels * factor * factor;
        shuffle.outChannels = outChannels;
        shuffle.factor = factor;
        b.net.layers.push_back(shuffle);
        return shuffle.output;
    };
    const uint32_t U = c.upsampleFeatures;
    uint32_t u = b.conv(x, F, U, 1, act, slope);
    // Two stages where one sub-pixel conv would need more than kMaxNetworkChannels outputs
    // (x32: 3 x 32^2 = 3072): U features shuffled up by f / kLastStageFactor first.
    uint32_t last = f;
    if (3 * f * f > kMaxNetworkChannels) {
        last = kLastStageFactor;
        const uint32_t first = f / last;
        u = pixelShuffle(b.conv(u, U, U * first * first, 3, act, slope), U, first);
    }
    const uint32_t shuffled = pixelShuffle(b.conv(u, U, 3 * last * last, 3, Activation::None, 0.0f), 3, last);
    const uint32_t r = b.conv(shuffled, 3, 3, 3, Activation::None, 0.0f);

    NetworkLayer skip;
    skip.kind = c.skip;
    skip.inputs = {kPositionInputTensor, r, c.skip == LayerKind::HermiteSkip ? kNormalInputTensor : kNoTensor};
    skip.output = b.newTensor();
    skip.inChannels = skip.outChannels = 3;
    skip.factor = f;
    b.net.layers.push_back(skip);
    b.net.outputTensor = skip.output;

    validateNetwork(b.net, "network config");
    return b.net;
}

size_t transferParameters(NetworkWeights& network, const NetworkWeights& donor)
{
    if (network.layers.size() != donor.layers.size())
        throw Error("parameter transfer: " + donor.name + " has " + std::to_string(donor.layers.size()) + " layers, " +
                    network.name + " " + std::to_string(network.layers.size()) + ": not the same architecture");
    size_t copied = 0;
    for (size_t i = 0; i < network.layers.size(); ++i) {
        const NetworkLayer& to = network.layers[i];
        const NetworkLayer& from = donor.layers[i];
        if (to.kind != from.kind)
            throw Error("parameter transfer: layer " + std::to_string(i) + " differs in kind between " + donor.name +
                        " and " + network.name);
        if (to.kind != LayerKind::Conv) continue;
        const size_t taps = size_t(to.inChannels) * to.kernelSize * to.kernelSize;
        if (to.inChannels == from.inChannels && to.outChannels == from.outChannels &&
            to.kernelSize == from.kernelSize) {
            std::copy_n(donor.parameters.begin() + from.weightOffset, taps * to.outChannels,
                        network.parameters.begin() + to.weightOffset);
            std::copy_n(donor.parameters.begin() + from.biasOffset, to.outChannels,
                        network.parameters.begin() + to.biasOffset);
            ++copied;
            continue;
        }
        // The sub-pixel convolution: 3 * f^2 outputs here, 3 * F^2 in the donor.
        const uint32_t f = network.scaleFactor, F = donor.scaleFactor;
        const bool subPixel = i + 1 < network.layers.size() && network.layers[i + 1].kind == LayerKind::PixelShuffle &&
            to.inChannels == from.inChannels && to.kernelSize == from.kernelSize && to.outChannels == 3 * f * f &&
            from.outChannels == 3 * F * F && F % f == 0;
        if (!subPixel)
            throw Error("parameter transfer: layer " + std::to_string(i) + " of " + network.name +
                        " has another shape in " + donor.name);
        const uint32_t stride = F / f;
        for (uint32_t c = 0; c < 3; ++c)
            for (uint32_t y = 0; y < f; ++y)
                for (uint32_t x = 0; x < f; ++x) {
                    const size_t o = (size_t(c) * f + y) * f + x;
                    const size_t d = (size_t(c) * F + y * stride) * F + x * stride;
                    std::copy_n(donor.parameters.begin() + from.weightOffset + d * taps, taps,
                                network.parameters.begin() + to.weightOffset + o * taps);
                    network.parameters[to.biasOffset + o] = donor.parameters[from.biasOffset + d];
                }
        ++copied;
    }
    return copied;
}

std::string describe(const SuperResolutionConfig& c)
{
    const char* act = c.activation == Activation::LeakyReLU ? "lrelu"
        : c.activation == Activation::ReLU                  ? "relu"
                                                            : "linear";
    char text[160];
    std::snprintf(text, sizeof text, "x%u F%u branch%u heads%u window%u res%u U%u %s%.2g%s", c.scaleFactor, c.features,
                  c.branchConvs, c.attentionHeads, c.attentionWindow, c.resBlocks, c.upsampleFeatures, act,
                  c.activation == Activation::LeakyReLU ? double(c.activationSlope) : 0.0,
                  c.skip == LayerKind::HermiteSkip     ? " hermite"
                      : c.skip == LayerKind::CubicSkip ? " cubic"
                                                       : "");
    return text;
}

}  // namespace ngi::nn
