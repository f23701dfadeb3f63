// The whole super-resolution network in GLSL against the C++ reference forward
// (ngi::nn::referenceForward) on random weights, and the GeometryImageSurface hook that
// writes level 0 with it. Parity tolerance: max abs error <= 1e-4 on the [0,1] position scale.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/octahedral.h"
#include "hostile_networks.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

namespace {

using ngi::nn::FeatureMap;

// Random parameters of roughly unit-variance activations (uniform, +-1/sqrt(fan-in)); the
// last conv (the residual the network learns) is scaled by `residualScale`.
ngi::NetworkWeights randomNetwork(const ngi::nn::SuperResolutionConfig& config, uint32_t seed, float residualScale)
{
    ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(config, "random");
    std::mt19937 rng(seed);
    size_t lastConv = 0;
    for (size_t i = 0; i < net.layers.size(); ++i)
        if (net.layers[i].kind == ngi::LayerKind::Conv) lastConv = i;
    for (size_t i = 0; i < net.layers.size(); ++i) {
        const ngi::NetworkLayer& l = net.layers[i];
        if (l.kind != ngi::LayerKind::Conv) continue;
        const uint32_t fanIn = l.inChannels * l.kernelSize * l.kernelSize;
        const float a = (i == lastConv ? residualScale : 1.0f) / std::sqrt(float(fanIn));
        std::uniform_real_distribution<float> u(-a, a);
        for (uint32_t k = 0; k < l.outChannels * fanIn; ++k) net.parameters[l.weightOffset + k] = u(rng);
        for (uint32_t k = 0; k < l.outChannels; ++k) net.parameters[l.biasOffset + k] = 0.1f * u(rng);
    }
    return net;
}

float maxAbsDiff(const std::vector<float>& a, const std::vector<float>& b)
{
    EXPECT_EQ(a.size(), b.size());
    float m = a.size() == b.size() ? 0.0f : INFINITY;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) m = std::max(m, std::abs(a[i] - b[i]));
    return m;
}

glm::vec3 texelPosition(const glm::uvec4& t)
{
    glm::vec3 p;
    const uint32_t bits[3] = {t.x, t.y, t.z};
    std::memcpy(&p, bits, sizeof(p));
    return p;
}

using SrNetwork = VulkanTest;

TEST_F(SrNetwork, DefaultArchitectureMatchesReferenceForward)
{
    // The default x8 architecture (F32, attention, two residual blocks) on a 17 x 11 input.
    const ngi::NetworkWeights net = randomNetwork({}, 1, 1.0f);
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(17, 0.1f);
    FeatureMap positions(3, 11, 17), normals(3, 11, 17);
    for (uint32_t y = 0; y < 11; ++y)
        for (uint32_t x = 0; x < 17; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                positions.at(c, y, x) = torus.positions.at(x, y)[c];
                normals.at(c, y, x) = torus.normals.at(x, y)[c];
            }
    const FeatureMap expected = ngi::nn::referenceForward(net, positions, normals);
    ngi::vk::SuperResolution sr(context(), net);
    const ngi::nn::FeatureMap got = sr.run(positions, normals);
    ASSERT_EQ(got.width, 129u);
    ASSERT_EQ(got.height, 81u);
    const float error = maxAbsDiff(got.data, expected.data);
    EXPECT_LE(error, 1e-4f);
    RecordProperty("max_abs_error", ::testing::PrintToString(error));
}

TEST_F(SrNetwork, OtherScaleFactorsAndWidthsMatchReferenceForward)
{
    for (uint32_t f : {2u, 4u, 32u}) {  // x32: two sub-pixel stages (x4, then x8)
        ngi::nn::SuperResolutionConfig config;
        config.scaleFactor = f;
        config.features = 12;  // 3 groups of 4; heads of 6 channels straddle groups
        config.attentionHeads = 2;
        config.attentionWindow = 5;
        config.resBlocks = 1;
        config.upsampleFeatures = 6;
        config.activation = ngi::Activation::ReLU;
        const ngi::NetworkWeights net = randomNetwork(config, f, 1.0f);
        const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(9);
        const FeatureMap positions = ngi::nn::featureMapFromGeometryImage(sphere.positions);
        const FeatureMap normals = ngi::nn::featureMapFromGeometryImage(sphere.normals);
        const FeatureMap expected = ngi::nn::referenceForward(net, positions, normals);
        ngi::vk::SuperResolution sr(context(), net);
        EXPECT_LE(maxAbsDiff(sr.run(positions, normals).data, expected.data), 1e-4f) << "x" << f;
    }
}

