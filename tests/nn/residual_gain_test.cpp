// The per-chart residual gain: referenceForward's c + g (n - c) blend of the bicubic c
// and the network n (bitwise the network at g = 1, the bicubic at g = 0), and the least-squares
// fit of g against the full image (ngi/nn/residual_gain.h).
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/nn/residual_gain.h"

#include "tiny_network.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace {

ngi::nn::FeatureMap randomMap(uint32_t h, uint32_t w, uint32_t seed, bool unit)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    ngi::nn::FeatureMap m(3, h, w);
    for (float& v : m.data) v = unit ? u(rng) : 0.5f + 0.4f * u(rng);
    if (unit)
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                const float l = std::sqrt(m.at(0, y, x) * m.at(0, y, x) + m.at(1, y, x) * m.at(1, y, x) +
                                          m.at(2, y, x) * m.at(2, y, x));
                for (uint32_t c = 0; c < 3; ++c) m.at(c, y, x) /= l;
            }
    return m;
}

TEST(ReferenceForward, ResidualGainBlendsTheOutputTowardTheBicubic)
{
    // The default architecture at its smallest (HermiteSkip writes the output), odd shape 7 x 9.
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("gain-x4", 3, 0.2f);
    ASSERT_TRUE(ngi::nn::outputSkipLayer(net));
    const ngi::nn::FeatureMap p = randomMap(7, 9, 1, false), n = randomMap(7, 9, 2, true);
    const ngi::nn::FeatureMap out = ngi::nn::referenceForward(net, p, n);
    EXPECT_EQ(ngi::nn::referenceForward(net, p, n, 1.0f).data, out.data);  // bitwise
    const ngi::nn::RestoreEndpoints ends = ngi::nn::referenceForwardEndpoints(net, p, n);
    EXPECT_EQ(ends.network.data, out.data);
    // The gain-0 end is the bicubic of the stored positions, not the network's Hermite skip.
    const ngi::nn::FeatureMap zero(3, out.height, out.width);
    EXPECT_EQ(ends.cubic.data, ngi::nn::cubicSkip(p, zero, 4).data);
    EXPECT_EQ(ngi::nn::referenceForward(net, p, n, 0.0f).data, ends.cubic.data);
    double apart = 0.0;
    for (size_t i = 0; i < out.data.size(); ++i) apart += std::abs(out.data[i] - ends.cubic.data[i]);
    EXPECT_GT(apart, 1e-3 * double(out.data.size())) << "endpoints that coincide test nothing";
    const ngi::nn::FeatureMap g = ngi::nn::referenceForward(net, p, n, 0.3f);
    for (size_t i = 0; i < out.data.size(); ++i)
        EXPECT_EQ(g.data[i], ends.cubic.data[i] + 0.3f * (ends.network.data[i] - ends.cubic.data[i])) << i;
    EXPECT_THROW(ngi::nn::referenceForward(net, p, n, 1.5f), ngi::Error);

    // A network whose output is not a skip has no coarse input to blend with: 1 runs, else fails.
    ngi::NetworkWeights noSkip = ngi::test::tinyNetwork(4, 0.1f);
    noSkip.layers.pop_back();
    noSkip.outputTensor = 3;
    noSkip.tensorCount = 4;
    EXPECT_FALSE(ngi::nn::outputSkipLayer(noSkip));
    EXPECT_NO_THROW(ngi::nn::referenceForward(noSkip, p, n));
    EXPECT_THROW(ngi::nn::referenceForward(noSkip, p, n, 0.5f), ngi::Error);
}

