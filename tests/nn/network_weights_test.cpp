// The network weights file (.ngiw): lossless round trip, atomic writes, rejection of every
// truncated or corrupt file (exhaustive truncation and single-bit flips, as asset_test),
// validation of inconsistent op lists; and the reference ops on hand-checkable cases.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/reference_forward.h"
#include "hostile_networks.h"

#include <gtest/gtest.h>

#include <bit>

#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <utility>

namespace {

ngi::NetworkWeights tinyNetwork() { return ngi::test::smallDefaultNetwork("tiny", 7, 0.5f); }

ngi::nn::FeatureMap randomMap(uint32_t c, uint32_t h, uint32_t w, uint32_t seed)
{
    ngi::nn::FeatureMap m(c, h, w);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& v : m.data) v = u(rng);
    return m;
}

TEST(NetworkWeights, RoundTripIsLossless)
{
    const ngi::NetworkWeights net = tinyNetwork();
    const auto bytes = ngi::serializeNetworkWeights(net);
    EXPECT_EQ(ngi::parseNetworkWeights(bytes, "a.ngiw"), net);
    EXPECT_EQ(ngi::networkHash(net), ngi::fnv1a64(bytes));
}

TEST(NetworkWeights, DefaultArchitectureIsValidAndSmall)
{
    for (uint32_t f : {4u, 8u, 16u, 32u, 64u}) {
        ngi::nn::SuperResolutionConfig c;
        c.scaleFactor = f;
        const ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(c, "x" + std::to_string(f));
        const auto shapes = ngi::validateNetwork(net, "default");
        EXPECT_EQ(shapes[net.outputTensor].channels, 3u);
        EXPECT_EQ(shapes[net.outputTensor].gridFactor, f);
        EXPECT_LT(net.parameters.size(), f <= 32 ? 200000u : 250000u);  // x64's first stage: 16 -> 1024 channels
        // x32 and x64 upsample in two sub-pixel stages (3 f^2 > kMaxNetworkChannels), the last x8.
        std::vector<uint32_t> shuffles;
        for (const ngi::NetworkLayer& l : net.layers)
            if (l.kind == ngi::LayerKind::PixelShuffle) shuffles.push_back(l.factor);
        if (f <= 16)
            EXPECT_EQ(shuffles, std::vector<uint32_t>{f});
        else
            EXPECT_EQ(shuffles, (std::vector<uint32_t>{f / 8, 8u})) << "x" << f;
    }
    ngi::nn::SuperResolutionConfig c;
    const ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(c, "x8");
    // 129 -> 1025 restore: a few GFLOP (the lavapipe budget is ~1 s at 5-15 GFLOP/s).
    const double gflop = 2.0 * double(ngi::networkMultiplyAdds(net, 129)) * 1e-9;
    EXPECT_GT(gflop, 1.0);
    EXPECT_LT(gflop, 5.0);
}

TEST(NetworkWeights, RejectsEveryTruncation)
{
    const auto bytes = ngi::serializeNetworkWeights(tinyNetwork());
    for (size_t n = 0; n < bytes.size(); ++n) {
        std::span<const uint8_t> cut(bytes.data(), n);
        try {
            ngi::parseNetworkWeights(cut, "cut.ngiw");
            ADD_FAILURE() << "accepted a file cut at " << n;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("cut.ngiw: ", 0), 0u) << e.what();
        }
    }
    auto padded = bytes;
    padded.push_back(0);
    EXPECT_THROW(ngi::parseNetworkWeights(padded, "pad.ngiw"), ngi::Error);
}

TEST(NetworkWeights, RejectsEverySingleBitFlip)
{
    const auto bytes = ngi::serializeNetworkWeights(tinyNetwork());
    for (size_t i = 0; i < bytes.size(); ++i)
        for (int bit = 0; bit < 8; ++bit) {
            auto flipped = bytes;
            flipped[i] ^= uint8_t(1u << bit);
            try {
                ngi::parseNetworkWeights(flipped, "flip.ngiw");
                ADD_FAILURE() << "accepted a flip of bit " << bit << " of byte " << i;
            } catch (const ngi::Error& e) {
                EXPECT_EQ(std::string(e.what()).rfind("flip.ngiw: ", 0), 0u) << e.what();
            }
        }
}

TEST(NetworkWeights, RejectsBadMagicAndVersionWithClearMessages)
{
    auto bytes = ngi::serializeNetworkWeights(tinyNetwork());
    auto wrongMagic = bytes;
    wrongMagic[2] = 'X';
    try {
        ngi::parseNetworkWeights(wrongMagic, "a.ngiw");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_STREQ(e.what(), "a.ngiw: not an ngi weights file (bad magic bytes)");
    }
    auto wrongVersion = bytes;
    wrongVersion[8] = 9;
    try {
        ngi::parseNetworkWeights(wrongVersion, "b.ngiw");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("unsupported weights format version 9"), std::string::npos);
    }
}