// The shipped networks (assets/sr-x4/x8/x16/x32.ngiw) as the engine runs them: x16's sub-pixel
// convolution has 768 output channels (3 x 16^2), the widest tensor any shipped network has;
// x32 upsamples in two sub-pixel stages (x4 to 16 features, then x8).
// Inputs: a window of the nested level of a rippled torus (values in [0,1] like a stored level).
TEST_F(SrNetwork, ShippedNetworksMatchReferenceForward)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(257, 0.1f);
    for (const uint32_t f : {4u, 8u, 16u, 32u}) {
        const ngi::NetworkWeights net =
            ngi::readNetworkWeights(NGI_SOURCE_DIR "/assets/sr-x" + std::to_string(f) + ".ngiw");
        ASSERT_EQ(net.scaleFactor, f);
        const uint32_t w = 13, h = 9, x0 = 20, y0 = 30;
        FeatureMap positions(3, h, w), normals(3, h, w);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                for (uint32_t c = 0; c < 3; ++c) {
                    positions.at(c, y, x) = torus.positions.at(x0 + x, y0 + y)[c];
                    normals.at(c, y, x) = torus.normals.at(x0 + x, y0 + y)[c];
                }
        const FeatureMap expected = ngi::nn::referenceForward(net, positions, normals);
        ngi::vk::SuperResolution sr(context(), net);
        const FeatureMap got = sr.run(positions, normals);
        ASSERT_EQ(got.width, (w - 1) * f + 1) << "x" << f;
        ASSERT_EQ(got.height, (h - 1) * f + 1) << "x" << f;
        EXPECT_LE(maxAbsDiff(got.data, expected.data), 1e-4f) << "x" << f;
    }
}

// An x2 network small enough for 11 x 11 inputs, ending in `skip`.
ngi::nn::SuperResolutionConfig smallX2Config(ngi::LayerKind skip)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 2;
    config.features = 8;
    config.attentionHeads = 2;
    config.resBlocks = 1;
    config.upsampleFeatures = 4;
    config.skip = skip;
    return config;
}

TEST_F(SrNetwork, FusedBilinearAndCubicSkipsMatchReferenceForward)
{
    // A BilinearSkip / CubicSkip after the last conv runs in that conv's epilogue (its own
    // pipeline variant, sr_conv.comp EPILOGUE): 9 x 11 -> 17 x 21, block-unaligned widths.
    for (const ngi::LayerKind skip : {ngi::LayerKind::BilinearSkip, ngi::LayerKind::CubicSkip}) {
        const ngi::nn::SuperResolutionConfig config = smallX2Config(skip);
        const ngi::NetworkWeights net = randomNetwork(config, 7, 1.0f);
        const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(11, 0.1f);
        FeatureMap positions = ngi::nn::featureMapFromGeometryImage(torus.positions);
        FeatureMap normals = ngi::nn::featureMapFromGeometryImage(torus.normals);
        // Crop to 9 rows: a non-square input.
        for (FeatureMap* m : {&positions, &normals}) {
            FeatureMap c(3, 9, m->width);
            for (uint32_t ch = 0; ch < 3; ++ch)
                for (uint32_t y = 0; y < 9; ++y)
                    for (uint32_t x = 0; x < m->width; ++x) c.at(ch, y, x) = m->at(ch, y, x);
            *m = c;
        }
        const FeatureMap expected = ngi::nn::referenceForward(net, positions, normals);
        ngi::vk::SuperResolution sr(context(), net);
        EXPECT_LE(maxAbsDiff(sr.run(positions, normals).data, expected.data), 1e-4f) << "skip kind " << uint32_t(skip);
    }
}

