// Each GLSL op of the super-resolution network (shaders/sr_*.comp) against the plain C++
// reference (ngi::nn, core/src/reference_forward.cpp) on odd shapes, validation on.
// Tolerance: max abs error <= 1e-5 on values of order 1 (fp32 accumulation in a different
// order), growing linearly past 256 products per output (1.1e-5 seen at 576); the data
// movement ops must be exact, the bilinear one within 1e-6.
#include "vulkan_fixture.h"

#include "ngi/engine/super_resolution.h"
#include "ngi/nn/reference_forward.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using ngi::nn::FeatureMap;

FeatureMap randomMap(uint32_t c, uint32_t h, uint32_t w, uint32_t seed)
{
    FeatureMap m(c, h, w);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& v : m.data) v = u(rng);
    return m;
}

float maxAbsDiff(const FeatureMap& a, const FeatureMap& b)
{
    EXPECT_EQ(a.channels, b.channels);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.width, b.width);
    if (a.data.size() != b.data.size()) return INFINITY;
    float m = 0.0f;
    for (size_t i = 0; i < a.data.size(); ++i) m = std::max(m, std::abs(a.data[i] - b.data[i]));
    return m;
}

struct ConvCase {
    uint32_t in, out, kernel;
    ngi::Padding padding;
    ngi::Activation activation;
    bool residual;
    ngi::vk::SrConvShape shape;
};

class SrOps : public VulkanTest {
protected:
    void checkConv(const ConvCase& c, uint32_t h, uint32_t w)
    {
        ngi::NetworkLayer l;
        l.kind = ngi::LayerKind::Conv;
        l.inChannels = c.in;
        l.outChannels = c.out;
        l.kernelSize = c.kernel;
        l.padding = c.padding;
        l.activation = c.activation;
        l.activationSlope = c.activation == ngi::Activation::LeakyReLU ? 0.1f : 0.0f;
        std::vector<float> params(7 + size_t(c.out) * c.in * c.kernel * c.kernel + c.out);
        std::mt19937 rng(c.in * 131 + c.out);
        std::uniform_real_distribution<float> u(-0.5f, 0.5f);
        for (float& p : params) p = u(rng);
        l.weightOffset = 7;  // not at 0: offsets must be honoured
        l.biasOffset = uint32_t(params.size()) - c.out;
        const FeatureMap in = randomMap(c.in, h, w, 1), res = randomMap(c.out, h, w, 2);
        const FeatureMap expected = ngi::nn::conv2d(in, l, params, c.residual ? &res : nullptr);
        std::vector<FeatureMap> inputs{in};
        if (c.residual) inputs.push_back(res);
        ngi::vk::SuperResolutionOptions options;
        (c.kernel == 3 ? options.conv3x3 : options.conv1x1) = c.shape;
        const FeatureMap got = ngi::vk::runSuperResolutionLayer(context(), l, params, inputs, w, h, options);
        const float tolerance = 1e-5f * std::max(1.0f, float(c.in * c.kernel * c.kernel) / 256.0f);
        EXPECT_LE(maxAbsDiff(got, expected), tolerance) << c.in << "->" << c.out << " k" << c.kernel;
    }
};

TEST_F(SrOps, Conv3x3ReplicateLeakyResidualOddShape)
{
    checkConv({5, 7, 3, ngi::Padding::Replicate, ngi::Activation::LeakyReLU, true, {}}, 7, 13);
}

TEST_F(SrOps, Conv3x3ZeroPaddingRelu)
{
    checkConv({5, 6, 3, ngi::Padding::Zero, ngi::Activation::ReLU, false, {}}, 7, 13);
}

TEST_F(SrOps, Conv1x1AndThreeInputChannels)
{
    checkConv({5, 9, 1, ngi::Padding::Zero, ngi::Activation::None, true, {}}, 7, 13);
    checkConv({3, 5, 3, ngi::Padding::Replicate, ngi::Activation::LeakyReLU, false, {}}, 11, 5);
}

TEST_F(SrOps, ConvEveryKernelShape)
{
    // Output groups and pixels per invocation that do not divide the shape.
    // (Each shape is a pipeline that lavapipe compiles for a second or two: keep them few.)
    for (const ngi::vk::SrConvShape shape : {ngi::vk::SrConvShape{1, 1}, ngi::vk::SrConvShape{3, 5}}) {
        checkConv({6, 13, 3, ngi::Padding::Replicate, ngi::Activation::None, false, shape}, 7, 13);
        checkConv({6, 13, 1, ngi::Padding::Zero, ngi::Activation::ReLU, true, shape}, 7, 13);
    }
}

TEST_F(SrOps, ConvWithManyInputAndOutputGroups)
{
    // 6 input groups (one weights block per output group, 10 blocks); the second case runs
    // 2 groups per invocation with a partial last block.
    checkConv({24, 40, 3, ngi::Padding::Replicate, ngi::Activation::LeakyReLU, true, {}}, 5, 9);
    checkConv({8, 22, 3, ngi::Padding::Zero, ngi::Activation::LeakyReLU, false, {}}, 5, 9);
}