TEST(NetworkWeights, ValidationRejectsInconsistentOpLists)
{
    const ngi::NetworkWeights good = tinyNetwork();
    auto expectRejected = [](ngi::NetworkWeights net, const char* why) {
        EXPECT_THROW(ngi::serializeNetworkWeights(net), ngi::Error) << why;
    };
    ngi::NetworkWeights a = good;
    a.layers[0].inChannels = 5;
    expectRejected(a, "channel mismatch");
    ngi::NetworkWeights b = good;
    b.layers[1].output = b.layers[0].output;
    expectRejected(b, "tensor written twice");
    ngi::NetworkWeights c = good;
    c.parameters.pop_back();
    expectRejected(c, "weights out of range");
    ngi::NetworkWeights d = good;
    d.layers[0].inputs[0] = d.tensorCount - 1;
    expectRejected(d, "use before definition");
    ngi::NetworkWeights e = good;
    e.parameters[3] = NAN;
    expectRejected(e, "non-finite parameter");
    ngi::NetworkWeights f = good;
    f.scaleFactor = 8;
    expectRejected(f, "output grid differs from the scale factor");
}

TEST(NetworkWeights, FileWriteIsAtomicAndReadNamesThePath)
{
    const auto dir = std::filesystem::temp_directory_path() / "ngi_network_weights_test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto path = dir / "w.ngiw";
    const ngi::NetworkWeights net = tinyNetwork();
    ngi::writeNetworkWeights(net, path);
    EXPECT_EQ(ngi::readNetworkWeights(path), net);
    ngi::NetworkWeights bad = net;
    bad.layers[0].kernelSize = 5;
    EXPECT_THROW(ngi::writeNetworkWeights(bad, path), ngi::Error);
    EXPECT_EQ(ngi::readNetworkWeights(path), net);
    size_t files = 0;
    for (auto& entry : std::filesystem::directory_iterator(dir)) files += entry.is_regular_file();
    EXPECT_EQ(files, 1u);
    try {
        ngi::readNetworkWeights(dir / "missing.ngiw");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.ngiw"), std::string::npos);
    }
    std::filesystem::remove_all(dir);
}

// The readers record where a network came from, for error messages only: not part of its
// identity (operator==, networkHash), and networkLabel falls back to the name.
TEST(NetworkWeights, SourceNamesTheNetworkButIsNotPartOfItsIdentity)
{
    ngi::NetworkWeights net = tinyNetwork();
    EXPECT_EQ(ngi::networkLabel(net), "network 'tiny'");
    const ngi::NetworkWeights parsed = ngi::parseNetworkWeights(ngi::serializeNetworkWeights(net), "dir/w.ngiw");
    EXPECT_EQ(parsed.source, "dir/w.ngiw");
    EXPECT_EQ(ngi::networkLabel(parsed), "dir/w.ngiw");
    EXPECT_EQ(parsed, net);
    EXPECT_EQ(ngi::networkHash(parsed), ngi::networkHash(net));
    net.name.clear();
    EXPECT_EQ(ngi::networkLabel(net), "network");
}

// Finding: the shipped network stays well within every resource limit.
TEST(NetworkWeights, ShippedNetworkIsWellWithinTheLimits)
{
    const ngi::NetworkWeights net = ngi::readNetworkWeights(NGI_SOURCE_DIR "/assets/sr-x8.ngiw");
    const ngi::NetworkFigures f = ngi::networkFigures(net, ngi::validateNetwork(net, "sr-x8.ngiw"));
    std::printf("sr-x8.ngiw: %u layers (limit %u), %u channels at most (%u), %llu parameters (%llu), %.1f "
                "multiply-adds per output sample (%.0f), %.2f activations per output sample (%.0f)\n",
                f.layers, ngi::kMaxNetworkLayers, f.maxChannels, ngi::kMaxNetworkChannels,
                (unsigned long long)f.parameters, (unsigned long long)ngi::kMaxNetworkParameters,
                f.multiplyAddsPerOutputSample, ngi::kMaxMultiplyAddsPerOutputSample, f.activationsPerOutputSample,
                ngi::kMaxActivationsPerOutputSample);
    EXPECT_EQ(f.layers, 18u);
    EXPECT_EQ(f.maxChannels, 192u);
    EXPECT_DOUBLE_EQ(f.multiplyAddsPerOutputSample, 1485.0);
    // At least 4x below every limit.
    EXPECT_LE(4 * f.layers, ngi::kMaxNetworkLayers);
    EXPECT_LE(4 * f.maxChannels, ngi::kMaxNetworkChannels);
    EXPECT_LE(4 * f.parameters, ngi::kMaxNetworkParameters);
    EXPECT_LE(4 * f.multiplyAddsPerOutputSample, ngi::kMaxMultiplyAddsPerOutputSample);
    EXPECT_LE(4 * f.activationsPerOutputSample, ngi::kMaxActivationsPerOutputSample);
    // The per-output-sample figure is the large-input limit of networkMultiplyAdds.
    const double perSample = double(ngi::networkMultiplyAdds(net, 1025)) / (8193.0 * 8193.0);
    EXPECT_NEAR(perSample, f.multiplyAddsPerOutputSample, 0.01 * f.multiplyAddsPerOutputSample);
}