// The per-chart residual gain (AssetChart::residualGain): the GLSL restore is c + g (n - c), the
// blend of the bicubic c and the network n, as the reference forward computes it, within the
// same 1e-4, for the Hermite skip (its own pass) and the bilinear / cubic skips fused into the
// last conv; g = 1 is bitwise the restore without a gain, g = 0 the bicubic. Through
// AssetSurface, each chart's restore applies its own gain.
TEST_F(SrNetwork, ResidualGainMatchesReferenceForwardForEverySkipKind)
{
    for (const ngi::LayerKind skip :
         {ngi::LayerKind::HermiteSkip, ngi::LayerKind::BilinearSkip, ngi::LayerKind::CubicSkip}) {
        const ngi::nn::SuperResolutionConfig config = smallX2Config(skip);
        const ngi::NetworkWeights net = randomNetwork(config, 11, 1.0f);
        const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(11, 0.1f);
        const FeatureMap positions = ngi::nn::featureMapFromGeometryImage(torus.positions);
        const FeatureMap normals = ngi::nn::featureMapFromGeometryImage(torus.normals);
        ngi::vk::SuperResolution sr(context(), net);
        const FeatureMap asTrained = sr.run(positions, normals);
        EXPECT_EQ(sr.run(positions, normals, 1.0f).data, asTrained.data) << "kind " << uint32_t(skip);
        const ngi::nn::RestoreEndpoints ends = ngi::nn::referenceForwardEndpoints(net, positions, normals);
        EXPECT_LE(maxAbsDiff(sr.run(positions, normals, 0.0f).data, ends.cubic.data), 1e-4f)
            << "kind " << uint32_t(skip);
        EXPECT_GT(maxAbsDiff(ends.network.data, ends.cubic.data), 1e-2f) << "endpoints that coincide test nothing";
        for (float gain : {0.0f, 0.37f}) {
            const FeatureMap expected = ngi::nn::referenceForward(net, positions, normals, gain);
            EXPECT_LE(maxAbsDiff(sr.run(positions, normals, gain).data, expected.data), 1e-4f)
                << "kind " << uint32_t(skip) << " gain " << gain;
        }
        EXPECT_THROW(sr.run(positions, normals, 1.5f), ngi::Error);
    }
    // Two charts of one asset restored in one build, each with its gain.
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 4;
    const ngi::NetworkWeights net = randomNetwork(config, 12, 0.05f);
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(33), 2);
    asset.charts[0].seams = {};  // no weld: level 0 is the network's output as it wrote it
    asset.charts.push_back(asset.charts[0]);
    asset.charts[0].residualGain = 0.25f;
    asset.charts[1].residualGain = 0.0f;
    ngi::vk::SuperResolution sr(context(), net);
    ngi::vk::AssetSurface surface(renderer(), asset, {.network = &sr});
    surface.build();
    for (size_t c = 0; c < 2; ++c) {
        const ngi::AssetChart& chart = asset.charts[c];
        ngi::GeometryImage decoded = ngi::storedNormals(chart);
        for (auto& n : decoded.texels) n = ngi::unpackNormalOctahedral(ngi::packNormalOctahedral(n));
        const FeatureMap expected =
            ngi::nn::referenceForward(net, ngi::nn::featureMapFromGeometryImage(ngi::storedPositions(chart)),
                                      ngi::nn::featureMapFromGeometryImage(decoded), chart.residualGain);
        const auto level0 = surface.chart(c).readLevel(0, false);
        ASSERT_EQ(level0.size(), size_t(33) * 33);
        float worst = 0.0f;
        for (uint32_t y = 0; y < 33; ++y)
            for (uint32_t x = 0; x < 33; ++x) {
                const glm::vec3 p = texelPosition(level0[size_t(y) * 33 + x]);
                for (uint32_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(p[int(k)] - expected.at(k, y, x)));
            }
        EXPECT_LE(worst, 1e-4f) << "chart " << c;
    }
}

// The library's default restore is the tools': the network the asset carries (or names) when
// it restores a chart, made, checked and freed by the surface; without one, bicubic.
TEST_F(SrNetwork, AnAssetSurfaceRestoresWithTheAssetsNetworkByDefault)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 4;
    const ngi::NetworkWeights net = randomNetwork(config, 13, 0.05f);
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(33), 2);
    asset.weights = ngi::serializeNetworkWeights(net);
    ngi::vk::AssetSurface byDefault(renderer(), asset);
    ASSERT_NE(byDefault.restoreNetwork(), nullptr);
    EXPECT_TRUE(byDefault.restoredByNetwork(0));
    EXPECT_EQ(byDefault.restoreProblem(), "");
    byDefault.build();
    EXPECT_EQ(byDefault.restoreNetwork(), nullptr);  // checked and freed with the uploads
    ngi::vk::SuperResolution sr(context(), net);
    ngi::vk::AssetSurface withNetwork(renderer(), asset, {.network = &sr});
    withNetwork.build();
    EXPECT_EQ(byDefault.chart(0).readLevel(0, false), withNetwork.chart(0).readLevel(0, false));

    asset.weights.clear();  // and it names none
    const ngi::vk::AssetSurface without(renderer(), asset);
    EXPECT_EQ(without.restoreNetwork(), nullptr);
    EXPECT_EQ(without.restoreProblem(), "the asset names no network");
    EXPECT_EQ(without.upsamplingOf(0), ngi::vk::Upsampling::bicubic);
}