void checkAttention(const ngi::vk::Context& context, uint32_t channels, uint32_t heads, uint32_t window, uint32_t h,
                    uint32_t w)
{
    ngi::NetworkLayer l;
    l.kind = ngi::LayerKind::NeighborhoodCrossAttention;
    l.inChannels = l.outChannels = channels;
    l.heads = heads;
    l.kernelSize = window;
    l.attentionScale = 1.0f / std::sqrt(float(channels / heads));
    const FeatureMap q = randomMap(channels, h, w, 3), k = randomMap(channels, h, w, 4),
                     v = randomMap(channels, h, w, 5);
    const FeatureMap expected = ngi::nn::neighborhoodCrossAttention(q, k, v, l);
    const FeatureMap inputs[3] = {q, k, v};
    const FeatureMap got = ngi::vk::runSuperResolutionLayer(context, l, {}, inputs, w, h);
    EXPECT_LE(maxAbsDiff(got, expected), 1e-5f) << channels << " channels " << heads << " heads " << window;
}

TEST_F(SrOps, AttentionHeadsAlignedWithChannelGroups) { checkAttention(context(), 12, 3, 3, 7, 13); }

TEST_F(SrOps, AttentionHeadsStraddlingChannelGroupsWideWindow)
{
    checkAttention(context(), 10, 2, 5, 7, 13);  // d = 5: heads cross vec4 groups; 5x5 masked at the border
    checkAttention(context(), 5, 1, 3, 2, 3);    // the window exceeds the image
}

TEST_F(SrOps, PixelShuffleCropIsExact)
{
    for (uint32_t f : {2u, 4u}) {
        const uint32_t c = f == 2 ? 5 : 3;
        const FeatureMap in = randomMap(c * f * f, 7, 13, 6);
        ngi::NetworkLayer l;
        l.kind = ngi::LayerKind::PixelShuffle;
        l.inChannels = c * f * f;
        l.outChannels = c;
        l.factor = f;
        const FeatureMap expected = ngi::nn::pixelShuffleCrop(in, f);
        const FeatureMap inputs[1] = {in};
        const FeatureMap got =
            ngi::vk::runSuperResolutionLayer(context(), l, {}, inputs, expected.width, expected.height);
        EXPECT_EQ(maxAbsDiff(got, expected), 0.0f) << "factor " << f;
    }
}

TEST_F(SrOps, SkipsMatchTheirReferences)
{
    // BilinearSkip: align_corners interpolation; CubicSkip: Catmull-Rom with linear
    // extrapolation beyond the border (ngi/network_weights.h).
    for (const ngi::LayerKind kind : {ngi::LayerKind::BilinearSkip, ngi::LayerKind::CubicSkip})
        for (uint32_t f : {2u, 8u}) {
            const FeatureMap coarse = randomMap(5, 7, 13, 7);
            const FeatureMap fine = randomMap(5, 6 * f + 1, 12 * f + 1, 8);
            ngi::NetworkLayer l;
            l.kind = kind;
            l.inChannels = l.outChannels = 5;
            l.factor = f;
            const FeatureMap expected = kind == ngi::LayerKind::CubicSkip ? ngi::nn::cubicSkip(coarse, fine, f)
                                                                          : ngi::nn::bilinearSkip(coarse, fine, f);
            const FeatureMap inputs[2] = {coarse, fine};
            const FeatureMap got = ngi::vk::runSuperResolutionLayer(context(), l, {}, inputs, fine.width, fine.height);
            EXPECT_LE(maxAbsDiff(got, expected), 2e-6f) << "kind " << uint32_t(kind) << " factor " << f;
        }
}

TEST_F(SrOps, HermiteSkipMatchesItsReference)
{
    for (uint32_t f : {2u, 8u}) {
        const FeatureMap coarse = randomMap(3, 7, 13, 9);
        FeatureMap normals = randomMap(3, 7, 13, 10);
        for (uint32_t y = 0; y < 7; ++y)
            for (uint32_t x = 0; x < 13; ++x) {
                float len = 0.0f;
                for (uint32_t c = 0; c < 3; ++c) len += normals.at(c, y, x) * normals.at(c, y, x);
                for (uint32_t c = 0; c < 3; ++c) normals.at(c, y, x) /= std::sqrt(len);
            }
        const FeatureMap fine = randomMap(3, 6 * f + 1, 12 * f + 1, 11);
        ngi::NetworkLayer l;
        l.kind = ngi::LayerKind::HermiteSkip;
        l.inChannels = l.outChannels = 3;
        l.factor = f;
        const FeatureMap expected = ngi::nn::hermiteSkip(coarse, normals, fine, f);
        const FeatureMap inputs[3] = {coarse, fine, normals};
        const FeatureMap got = ngi::vk::runSuperResolutionLayer(context(), l, {}, inputs, fine.width, fine.height);
        EXPECT_LE(maxAbsDiff(got, expected), 4e-6f) << "factor " << f;
    }
}

}  // namespace