// Finding: a 330 KB network of 4000 layers hung every tool. Each limit is checked
// by the validator (hence the reader) with a message naming the file, the figure and the limit.
TEST(NetworkWeights, RejectsNetworksBeyondTheResourceLimits)
{
    auto expectRejected = [](const ngi::NetworkWeights& net, const std::string& what) {
        try {
            ngi::validateNetwork(net, "big.ngiw");
            ADD_FAILURE() << "accepted: " << what;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("big.ngiw: ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    EXPECT_NO_THROW(ngi::validateNetwork(ngi::test::longNetwork(ngi::kMaxNetworkLayers - 3, 4), "ok"));
    expectRejected(ngi::test::longNetwork(ngi::kMaxNetworkLayers - 2, 4),
                   "the network has 257 layers; the limit is 256 (kMaxNetworkLayers)");
    ngi::NetworkWeights params = ngi::test::tinyNetwork(4, 0.0f);
    params.parameters.resize(ngi::kMaxNetworkParameters + 1);
    expectRejected(params, "the network has 4194305 parameters; the limit is 4194304 (kMaxNetworkParameters)");
    // A first conv of 3 -> 1025 channels.
    ngi::NetworkWeights wide = ngi::test::tinyNetwork(16, 0.0f);
    wide.layers.insert(wide.layers.begin(), wide.layers[0]);
    wide.layers[0].output = 5;
    wide.layers[0].outChannels = 1025;
    wide.layers[0].biasOffset = wide.layers[0].weightOffset = 0;
    wide.parameters.resize(4 * 1025);
    wide.tensorCount = 6;
    expectRejected(wide, "layer 0: has 1025 output channels; the limit is 1024 (kMaxNetworkChannels)");
    // Three convs on the output grid of a x4 network, 3 -> 32 -> 32 -> 3: 96 + 1024 + 96
    // multiply-adds per output sample with 1x1 kernels; 96 + 9216 + 96 with a 3x3 in the middle.
    ngi::NetworkWeights costly = ngi::test::tinyNetwork(4, 0.0f);
    ngi::NetworkLayer fine;
    fine.kind = ngi::LayerKind::Conv;
    fine.kernelSize = 1;
    const std::array<std::array<uint32_t, 4>, 3> chain{{{4, 5, 3, 32}, {5, 6, 32, 32}, {6, 7, 32, 3}}};
    for (const auto& [in, out, inChannels, outChannels] : chain) {
        fine.inputs = {in, ngi::kNoTensor, ngi::kNoTensor};
        fine.output = out;
        fine.inChannels = inChannels;
        fine.outChannels = outChannels;
        costly.layers.push_back(fine);
    }
    costly.parameters.resize(32 * 32 * 9 + 32);
    costly.tensorCount = 8;
    costly.outputTensor = 7;
    EXPECT_NO_THROW(ngi::validateNetwork(costly, "ok"));
    costly.layers[4].kernelSize = 3;
    expectRejected(costly,
                   "the network costs 9417.0 multiply-adds per output sample; the limit is 8192.0 "
                   "(kMaxMultiplyAddsPerOutputSample)");
    // 200 channels on the output grid: 200 values per output sample (MACs: 600).
    ngi::NetworkWeights memory = ngi::test::tinyNetwork(4, 0.0f);
    fine.inputs[0] = 4;
    fine.output = 5;
    fine.inChannels = 3;
    fine.outChannels = 200;
    fine.kernelSize = 1;
    memory.layers.push_back(fine);
    fine.inputs[0] = 5;
    fine.output = 6;
    fine.inChannels = 200;
    fine.outChannels = 3;
    memory.layers.push_back(fine);
    memory.parameters.resize(200 * 3 + 200);
    memory.tensorCount = 7;
    memory.outputTensor = 6;
    expectRejected(memory, "values per output sample; the limit is 128.0 (kMaxActivationsPerOutputSample)");
}

// The 4000-layer file itself: refused by the reader from its declared layer count, before
// the layers are allocated or anything runs.
TEST(NetworkWeights, ReaderRejectsA4000LayerFile)
{
    const std::vector<uint8_t> bytes = ngi::test::unvalidatedWeightsFile(ngi::test::longNetwork(3997, 8));
    EXPECT_GT(bytes.size(), 300000u);
    try {
        ngi::parseNetworkWeights(bytes, "deep.ngiw");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_STREQ(e.what(), "deep.ngiw: the network has 4000 layers; the limit is 256 (kMaxNetworkLayers)");
    }
}

// Finding: large but finite parameters (a huge attention scale, weights near
// FLT_MAX, a huge LeakyReLU slope) made the attention's softmax NaN and the reference read out
// of bounds (SIGSEGV in ngi-eval). Now nothing but the window inside the image is read, and
// the first layer that yields a NaN or an infinity ends the restore with an error naming the
// network and the layer.
TEST(ReferenceForward, OverflowingParametersAreAnErrorNamingTheNetworkAndTheLayer)
{
    const ngi::NetworkWeights good = tinyNetwork();
    const ngi::nn::FeatureMap positions = randomMap(3, 6, 5, 3), normals = randomMap(3, 6, 5, 4);
    ASSERT_NO_THROW(ngi::nn::referenceForward(good, positions, normals));
    size_t attention = 0;
    while (good.layers[attention].kind != ngi::LayerKind::NeighborhoodCrossAttention) ++attention;
    auto expectError = [&](const ngi::NetworkWeights& mutated, const std::string& name, size_t layer) {
        const ngi::NetworkWeights net = ngi::parseNetworkWeights(ngi::test::unvalidatedWeightsFile(mutated), name);
        try {
            ngi::nn::referenceForward(net, positions, normals);
            ADD_FAILURE() << "no error for layer " << layer;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()),
                      name + ": the restore produced non-finite values (layer " + std::to_string(layer) + ")");
        }
    };
    // Queries and keys of magnitude ~10 (weights x10): q.k * FLT_MAX overflows (with |q.k| < 1
    // a huge scale is a finite hard maximum).
    ngi::NetworkWeights scale = good;
    for (float& p : scale.parameters) p *= 10.0f;
    ASSERT_NO_THROW(ngi::nn::referenceForward(scale, positions, normals));
    scale.layers[attention].attentionScale = FLT_MAX;
    expectError(scale, "scale.ngiw", attention);
    ngi::NetworkWeights huge = good;
    for (float& p : huge.parameters) p = FLT_MAX;
    expectError(huge, "the asset's WGHT chunk", 0);
    ngi::NetworkWeights slope = good;
    for (float& p : slope.parameters) p = 1e20f * std::abs(p);
    for (ngi::NetworkLayer& l : slope.layers)
        if (l.kind == ngi::LayerKind::Conv) l.activation = ngi::Activation::LeakyReLU, l.activationSlope = 3e38f;
    EXPECT_THROW(ngi::nn::referenceForward(ngi::parseNetworkWeights(ngi::test::unvalidatedWeightsFile(slope), "s.ngiw"),
                                           positions, normals),
                 ngi::Error);
}

TEST(ReferenceOps, AttentionWithOverflowingLogitsReadsOnlyTheImage)
{
    // Logits of +inf (q.k * 3e38): the softmax is NaN, the corner's masked neighbours are
    // still never read (an ASan run would report it); the output is NaN, not garbage.
    ngi::NetworkLayer l;
    l.kind = ngi::LayerKind::NeighborhoodCrossAttention;
    l.inChannels = l.outChannels = 2;
    l.heads = 1;
    l.kernelSize = 15;
    l.attentionScale = 3e38f;
    ngi::nn::FeatureMap q(2, 2, 3), k(2, 2, 3), v(2, 2, 3);
    std::fill(q.data.begin(), q.data.end(), 4.0f);
    std::fill(k.data.begin(), k.data.end(), 4.0f);
    std::fill(v.data.begin(), v.data.end(), 1.0f);
    const ngi::nn::FeatureMap out = ngi::nn::neighborhoodCrossAttention(q, k, v, l);
    for (float x : out.data) EXPECT_FALSE(std::isfinite(x));
    // Finite logits whose differences overflow nothing: an exact average of the window.
    l.attentionScale = 1e-3f;
    const ngi::nn::FeatureMap calm = ngi::nn::neighborhoodCrossAttention(q, k, v, l);
    for (float x : calm.data) EXPECT_FLOAT_EQ(x, 1.0f);
}

TEST(ReferenceOps, BilinearSkipReproducesCoarseSamplesAndInterpolatesLinearFunctions)
{
    ngi::nn::FeatureMap coarse(2, 5, 7);
    for (uint32_t c = 0; c < 2; ++c)
        for (uint32_t y = 0; y < 5; ++y)
            for (uint32_t x = 0; x < 7; ++x) coarse.at(c, y, x) = 0.25f * x - 0.5f * y + float(c);
    const ngi::nn::FeatureMap zero(2, 33, 49);
    const ngi::nn::FeatureMap fine = ngi::nn::bilinearSkip(coarse, zero, 8);
    for (uint32_t c = 0; c < 2; ++c)
        for (uint32_t Y = 0; Y < 33; ++Y)
            for (uint32_t X = 0; X < 49; ++X)
                EXPECT_NEAR(fine.at(c, Y, X), 0.25f * X / 8.0f - 0.5f * Y / 8.0f + float(c), 1e-6f);
    for (uint32_t y = 0; y < 5; ++y)
        for (uint32_t x = 0; x < 7; ++x) EXPECT_EQ(fine.at(1, 8 * y, 8 * x), coarse.at(1, y, x));
}

TEST(ReferenceOps, CubicSkipReproducesLinearFunctionsEverywhereAndQuadraticsInside)
{
    // Catmull-Rom is third-order accurate: quadratics are exact where all four taps are real
    // samples; linear extrapolation beyond the border keeps linear functions exact up to it.
    const uint32_t f = 4, w = 7, h = 5;
    ngi::nn::FeatureMap linear(1, h, w), quadratic(1, h, w);
    auto lin = [](float x, float y) { return 0.25f * x - 0.5f * y + 1.0f; };
    auto quad = [](float x, float y) { return 0.1f * x * x - 0.05f * x * y + 0.2f * y * y + 0.3f * x; };
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            linear.at(0, y, x) = lin(float(x), float(y)), quadratic.at(0, y, x) = quad(float(x), float(y));
    const ngi::nn::FeatureMap zero(1, (h - 1) * f + 1, (w - 1) * f + 1);
    const ngi::nn::FeatureMap a = ngi::nn::cubicSkip(linear, zero, f), b = ngi::nn::cubicSkip(quadratic, zero, f);
    for (uint32_t Y = 0; Y < zero.height; ++Y)
        for (uint32_t X = 0; X < zero.width; ++X) {
            const float x = float(X) / f, y = float(Y) / f;
            EXPECT_NEAR(a.at(0, Y, X), lin(x, y), 1e-5f) << X << "," << Y;
            if (X >= f && X < (w - 2) * f && Y >= f && Y < (h - 2) * f) {
                EXPECT_NEAR(b.at(0, Y, X), quad(x, y), 1e-5f) << X << "," << Y;
            }
            if (X % f == 0 && Y % f == 0) {
                EXPECT_NEAR(b.at(0, Y, X), quadratic.at(0, Y / f, X / f), 1e-6f);
            }
        }
    const std::array<float, 4> half = ngi::nn::catmullRomWeights(0.5f);
    EXPECT_FLOAT_EQ(half[0], -0.0625f);
    EXPECT_FLOAT_EQ(half[1], 0.5625f);
    EXPECT_FLOAT_EQ(half[0] + half[1] + half[2] + half[3], 1.0f);
}

TEST(ReferenceOps, HermiteSkipIsCatmullRomOnAPlaneAndBeatsItOnASphere)
{
    const uint32_t f = 8, w = 9, h = 7;
    const ngi::nn::FeatureMap zero(3, (h - 1) * f + 1, (w - 1) * f + 1);
    // A tilted plane with its normal: every tangent already lies in the tangent plane, so
    // HermiteSkip is exactly Catmull-Rom (linear functions reproduced up to the border).
    ngi::nn::FeatureMap plane(3, h, w), planeNormals(3, h, w);
    const float nx = 0.3f, ny = -0.2f, nz = 1.0f, nl = std::sqrt(nx * nx + ny * ny + nz * nz);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float u = 0.1f * float(x), v = 0.1f * float(y);
            plane.at(0, y, x) = u, plane.at(1, y, x) = v, plane.at(2, y, x) = 0.5f - (nx * u + ny * v) / nz;
            planeNormals.at(0, y, x) = nx / nl, planeNormals.at(1, y, x) = ny / nl, planeNormals.at(2, y, x) = nz / nl;
        }
    const ngi::nn::FeatureMap hp = ngi::nn::hermiteSkip(plane, planeNormals, zero, f),
                              cp = ngi::nn::cubicSkip(plane, zero, f);
    for (size_t i = 0; i < hp.data.size(); ++i) ASSERT_NEAR(hp.data[i], cp.data[i], 2e-6f) << i;
    // A sphere patch sampled by longitude/latitude with its exact normals: the normals fix
    // the tangent planes that Catmull-Rom's differences only estimate, so the restored
    // samples stay much closer to the sphere (measured: max radius error 9.1e-5 vs 3.7e-3).
    ngi::nn::FeatureMap sphere(3, h, w), sphereNormals(3, h, w);
    const float r = 0.5f, step = 0.25f;
    auto point = [&](float lon, float lat, int c) {
        const float p[3] = {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
        return p[c];
    };
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const float lon = step * float(x), lat = step * (float(y) - 3.0f);
                sphere.at(uint32_t(c), y, x) = r * point(lon, lat, c);
                sphereNormals.at(uint32_t(c), y, x) = point(lon, lat, c);
            }
    const ngi::nn::FeatureMap hs = ngi::nn::hermiteSkip(sphere, sphereNormals, zero, f);
    const ngi::nn::FeatureMap cs = ngi::nn::cubicSkip(sphere, zero, f);
    double hermiteError = 0.0, cubicError = 0.0;
    for (uint32_t Y = 0; Y < zero.height; ++Y)
        for (uint32_t X = 0; X < zero.width; ++X) {
            auto radiusError = [&](const ngi::nn::FeatureMap& m) {
                const double a = m.at(0, Y, X), b = m.at(1, Y, X), c = m.at(2, Y, X);
                return std::abs(std::sqrt(a * a + b * b + c * c) - r);
            };
            hermiteError = std::max(hermiteError, radiusError(hs));
            cubicError = std::max(cubicError, radiusError(cs));
            if (X % f == 0 && Y % f == 0) {
                EXPECT_NEAR(hs.at(0, Y, X), sphere.at(0, Y / f, X / f), 1e-6f);  // interpolates
            }
        }
    EXPECT_GT(cubicError, 1e-4);
    EXPECT_LT(hermiteError, 0.1 * cubicError) << hermiteError << " vs " << cubicError;
    EXPECT_THROW(ngi::nn::hermiteSkip(sphere, ngi::nn::FeatureMap(3, h, w - 1), zero, f), ngi::Error);
}