TEST_F(SrNetwork, TensorsAreAliasedByLiveness)
{
    const ngi::NetworkWeights net = randomNetwork({}, 2, 1.0f);
    ngi::vk::SuperResolution sr(context(), net);
    const uint64_t weightBytes = sr.gpuBytes();
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(17);
    const FeatureMap p = ngi::nn::featureMapFromGeometryImage(sphere.positions);
    const FeatureMap n = ngi::nn::featureMapFromGeometryImage(sphere.normals);
    sr.run(p, n);
    // Without aliasing: every tensor of the net. With it: well under half of that.
    const auto shapes = ngi::validateNetwork(net, "net");
    uint64_t all = 0;
    for (const auto& s : shapes)
        all += uint64_t((s.channels + 3) / 4) * 16 * ((17 - 1) * s.gridFactor + 1) * ((17 - 1) * s.gridFactor + 1);
    const uint64_t tensors = sr.gpuBytes() - weightBytes;
    EXPECT_LT(tensors, all / 2);
    sr.releaseTensors();
    EXPECT_EQ(sr.gpuBytes(), weightBytes);
}

// Level 0 of a surface built with the network: positions from the network (vs the reference
// forward on the uploaded level, normals decoded from their octahedral texels), normals
// derived from them (vs a CPU rendition of shaders/sr_output.comp), levels 1 .. stored - 1
// nested subsamples of level 0, the stored level untouched.
TEST_F(SrNetwork, SurfaceLevelZeroIsWrittenByTheNetwork)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 4;
    const ngi::NetworkWeights net = randomNetwork(config, 3, 0.02f);
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    const ngi::GeometryImage p2 = ngi::downsampleNested(sphere.positions, 2);
    const ngi::GeometryImage n2 = ngi::downsampleNested(sphere.normals, 2);
    ngi::vk::SuperResolution sr(context(), net);
    ngi::vk::GeometryImageSurface surface(renderer(), p2, n2, 65);
    context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); });
    surface.releaseUpload();

    ngi::GeometryImage decoded = n2;
    for (auto& n : decoded.texels) n = ngi::unpackNormalOctahedral(ngi::packNormalOctahedral(n));
    const FeatureMap expected = ngi::nn::referenceForward(net, ngi::nn::featureMapFromGeometryImage(p2),
                                                          ngi::nn::featureMapFromGeometryImage(decoded));
    const auto level0 = surface.readLevel(0, false);
    ASSERT_EQ(level0.size(), size_t(65) * 65);
    float worst = 0.0f, worstNormal = 0.0f, worstTruth = 0.0f;
    auto at = [&](int x, int y) { return texelPosition(level0[size_t(y) * 65 + x]); };
    // Shading normals: Catmull-Rom of the stored normals (clamped), renormalized (sr_output.comp).
    auto cubicNormal = [&](int X, int Y) {
        const std::array<float, 4> wx = ngi::nn::catmullRomWeights(float(X % 4) / 4.0f);
        const std::array<float, 4> wy = ngi::nn::catmullRomWeights(float(Y % 4) / 4.0f);
        glm::vec3 n(0.0f);
        for (int ky = 0; ky < 4; ++ky)
            for (int kx = 0; kx < 4; ++kx)
                n += wy[size_t(ky)] * wx[size_t(kx)] *
                    decoded.at(uint32_t(std::clamp(X / 4 - 1 + kx, 0, 16)),
                               uint32_t(std::clamp(Y / 4 - 1 + ky, 0, 16)));
        return glm::normalize(n);
    };
    for (int y = 0; y < 65; ++y)
        for (int x = 0; x < 65; ++x) {
            const glm::vec3 p = at(x, y);
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(p[c] - expected.at(c, y, x)));
            const glm::vec3 n = ngi::unpackNormalOctahedral(level0[size_t(y) * 65 + x].w);
            worstNormal = std::max(worstNormal, glm::length(n - cubicNormal(x, y)));
            worstTruth = std::max(worstTruth, glm::length(n - sphere.normals.at(uint32_t(x), uint32_t(y))));
        }
    // And they are the sphere's own normals at full resolution up to the interpolation error
    // from a 17^2 level (measured 0.029, 1.7 degrees, whatever the network's residual).
    EXPECT_LE(worstTruth, 0.05f);
    EXPECT_LE(worst, 1e-4f);
    EXPECT_LE(worstNormal, 2e-3f);
    const auto level1 = surface.readLevel(1, false);
    for (uint32_t y = 0; y < 33; ++y)
        for (uint32_t x = 0; x < 33; ++x) ASSERT_EQ(level1[y * 33 + x], level0[(2 * y) * 65 + 2 * x]);
    const auto level2 = surface.readLevel(2, false);
    for (size_t i = 0; i < level2.size(); ++i) ASSERT_EQ(texelPosition(level2[i]), p2.texels[i]);
    EXPECT_NO_THROW(sr.checkLastRestore());  // a sane network restores finite positions only
}