TEST(ResidualGain, FitsTheLeastSquaresGainClampedToZeroOne)
{
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("gain-x4", 5, 0.2f);
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(33);
    const ngi::Asset asset = ngi::makeAnalyticAsset("sphere", sphere, 2);  // 9^2 stored, x4
    const ngi::AssetChart& chart = asset.charts[0];
    const ngi::nn::RestoreEndpoints ends =
        ngi::nn::referenceForwardEndpoints(net, ngi::nn::featureMapFromGeometryImage(ngi::storedPositions(chart)),
                                           ngi::nn::featureMapFromGeometryImage(ngi::storedNormals(chart)));
    auto target = [&](float k) {
        ngi::nn::FeatureMap t = ends.cubic;
        for (size_t i = 0; i < t.data.size(); ++i) t.data[i] += k * (ends.network.data[i] - ends.cubic.data[i]);
        return ngi::nn::geometryImageFromFeatureMap(t);
    };
    const ngi::nn::ResidualGainFit part = ngi::nn::fitResidualGain(net, chart, target(0.4f), sphere.normals);
    EXPECT_NEAR(part.gain, 0.4f, 1e-4f);
    EXPECT_LT(part.rmsGained, 1e-3 * part.rmsCubic);
    EXPECT_LT(part.rmsGained, 1e-3 * part.rmsNetwork);
    EXPECT_EQ(ngi::nn::fitResidualGain(net, chart, target(-1.0f), sphere.normals).gain,
              0.0f);  // the network points away
    EXPECT_EQ(ngi::nn::fitResidualGain(net, chart, target(2.0f), sphere.normals).gain, 1.0f);
    // Against the real full image: never worse than the bicubic or the network (point-to-plane).
    const ngi::nn::ResidualGainFit real = ngi::nn::fitResidualGain(net, chart, sphere.positions, sphere.normals);
    EXPECT_LE(real.rmsGained, real.rmsCubic * (1.0 + 1e-9));
    EXPECT_LE(real.rmsGained, real.rmsNetwork * (1.0 + 1e-9));
    // Wrong factor or size: one error.
    EXPECT_THROW(ngi::nn::fitResidualGain(ngi::test::smallDefaultNetwork("x", 1, 0.1f),
                                          ngi::makeAnalyticAsset("s", sphere, 1).charts[0], sphere.positions,
                                          sphere.normals),
                 ngi::Error);
    EXPECT_THROW(ngi::nn::fitResidualGain(net, chart, sphere.positions, ngi::GeometryImage(17)), ngi::Error);
}

// Weighted by w_i (the surface each sample stands for, in the bake): the gain is the weighted
// least squares. A target that wants 0.2 in the top half of the image and 0.8 in the bottom half
// gets 0.2 or 0.8 where only that half weighs, and in between with equal weights.
TEST(ResidualGain, WeightsEachSamplesTerms)
{
    const ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("gain-x4", 5, 0.2f);
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(33);
    const ngi::AssetChart chart = ngi::makeAnalyticAsset("sphere", sphere, 2).charts[0];
    const ngi::nn::RestoreEndpoints ends =
        ngi::nn::referenceForwardEndpoints(net, ngi::nn::featureMapFromGeometryImage(ngi::storedPositions(chart)),
                                           ngi::nn::featureMapFromGeometryImage(ngi::storedNormals(chart)));
    const size_t plane = size_t(33) * 33;
    const auto top = [&](size_t i) { return i < 16 * 33; };  // rows 0-15
    ngi::nn::FeatureMap t = ends.cubic;
    for (size_t i = 0; i < t.data.size(); ++i)
        t.data[i] += (top(i % plane) ? 0.2f : 0.8f) * (ends.network.data[i] - ends.cubic.data[i]);
    const ngi::GeometryImage target = ngi::nn::geometryImageFromFeatureMap(t);
    std::vector<double> topOnly(plane), bottomOnly(plane);
    for (size_t i = 0; i < plane; ++i) topOnly[i] = top(i) ? 2.0 : 0.0, bottomOnly[i] = top(i) ? 0.0 : 2.0;
    const ngi::nn::ResidualGainFit a = ngi::nn::fitResidualGain(net, chart, target, sphere.normals, topOnly);
    const ngi::nn::ResidualGainFit b = ngi::nn::fitResidualGain(net, chart, target, sphere.normals, bottomOnly);
    const ngi::nn::ResidualGainFit equal = ngi::nn::fitResidualGain(net, chart, target, sphere.normals);
    EXPECT_NEAR(a.gain, 0.2f, 1e-4f);
    EXPECT_NEAR(b.gain, 0.8f, 1e-4f);
    EXPECT_GT(equal.gain, 0.2f + 0.05f);
    EXPECT_LT(equal.gain, 0.8f - 0.05f);
    EXPECT_LT(a.rmsGained, 1e-3 * a.rmsCubic);  // the half that weighs is fitted exactly
    // All weights 1 is no weighting.
    const ngi::nn::ResidualGainFit ones =
        ngi::nn::fitResidualGain(net, chart, target, sphere.normals, std::vector<double>(plane, 1.0));
    EXPECT_EQ(ones.gain, equal.gain);
    EXPECT_DOUBLE_EQ(ones.rmsGained, equal.rmsGained);
    EXPECT_THROW(ngi::nn::fitResidualGain(net, chart, target, sphere.normals, std::vector<double>(plane - 1, 1.0)),
                 ngi::Error);
}

}  // namespace