// The shipped networks (assets/sr-xF.ngiw, reproduced by tools/train-sr.sh F): the default
// architecture at their factor, and sane on analytic surfaces they never saw (trained on baked
// meshes only). The input is a 17^2 window of the level F times coarser than a 1025^2 image,
// so neighbouring samples are as far apart as in a real asset. Errors are measured along the
// true normal (what a surface distance sees). On such smooth surfaces the Hermite skip is
// already within ~1e-7 of the truth (x8), far below the errors on baked meshes that the
// networks were trained to reduce (experiments/sr-quality.sh measures those): x8 (exact inputs) must
// stay within 1e-5 of its skip and far better than bilinear; x4, x16 and x32, trained on
// decoded inputs, must move the surface by less than the coding's half step.
TEST(ShippedNetwork, EachIsTheDefaultLayoutAndAddsNoNoiseOnAnalyticSurfaces)
{
    // The input each network was trained for: x8 the exact level; x4, x16, x32 the level as the
    // asset codec decodes it (pyramid positions, predicted normals) at a step inside their
    // training range (tools/train-sr.sh).
    struct Shipped {
        uint32_t factor, step, tangentScale;
    };
    const std::pair<const char*, ngi::AnalyticSurface> surfaces[] = {
        {"sphere", ngi::sphereGeometryImage(1025)}, {"rippled torus", ngi::rippledTorusGeometryImage(1025)}};
    for (const Shipped shipped : {Shipped{4, 32, 4}, Shipped{8, 0, 0}, Shipped{16, 64, 2}, Shipped{32, 1024, 2}}) {
        const uint32_t factor = shipped.factor;
        const std::string file = NGI_SOURCE_DIR "/assets/sr-x" + std::to_string(factor) + ".ngiw";
        SCOPED_TRACE(file);
        const ngi::NetworkWeights net = ngi::readNetworkWeights(file);
        ngi::nn::SuperResolutionConfig config;
        config.scaleFactor = factor;
        const ngi::NetworkWeights layout = ngi::nn::buildSuperResolutionNetwork(config, "x");
        EXPECT_EQ(net.scaleFactor, factor);
        EXPECT_EQ(net.layers, layout.layers);
        EXPECT_EQ(net.parameters.size(), layout.parameters.size());
        const uint32_t levels = uint32_t(std::countr_zero(factor));
        // Coarse window and origin inside one octant of the sphere (x32's 33^2 level: 9^2 over
        // the same fine region as x16's window).
        const uint32_t window = factor == 32 ? 9 : 17, x0 = factor == 32 ? 12 : 24, y0 = factor == 32 ? 20 : 40;
        auto crop = [](const ngi::GeometryImage& image, uint32_t x, uint32_t y, uint32_t n) {
            ngi::nn::FeatureMap m(3, n, n);
            for (uint32_t j = 0; j < n; ++j)
                for (uint32_t i = 0; i < n; ++i)
                    for (uint32_t c = 0; c < 3; ++c) m.at(c, j, i) = image.at(x + i, y + j)[int(c)];
            return m;
        };
        for (const auto& [name, surface] : surfaces) {
            ngi::GeometryImage coarse = ngi::downsampleNested(surface.positions, levels);
            ngi::GeometryImage coarseNormals = ngi::downsampleNested(surface.normals, levels);
            if (shipped.step > 0) {
                ngi::Asset asset;
                asset.coding = {.pyramid = true,
                                .progressive = true,
                                .positionStep = shipped.step,
                                .positionTangentScale = shipped.tangentScale,
                                .normalBits = 0};
                ngi::AssetChart chart;
                chart.fullResolution = coarse.size - 1;
                chart.storedLevel = 0;
                ngi::storeGeometryImage(chart, coarse, coarseNormals);
                asset.charts.push_back(std::move(chart));
                ngi::applyAssetCoding(asset);
                coarse = ngi::storedPositions(asset.charts[0]);
                coarseNormals = ngi::storedNormals(asset.charts[0]);
            }
            const ngi::nn::FeatureMap positions = crop(coarse, x0, y0, window);
            const ngi::nn::FeatureMap normals = crop(coarseNormals, x0, y0, window);
            const uint32_t fine = (window - 1) * factor + 1;
            const ngi::nn::FeatureMap truth = crop(surface.positions, factor * x0, factor * y0, fine);
            const ngi::nn::FeatureMap truthNormals = crop(surface.normals, factor * x0, factor * y0, fine);
            const ngi::nn::FeatureMap restored = ngi::nn::referenceForward(net, positions, normals);
            const ngi::nn::FeatureMap zero(3, fine, fine);
            const ngi::nn::FeatureMap bilinear = ngi::nn::bilinearSkip(positions, zero, factor);
            const ngi::nn::FeatureMap skip = ngi::nn::hermiteSkip(positions, normals, zero, factor);
            // Along the true normal: what a surface distance sees. A network trained on decoded
            // inputs (x4, x16: coarse tangential steps) may also move samples within the tangent
            // plane, which leaves the surface where it is.
            const size_t plane = size_t(fine) * fine;
            auto alongNormal = [&](const ngi::nn::FeatureMap& a, const ngi::nn::FeatureMap& b, size_t k) {
                double d = 0.0;
                for (size_t c = 0; c < 3; ++c)
                    d += (a.data[c * plane + k] - b.data[c * plane + k]) * truthNormals.data[c * plane + k];
                return std::abs(d) / double(plane);
            };
            double networkError = 0.0, bilinearError = 0.0, skipError = 0.0, residual = 0.0, drift = 0.0;
            for (size_t k = 0; k < plane; ++k) {
                networkError += alongNormal(restored, truth, k);
                skipError += alongNormal(skip, truth, k);
                bilinearError += alongNormal(bilinear, truth, k);
                residual += alongNormal(restored, skip, k);
                for (size_t c = 0; c < 3; ++c)
                    drift += std::abs(restored.data[c * plane + k] - skip.data[c * plane + k]) / double(3 * plane);
            }
            std::printf(
                "x%u %s (step %u), along the normal: mean error network %.3e, its skip %.3e, bilinear %.3e; mean "
                "residual beyond the skip %.3e (3D, per coordinate: %.3e)\n",
                factor, name, shipped.step, networkError, skipError, bilinearError, residual, drift);
            if (shipped.step == 0) {
                EXPECT_LT(networkError, 0.5 * bilinearError) << name;
                EXPECT_LT(residual, 1e-5) << name;
            } else {
                // A network trained to remove coding noise cannot tell a smooth surface's exact
                // samples from noisy ones of the smallest step it saw, and moves them by about
                // that much (x4 at step 32: 8.5e-5 from the truth along the normal on the sphere,
                // where its skip is 7.2e-5: on these surfaces it is farther than the bicubic,
                // which is why every asset blends it toward the bicubic by a fitted gain,
                // asset.h). The bound:
                // it moves the surface by less than the coding's own half step.
                EXPECT_LT(residual, 0.5 * shipped.step / 65536.0) << name;
            }
        }
    }
}