// Finding: weights whose values overflow (here every conv parameter near FLT_MAX)
// made ngi-render exit 0 with a blank image. The output pass counts the non-finite restored
// samples; checkLastRestore (and run) turn any into an error naming the network.
TEST_F(SrNetwork, OverflowingWeightsAreAnErrorNamingTheNetworkNotABlankImage)
{
    ngi::nn::SuperResolutionConfig config;
    config.scaleFactor = 4;
    ngi::NetworkWeights net = randomNetwork(config, 5, 1.0f);
    for (float& p : net.parameters) p = p < 0.0f ? -3e38f : 3e38f;
    net.source = "hostile.ngiw";
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    const ngi::GeometryImage p2 = ngi::downsampleNested(sphere.positions, 2);
    const ngi::GeometryImage n2 = ngi::downsampleNested(sphere.normals, 2);
    ngi::vk::SuperResolution sr(context(), net);
    EXPECT_NO_THROW(sr.checkLastRestore());  // nothing restored yet
    ngi::vk::GeometryImageSurface surface(renderer(), p2, n2, 65);
    context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); });
    try {
        sr.checkLastRestore();
        FAIL() << "no error";
    } catch (const ngi::Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("hostile.ngiw: the restore produced non-finite values (", 0), 0u) << message;
        EXPECT_NE(message.find(" of 4225 restored samples)"), std::string::npos) << message;
    }
    const FeatureMap positions = ngi::nn::featureMapFromGeometryImage(p2),
                     normals = ngi::nn::featureMapFromGeometryImage(n2);
    EXPECT_THROW(sr.run(positions, normals), ngi::Error);
    EXPECT_THROW(ngi::nn::referenceForward(net, positions, normals), ngi::Error);
}

// Finding: the GPU's layer limit names the network and the layer.
TEST_F(SrNetwork, ConvBeyondTheWeightsWindowNamesTheNetworkAndTheLayer)
{
    ngi::NetworkWeights net = ngi::test::wideConvNetwork(8);
    net.source = "wide.ngiw";
    ASSERT_NO_THROW(ngi::validateNetwork(net, "wide.ngiw"));
    try {
        ngi::vk::SuperResolution sr(context(), net);
        FAIL() << "no error";
    } catch (const ngi::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("wide.ngiw: layer 1 has too many input channels (500)", 0), 0u)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("at most 452 at 3x3"), std::string::npos) << e.what();
    }
}

TEST_F(SrNetwork, SurfaceRejectsANetworkOfTheWrongFactor)
{
    const ngi::NetworkWeights net = randomNetwork({}, 4, 1.0f);  // x8
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    const ngi::GeometryImage p2 = ngi::downsampleNested(sphere.positions, 2);
    const ngi::GeometryImage n2 = ngi::downsampleNested(sphere.normals, 2);
    ngi::vk::SuperResolution sr(context(), net);
    ngi::vk::GeometryImageSurface surface(renderer(), p2, n2, 65);
    EXPECT_THROW(context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd, {&sr}); }), ngi::Error);
}

}  // namespace