TEST(ReferenceOps, PixelShuffleCropPlacesSubPixelsOnTheNestedGrid)
{
    // Channel c*f*f + i*f + j of coarse sample (y, x) lands at fine (f*y + i, f*x + j).
    const uint32_t f = 2;
    ngi::nn::FeatureMap in(2 * f * f, 3, 4);
    for (uint32_t ch = 0; ch < in.channels; ++ch)
        for (uint32_t y = 0; y < 3; ++y)
            for (uint32_t x = 0; x < 4; ++x) in.at(ch, y, x) = float(ch * 100 + y * 10 + x);
    const ngi::nn::FeatureMap out = ngi::nn::pixelShuffleCrop(in, f);
    ASSERT_EQ(out.channels, 2u);
    ASSERT_EQ(out.height, 5u);
    ASSERT_EQ(out.width, 7u);
    EXPECT_EQ(out.at(1, 3, 4), float((1 * 4 + 1 * 2 + 0) * 100 + 1 * 10 + 2));
    EXPECT_EQ(out.at(0, 4, 6), float(0 * 100 + 2 * 10 + 3));
}

TEST(ReferenceOps, AttentionWithZeroQueriesAveragesTheValidNeighbours)
{
    ngi::NetworkLayer l;
    l.kind = ngi::LayerKind::NeighborhoodCrossAttention;
    l.inChannels = l.outChannels = 4;
    l.heads = 2;
    l.kernelSize = 3;
    l.attentionScale = 0.7f;
    const ngi::nn::FeatureMap q(4, 5, 3);
    const ngi::nn::FeatureMap k = randomMap(4, 5, 3, 1), v = randomMap(4, 5, 3, 2);
    const ngi::nn::FeatureMap out = ngi::nn::neighborhoodCrossAttention(q, k, v, l);
    // Corner (0, 0): the 4 in-image neighbours get equal weight; masked ones none.
    const float mean = (v.at(3, 0, 0) + v.at(3, 0, 1) + v.at(3, 1, 0) + v.at(3, 1, 1)) / 4.0f;
    EXPECT_NEAR(out.at(3, 0, 0), mean, 1e-6f);
}

TEST(ReferenceOps, ConvReplicatePaddingOfAConstantIsTheKernelSum)
{
    ngi::NetworkLayer l;
    l.kind = ngi::LayerKind::Conv;
    l.inChannels = 1;
    l.outChannels = 1;
    l.kernelSize = 3;
    l.padding = ngi::Padding::Replicate;
    l.biasOffset = 9;
    std::vector<float> params{1, 2, 3, 4, 5, 6, 7, 8, 9, 0.5f};
    ngi::nn::FeatureMap in(1, 4, 3);
    std::fill(in.data.begin(), in.data.end(), 2.0f);
    const ngi::nn::FeatureMap out = ngi::nn::conv2d(in, l, params, nullptr);
    for (float v : out.data) EXPECT_FLOAT_EQ(v, 2.0f * 45.0f + 0.5f);
    l.padding = ngi::Padding::Zero;
    const ngi::nn::FeatureMap zero = ngi::nn::conv2d(in, l, params, nullptr);
    EXPECT_FLOAT_EQ(zero.at(0, 0, 0), 2.0f * (5 + 6 + 8 + 9) + 0.5f);
}

}  // namespace

// Transfer learning (ngi-train --init): an x2 network started from an x4 one predicts, at its
// own fine samples, exactly what the donor predicts at the same positions (fine sample 2Y of
// x4). With the donor's full-resolution conv set to the identity, the whole output is
// comparable sample by sample: the skip interpolates at the same fractions (t = 1/2 = 2/4).
TEST(ParameterTransfer, AnX2NetworkFromAnX4OnePredictsTheDonorsSharedSubSamples)
{
    ngi::NetworkWeights donor = ngi::test::smallDefaultNetwork("donor-x4", 11, 0.5f);
    ASSERT_EQ(donor.scaleFactor, 4u);
    // The last Conv is the 3 -> 3 full-resolution conv: make it the identity.
    size_t last = 0;
    for (size_t i = 0; i < donor.layers.size(); ++i)
        if (donor.layers[i].kind == ngi::LayerKind::Conv) last = i;
    const ngi::NetworkLayer& fin = donor.layers[last];
    ASSERT_EQ(fin.inChannels, 3u);
    ASSERT_EQ(fin.kernelSize, 3u);
    for (uint32_t o = 0; o < 3; ++o) {
        for (uint32_t t = 0; t < 27; ++t) donor.parameters[fin.weightOffset + o * 27 + t] = 0.0f;
        donor.parameters[fin.weightOffset + o * 27 + o * 9 + 4] = 1.0f;
        donor.parameters[fin.biasOffset + o] = 0.0f;
    }
    ngi::nn::SuperResolutionConfig c = ngi::test::smallDefaultConfig(2);
    ngi::NetworkWeights x2 = ngi::nn::buildSuperResolutionNetwork(c, "x2");
    size_t convs = 0;
    for (const ngi::NetworkLayer& l : x2.layers) convs += l.kind == ngi::LayerKind::Conv;
    EXPECT_EQ(ngi::nn::transferParameters(x2, donor), convs);  // every Conv, the sub-pixel one too

    const ngi::nn::FeatureMap positions = randomMap(3, 9, 9, 3);
    ngi::nn::FeatureMap normals = randomMap(3, 9, 9, 4);
    for (uint32_t p = 0; p < 81; ++p) {
        float n2 = 0.0f;
        for (uint32_t ch = 0; ch < 3; ++ch) n2 += normals.data[ch * 81 + p] * normals.data[ch * 81 + p];
        for (uint32_t ch = 0; ch < 3; ++ch) normals.data[ch * 81 + p] /= std::sqrt(n2);
    }
    const ngi::nn::FeatureMap out4 = ngi::nn::referenceForward(donor, positions, normals);
    const ngi::nn::FeatureMap out2 = ngi::nn::referenceForward(x2, positions, normals);
    ASSERT_EQ(out4.width, 33u);
    ASSERT_EQ(out2.width, 17u);
    double worst = 0.0, scale = 0.0;
    for (uint32_t ch = 0; ch < 3; ++ch)
        for (uint32_t y = 0; y < 17; ++y)
            for (uint32_t x = 0; x < 17; ++x) {
                const float a = out2.data[(ch * 17 + y) * 17 + x];
                const float b = out4.data[(ch * 33 + 2 * y) * 33 + 2 * x];
                worst = std::max(worst, double(std::fabs(a - b)));
                scale = std::max(scale, double(std::fabs(b)));
            }
    EXPECT_GT(scale, 0.1);                   // the outputs are not trivially 0
    EXPECT_LE(worst, 1e-5 * (1.0 + scale));  // float rounding of the same sums

    // Another architecture is refused, naming both networks.
    c.resBlocks = 2;
    ngi::NetworkWeights deeper = ngi::nn::buildSuperResolutionNetwork(c, "deeper");
    try {
        ngi::nn::transferParameters(deeper, donor);
        FAIL() << "a deeper network took the donor's parameters";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("donor-x4"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("deeper"), std::string::npos) << e.what();
    }
}
