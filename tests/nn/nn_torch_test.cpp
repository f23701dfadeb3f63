// The libtorch side of ngi nn (one translation unit: libtorch headers are heavy):
// MS-SSIM against known values and an independent double-precision implementation, the
// C++ reference forward against the libtorch forward on the same random weights, and a
// training smoke test (loss decreases, checkpoints resume, bad data is rejected clearly).
#include "ngi/error.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/ms_ssim.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/nn/torch_network.h"
#include "ngi/nn/training.h"
#include "ngi/png_io.h"
#include "ngi/pyramid_codec.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace {

using ngi::nn::FeatureMap;

// ---- MS-SSIM -------------------------------------------------------------------------

// Independent MS-SSIM: plain loops in double, 2D window sums, same conventions as
// ms_ssim.h (valid window, 2x2 floor average pooling, clamp, product over scales).
double naiveMsSsim(const torch::Tensor& xIn, const torch::Tensor& yIn, const ngi::nn::MsSsimOptions& o)
{
    const int64_t n = xIn.size(0), channels = xIn.size(1);
    const double c1 = std::pow(o.k1 * o.dataRange, 2), c2 = std::pow(o.k2 * o.dataRange, 2);
    std::vector<double> g(size_t(o.windowSize));
    double gs = 0;
    for (int i = 0; i < o.windowSize; ++i) {
        const double t = i - (o.windowSize - 1) / 2.0;
        gs += g[size_t(i)] = std::exp(-t * t / (2 * o.sigma * o.sigma));
    }
    for (double& v : g) v /= gs;
    double total = 0;
    for (int64_t b = 0; b < n; ++b)
        for (int64_t c = 0; c < channels; ++c) {
            int64_t h = xIn.size(2), w = xIn.size(3);
            std::vector<double> x(size_t(h * w)), y(size_t(h * w));
            for (int64_t i = 0; i < h; ++i)
                for (int64_t j = 0; j < w; ++j) {
                    x[size_t(i * w + j)] = xIn[b][c][i][j].item<float>();
                    y[size_t(i * w + j)] = yIn[b][c][i][j].item<float>();
                }
            double product = 1;
            for (size_t s = 0; s < o.weights.size(); ++s) {
                if (s > 0) {
                    const int64_t h2 = h / 2, w2 = w / 2;
                    std::vector<double> x2(size_t(h2 * w2)), y2(size_t(h2 * w2));
                    for (int64_t i = 0; i < h2; ++i)
                        for (int64_t j = 0; j < w2; ++j) {
                            auto avg = [&](const std::vector<double>& v) {
                                return (v[size_t(2 * i * w + 2 * j)] + v[size_t(2 * i * w + 2 * j + 1)] +
                                        v[size_t((2 * i + 1) * w + 2 * j)] + v[size_t((2 * i + 1) * w + 2 * j + 1)]) /
                                    4;
                            };
                            x2[size_t(i * w2 + j)] = avg(x);
                            y2[size_t(i * w2 + j)] = avg(y);
                        }
                    x = x2, y = y2, h = h2, w = w2;
                }
                const int64_t k = o.windowSize, oh = h - k + 1, ow = w - k + 1;
                double sum = 0;
                for (int64_t i = 0; i < oh; ++i)
                    for (int64_t j = 0; j < ow; ++j) {
                        double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
                        for (int64_t a = 0; a < k; ++a)
                            for (int64_t d = 0; d < k; ++d) {
                                const double wt = g[size_t(a)] * g[size_t(d)];
                                const double xv = x[size_t((i + a) * w + j + d)], yv = y[size_t((i + a) * w + j + d)];
                                mx += wt * xv, my += wt * yv, xx += wt * xv * xv, yy += wt * yv * yv,
                                    xy += wt * xv * yv;
                            }
                        double v = (2 * (xy - mx * my) + c2) / ((xx - mx * mx) + (yy - my * my) + c2);
                        if (s + 1 == o.weights.size()) v *= (2 * mx * my + c1) / (mx * mx + my * my + c1);
                        sum += v;
                    }
                product *= std::pow(std::max(sum / double(oh * ow), 1e-6), o.weights[s]);
            }
            total += product;
        }
    return total / double(n * channels);
}

torch::Tensor smoothImage(int64_t n, int64_t c, int64_t h, int64_t w, uint64_t seed)
{
    torch::manual_seed(seed);
    // Low-frequency structure + a little high-frequency texture, values in about [0, 1].
    torch::Tensor coarse = torch::rand({n, c, h / 8 + 2, w / 8 + 2});
    torch::Tensor up = torch::nn::functional::interpolate(coarse,
                                                          torch::nn::functional::InterpolateFuncOptions()
                                                              .size(std::vector<int64_t>{h, w})
                                                              .mode(torch::kBilinear)
                                                              .align_corners(true));
    return up * 0.9 + 0.1 * torch::rand({n, c, h, w});
}

TEST(MsSsim, IdenticalImagesScoreOne)
{
    const torch::Tensor x = smoothImage(2, 3, 180, 190, 1);
    EXPECT_NEAR(ngi::nn::msSsim(x, x).item<double>(), 1.0, 1e-6);
}

TEST(MsSsim, ConstantImagesGiveTheLuminanceTermByHand)
{
    // sigma = 0 everywhere: cs = C2 / C2 = 1 at every scale; only l at the coarsest scale
    // remains: MS-SSIM = ((2ab + C1) / (a^2 + b^2 + C1))^0.1333.
    const double a = 0.3, b = 0.7, c1 = 1e-4;
    // Exact in double precision; in fp32 the residual cancellation in E[x^2] - mu^2 leaves
    // ~1e-8 variances against C2 = 9e-4, hence the looser bound.
    const torch::Tensor x = torch::full({1, 1, 176, 176}, a, torch::kFloat64);
    const torch::Tensor y = torch::full({1, 1, 176, 176}, b, torch::kFloat64);
    const double expected = std::pow((2 * a * b + c1) / (a * a + b * b + c1), 0.1333);
    EXPECT_NEAR(ngi::nn::msSsim(x, y).item<double>(), expected, 1e-9);
    EXPECT_NEAR(ngi::nn::msSsim(x.to(torch::kFloat32), y.to(torch::kFloat32)).item<double>(), expected, 2e-4);
}

TEST(MsSsim, MatchesAnIndependentDoublePrecisionImplementation)
{
    const torch::Tensor x = smoothImage(1, 2, 181, 177, 2);
    const torch::Tensor y = (x + 0.05 * torch::randn_like(x)).clamp(0, 1);
    const ngi::nn::MsSsimOptions o;
    EXPECT_NEAR(ngi::nn::msSsim(x, y, o).item<double>(), naiveMsSsim(x, y, o), 1e-5);
    ngi::nn::MsSsimOptions small;
    small.windowSize = 7;
    small.sigma = 1.0;
    small.weights = {0.3, 0.7};
    const torch::Tensor xs = smoothImage(2, 3, 31, 23, 3), ys = smoothImage(2, 3, 31, 23, 4);
    EXPECT_NEAR(ngi::nn::msSsim(xs, ys, small).item<double>(), naiveMsSsim(xs, ys, small), 1e-5);
}

TEST(MsSsim, DecreasesWithNoiseAndIsSymmetric)
{
    const torch::Tensor x = smoothImage(1, 3, 192, 192, 5);
    const torch::Tensor noise = torch::randn_like(x);
    double previous = 1.0;
    for (double sigma : {0.005, 0.02, 0.05, 0.2}) {
        const torch::Tensor y = x + sigma * noise;
        const double score = ngi::nn::msSsim(x, y).item<double>();
        EXPECT_LT(score, previous) << "sigma " << sigma;
        EXPECT_NEAR(score, ngi::nn::msSsim(y, x).item<double>(), 1e-6);
        previous = score;
    }
    EXPECT_GT(ngi::nn::msSsim(x, x + 0.005 * noise).item<double>(), 0.99);
    EXPECT_LT(previous, 0.9);
    EXPECT_THROW(ngi::nn::msSsim(x.narrow(2, 0, 100), x.narrow(2, 0, 100)), ngi::Error);
}

// ---- reference forward == libtorch forward --------------------------------------------

torch::Tensor toTorch(const FeatureMap& m)
{
    return torch::from_blob(const_cast<float*>(m.data.data()), {1, m.channels, m.height, m.width}, torch::kFloat32)
        .clone();
}

void randomInputs(uint32_t h, uint32_t w, uint32_t seed, FeatureMap& positions, FeatureMap& normals)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    positions = FeatureMap(3, h, w);
    normals = FeatureMap(3, h, w);
    for (float& v : positions.data) v = u(rng);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float n[3], len = 0;
            for (float& c : n) {
                c = u(rng) * 2 - 1;
                len += c * c;
            }
            for (int c = 0; c < 3; ++c) normals.at(c, y, x) = n[c] / std::sqrt(len);
        }
}

double maxAbsDifference(const FeatureMap& reference, const torch::Tensor& t)
{
    const torch::Tensor r = toTorch(reference);
    EXPECT_EQ(r.sizes(), t.sizes());
    return (r - t).abs().max().item<double>();
}

ngi::nn::SuperResolutionConfig tinyConfig()
{
    ngi::nn::SuperResolutionConfig c;
    c.scaleFactor = 4;
    c.features = 8;
    c.branchConvs = 2;
    c.attentionHeads = 2;
    c.resBlocks = 1;
    c.upsampleFeatures = 4;
    return c;
}

TEST(ReferenceForward, MatchesLibtorchOnRandomWeightsAndOddShapes)
{
    torch::NoGradGuard noGrad;
    ngi::nn::SuperResolutionConfig twoStage = tinyConfig();  // x32: two sub-pixel stages
    twoStage.scaleFactor = 32;
    for (const auto& [config, h, w] :
         {std::tuple{tinyConfig(), 7u, 5u}, std::tuple{ngi::nn::SuperResolutionConfig{}, 13u, 11u},
          std::tuple{twoStage, 4u, 3u}}) {
        // Random weights at full scale (no down-scaled init) so every op contributes.
        // Variance-preserving random weights (uniform, bound sqrt(3 / fan-in)) and random
        // biases, so activations stay O(1) through the whole network and every op matters.
        ngi::NetworkWeights layout = ngi::nn::buildSuperResolutionNetwork(config, "parity");
        std::mt19937 rng(11);
        for (const ngi::NetworkLayer& l : layout.layers) {
            if (l.kind != ngi::LayerKind::Conv) continue;
            const float bound = std::sqrt(3.0f / float(l.inChannels * l.kernelSize * l.kernelSize));
            std::uniform_real_distribution<float> u(-bound, bound), b(-0.1f, 0.1f);
            const size_t count = size_t(l.outChannels) * l.inChannels * l.kernelSize * l.kernelSize;
            for (size_t i = 0; i < count; ++i) layout.parameters[l.weightOffset + i] = u(rng);
            for (size_t i = 0; i < l.outChannels; ++i) layout.parameters[l.biasOffset + i] = b(rng);
        }
        ngi::nn::SuperResolutionNet net(layout, false);
        FeatureMap positions, normals;
        randomInputs(h, w, 3, positions, normals);
        const torch::Tensor out = net->forward(toTorch(positions), toTorch(normals));
        const FeatureMap reference = ngi::nn::referenceForward(layout, positions, normals);
        EXPECT_EQ(reference.height, (h - 1) * config.scaleFactor + 1);
        EXPECT_GT((out - ngi::nn::bilinearUpsample(toTorch(positions), config.scaleFactor)).abs().max().item<double>(),
                  0.1);
        EXPECT_LE(maxAbsDifference(reference, out), 1e-5) << ngi::nn::describe(config);
        // Export -> file -> import gives the same network.
        const ngi::NetworkWeights exported = net->exportWeights();
        EXPECT_EQ(exported.parameters, layout.parameters);
        ngi::nn::SuperResolutionNet again(ngi::parseNetworkWeights(ngi::serializeNetworkWeights(exported), "x"), false);
        EXPECT_TRUE(torch::equal(again->forward(toTorch(positions), toTorch(normals)), out));
    }
}

TEST(ReferenceForward, InitializedNetworkStartsCloseToItsSkip)
{
    torch::NoGradGuard noGrad;
    const ngi::NetworkWeights layout = ngi::nn::buildSuperResolutionNetwork(tinyConfig(), "init");
    ngi::nn::SuperResolutionNet net(layout, true, 5);
    FeatureMap positions, normals;
    randomInputs(9, 9, 4, positions, normals);
    // Neighbouring stored samples differ by ~1/128 on real geometry images.
    for (float& v : positions.data) v = 0.5f + (v - 0.5f) / 64.0f;
    const torch::Tensor p = toTorch(positions);
    const torch::Tensor out = net->forward(p, toTorch(normals));
    const torch::Tensor cubic = ngi::nn::hermiteUpsample(p, toTorch(normals), 4);  // the default skip
    // Residual ~1e-6 (x0.01 init at gain 2^-10): far below the ~1e-4 errors to be learnt,
    // but not zero, so every layer gets a gradient.
    EXPECT_LT((out - cubic).abs().max().item<double>(), 1e-4);
    EXPECT_GT((out - cubic).abs().max().item<double>(), 0.0);
    EXPECT_LE(maxAbsDifference(ngi::nn::referenceForward(net->exportWeights(), positions, normals), out), 1e-5);
}

// The convolutions reading the stored positions train as zero-sum kernels (torch_network.h),
// so the network is blind to where the surface sits: moving the input by c moves the output
// by exactly c (the skip's weights sum to 1), whatever the trained weights are.
TEST(TorchNetwork, TrainedNetworkIsTranslationEquivariant)
{
    torch::NoGradGuard noGrad;
    const ngi::NetworkWeights layout = ngi::nn::buildSuperResolutionNetwork(tinyConfig(), "shift");
    ngi::nn::SuperResolutionNet net(layout, true, 7);
    torch::manual_seed(3);
    for (torch::Tensor& p : net->parameters()) p.uniform_(-0.5, 0.5);  // as if trained: far from the init
    net->projectConstrainedWeights();                                  // as the trainer does after each step
    FeatureMap positions, normals;
    randomInputs(9, 7, 8, positions, normals);
    const torch::Tensor p = toTorch(positions), n = toTorch(normals);
    const torch::Tensor shift = torch::tensor({0.25f, -0.125f, 0.5f}).reshape({1, 3, 1, 1});
    const torch::Tensor out = net->forward(p, n), moved = net->forward(p + shift, n);
    EXPECT_GT((out - ngi::nn::cubicUpsample(p, 4)).abs().max().item<double>(), 1e-3);  // a real residual
    EXPECT_LE((moved - out - shift).abs().max().item<double>(), 2e-6);
    // Exported, the position kernels sum to zero; loaded again they run unchanged.
    const ngi::NetworkWeights exported = net->exportWeights();
    const ngi::NetworkLayer& first = exported.layers[0];
    ASSERT_EQ(first.inputs[0], ngi::kPositionInputTensor);
    for (uint32_t k = 0; k < first.outChannels * first.inChannels; ++k) {
        double sum = 0.0;
        for (uint32_t t = 0; t < 9; ++t) sum += exported.parameters[first.weightOffset + k * 9 + t];
        EXPECT_NEAR(sum, 0.0, 1e-4) << "kernel " << k;
    }
    ngi::nn::SuperResolutionNet again(exported, false);
    EXPECT_LE((again->forward(p, n) - out).abs().max().item<double>(), 1e-6);
    EXPECT_LE(maxAbsDifference(ngi::nn::referenceForward(exported, positions, normals), out), 1e-5);
}

TEST(ReferenceOps, LibtorchCubicUpsampleMatchesTheReferenceCubicSkip)
{
    torch::NoGradGuard noGrad;
    for (uint32_t f : {2u, 8u}) {
        FeatureMap coarse(5, 7, 13);
        std::mt19937 rng(f);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        for (float& v : coarse.data) v = u(rng);
        const FeatureMap zero(5, 6 * f + 1, 12 * f + 1);
        const FeatureMap expected = ngi::nn::cubicSkip(coarse, zero, f);
        EXPECT_LE(maxAbsDifference(expected, ngi::nn::cubicUpsample(toTorch(coarse), f)), 1e-5) << f;
    }
}

TEST(ReferenceOps, LibtorchHermiteUpsampleMatchesTheReferenceHermiteSkip)
{
    torch::NoGradGuard noGrad;
    for (uint32_t f : {2u, 8u}) {
        FeatureMap positions, normals;
        randomInputs(7, 13, f, positions, normals);
        const FeatureMap zero(3, 6 * f + 1, 12 * f + 1);
        const FeatureMap expected = ngi::nn::hermiteSkip(positions, normals, zero, f);
        const torch::Tensor got = ngi::nn::hermiteUpsample(toTorch(positions), toTorch(normals), f);
        EXPECT_LE(maxAbsDifference(expected, got), 1e-5) << f;
        // Not Catmull-Rom: random normals bend the tangents.
        EXPECT_GT((got - ngi::nn::cubicUpsample(toTorch(positions), f)).abs().max().item<double>(), 1e-2);
    }
}

// ---- training ------------------------------------------------------------------------

// A bumpy height field over the unit square with its analytic normals (size 2^k + 1).
void syntheticGeometryImage(uint32_t size, float phase, ngi::GeometryImage& positions, ngi::GeometryImage& normals)
{
    positions = ngi::GeometryImage(size);
    normals = ngi::GeometryImage(size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const float u = float(x) / float(size - 1), v = float(y) / float(size - 1);
            const float a = 9.0f, b = 7.0f;
            const float z = 0.5f + 0.15f * std::sin(a * u + phase) * std::cos(b * v) + 0.1f * (u - 0.5f) * (u - 0.5f);
            const float dzdu = 0.15f * a * std::cos(a * u + phase) * std::cos(b * v) + 0.2f * (u - 0.5f);
            const float dzdv = -0.15f * b * std::sin(a * u + phase) * std::sin(b * v);
            positions.at(x, y) = {u, v, z};
            const glm::vec3 n(-dzdu, -dzdv, 1.0f);
            normals.at(x, y) = n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        }
}

void writeGeometryPng(const std::filesystem::path& path, const ngi::GeometryImage& image, bool normals)
{
    ngi::PngImage png;
    png.width = png.height = image.size;
    png.channels = 3;
    png.bitDepth = 16;
    for (const glm::vec3& t : image.texels)
        for (int c = 0; c < 3; ++c)
            png.samples.push_back(
                uint16_t(std::lround(std::clamp(normals ? t[c] * 0.5f + 0.5f : t[c], 0.0f, 1.0f) * 65535.0f)));
    ngi::writePng(path, png);
}

std::filesystem::path writeSyntheticSet(const std::string& dirName)
{
    const auto dir = std::filesystem::temp_directory_path() / dirName;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (int i = 0; i < 2; ++i) {
        ngi::GeometryImage p, n;
        syntheticGeometryImage(65, 0.7f * float(i), p, n);
        // s0 in ngi-bake's spelling, s1 in the plural one: both are read.
        writeGeometryPng(dir / ("s" + std::to_string(i) + (i == 0 ? "_position.png" : "_positions.png")), p, false);
        writeGeometryPng(dir / ("s" + std::to_string(i) + (i == 0 ? "_normal.png" : "_normals.png")), n, true);
    }
    return dir;
}

ngi::nn::TrainOptions smokeOptions()
{
    ngi::nn::TrainOptions o;
    o.learningRate = 2e-3;
    o.patches.patchSamples = 13;  // 13 coarse samples -> 49 fine, loss window 33 at x4
    o.patches.contextSamples = 2;
    o.patches.batchSize = 4;
    o.msSsim.windowSize = 7;
    o.msSsim.sigma = 1.0;
    o.msSsim.weights = {0.5, 0.5};
    o.checkpointEvery = 0;
    return o;
}

TEST(Training, PatchesAreAlignedWithTheirTargets)
{
    // With a network that is exactly its skip (zero residual), the loss on a linear
    // (planar) image with its true normal is zero for every patch, symmetry and border
    // placement (every skip kind reproduces planes).
    ngi::GeometryImage p(65), n(65);
    const glm::vec3 normal = glm::normalize(glm::vec3(-0.2f, 0.1f, 1.0f));
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            p.at(x, y) = {x / 64.0f, y / 64.0f, 0.3f + 0.2f * x / 64.0f - 0.1f * y / 64.0f};
            n.at(x, y) = normal;
        }
    const std::vector<ngi::nn::TrainingImage> images{ngi::nn::makeTrainingImage("plane", p, n, 4)};
    ngi::NetworkWeights layout = ngi::nn::buildSuperResolutionNetwork(tinyConfig(), "zero");
    ngi::nn::SuperResolutionNet net(layout, false);  // all-zero parameters: output = the skip
    std::mt19937_64 rng(3);
    const ngi::nn::TrainOptions o = smokeOptions();
    for (int i = 0; i < 10; ++i) {
        const ngi::nn::PatchBatch batch = ngi::nn::samplePatches(images, 4, o.patches, rng);
        const ngi::nn::LossTerms loss = ngi::nn::trainingLoss(net, batch, o.msSsim);
        EXPECT_LT(loss.l1, 1e-6);
    }
}

TEST(Training, PointToPlaneL1ChargesOnlyTheErrorAlongTheTargetNormal)
{
    // A plane with normal n: moving every restored sample along the plane costs nothing,
    // moving it by d along n costs |d|; the paper's L1 charges both.
    const torch::Tensor n = torch::tensor({0.6f, 0.0f, 0.8f}).view({1, 3, 1, 1}).expand({2, 3, 9, 9});
    const torch::Tensor target = torch::rand({2, 3, 9, 9});
    const torch::Tensor along = torch::tensor({0.8f, 0.0f, -0.6f}).view({1, 3, 1, 1}) * 1e-3f;  // tangent
    EXPECT_LT(ngi::nn::pointToPlaneL1(target + along, target, n).item<double>(), 1e-7);
    EXPECT_NEAR(ngi::nn::pointToPlaneL1(target - 2e-3f * n, target, n).item<double>(), 2e-3, 1e-7);
    EXPECT_THROW(ngi::nn::pointToPlaneL1(target, target, n.narrow(2, 0, 4)), ngi::Error);

    // trainingLoss adds it with its weight: a zero network on a curved image, where the skip
    // leaves errors off the plane, reports the term and its total grows by weight x term.
    ngi::GeometryImage p(65), nrm(65);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const float u = x / 64.0f, v = y / 64.0f, z = 0.3f + 0.2f * std::sin(9.0f * u) * std::cos(7.0f * v);
            p.at(x, y) = {u, v, z};
            nrm.at(x, y) = glm::normalize(glm::vec3(-1.8f * std::cos(9.0f * u) * std::cos(7.0f * v),
                                                    1.4f * std::sin(9.0f * u) * std::sin(7.0f * v), 1.0f));
        }
    const std::vector<ngi::nn::TrainingImage> images{ngi::nn::makeTrainingImage("wave", p, nrm, 4)};
    ngi::nn::SuperResolutionNet net(ngi::nn::buildSuperResolutionNetwork(tinyConfig(), "zero"), false);
    std::mt19937_64 rng(5);
    const ngi::nn::TrainOptions o = smokeOptions();
    const ngi::nn::PatchBatch batch = ngi::nn::samplePatches(images, 4, o.patches, rng);
    ASSERT_EQ(batch.targetNormals.sizes(), batch.target.sizes());
    const ngi::nn::LossTerms paper = ngi::nn::trainingLoss(net, batch, o.msSsim);
    const ngi::nn::LossTerms both = ngi::nn::trainingLoss(net, batch, o.msSsim, 3.0);
    EXPECT_EQ(paper.pointToPlaneL1, 0.0);
    EXPECT_GT(both.pointToPlaneL1, 1e-6);
    EXPECT_LE(both.pointToPlaneL1, both.l1 * 3.0 + 1e-9);  // |<e, n>| <= |e|_1 = 3 x the mean L1
    EXPECT_NEAR(both.total.item<double>(), paper.total.item<double>() + 3.0 * both.pointToPlaneL1, 1e-6);
}

TEST(Training, FewStepsOfATinyModelReduceTheLoss)
{
    torch::set_num_threads(1);  // tiny tensors: a second (spinning) thread only costs here
    const auto dir = writeSyntheticSet("ngi_nn_smoke");
    const std::vector<ngi::nn::TrainingImage> images = ngi::nn::loadTrainingSet(dir, 4);
    ASSERT_EQ(images.size(), 2u);
    ngi::nn::SuperResolutionNet net(ngi::nn::buildSuperResolutionNetwork(tinyConfig(), "smoke"), true, 1);
    ngi::nn::TrainOptions o = smokeOptions();
    std::mt19937_64 rng(99);
    ngi::nn::PatchOptions fixed = o.patches;
    fixed.batchSize = 16;
    const ngi::nn::PatchBatch probe = ngi::nn::samplePatches(images, 4, fixed, rng);
    const double before = ngi::nn::trainingLoss(net, probe, o.msSsim).total.item<double>();
    o.steps = 60;
    o.checkpointDirectory = dir / "checkpoints";
    o.checkpointEvery = 30;
    uint64_t calls = 0;
    const ngi::nn::TrainProgress last = ngi::nn::train(net, images, o, [&](const ngi::nn::TrainProgress&) { ++calls; });
    EXPECT_EQ(calls, 60u);
    EXPECT_EQ(last.step, 60u);
    const double after = ngi::nn::trainingLoss(net, probe, o.msSsim).total.item<double>();
    EXPECT_LT(after, 0.9 * before) << "before " << before << " after " << after;  // measured: -14%
    // The checkpoint is written through the output stager: no temporary file stays beside it.
    for (const auto& entry : std::filesystem::directory_iterator(o.checkpointDirectory))
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
    EXPECT_TRUE(std::filesystem::is_regular_file(o.checkpointDirectory / "checkpoint.optim.pt"));

    // Resume from the step-60 checkpoint and continue to 65.
    uint64_t step = 0;
    ngi::nn::SuperResolutionNet resumed(ngi::nn::readCheckpoint(o.checkpointDirectory, step), false);
    EXPECT_EQ(step, 60u);
    EXPECT_TRUE(
        torch::equal(resumed->forward(probe.positions, probe.normals), net->forward(probe.positions, probe.normals)));
    o.steps = 65;
    o.resume = true;
    calls = 0;
    ngi::nn::train(resumed, images, o, [&](const ngi::nn::TrainProgress& p) {
        ++calls;
        EXPECT_GT(p.step, 60u);
    });
    EXPECT_EQ(calls, 5u);
    std::filesystem::remove_all(dir);
}

TEST(Training, RejectsMissingOrCorruptDataWithTheFileName)
{
    const auto dir = writeSyntheticSet("ngi_nn_bad_data");
    auto expectError = [&](const std::string& needle) {
        try {
            ngi::nn::loadTrainingSet(dir, 4);
            ADD_FAILURE() << "accepted bad data (" << needle << ")";
        } catch (const ngi::Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    std::filesystem::remove(dir / "s1_normals.png");
    expectError("s1_normals.png");
    {
        std::ofstream(dir / "s1_normals.png") << "not a png";
    }
    expectError("s1_normals.png");
    std::filesystem::remove_all(dir);
    try {
        ngi::nn::loadTrainingSet(dir, 4);
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("no such training data directory"), std::string::npos);
    }
    std::filesystem::create_directories(dir);
    EXPECT_THROW(ngi::nn::loadTrainingSet(dir, 4), ngi::Error);
    std::filesystem::remove_all(dir);
}

TEST(DecodedInputs, StepOneIsTheQuantizedLevelAndStepQStaysWithinHalfAStep)
{
    // 65^2 full image, x4: a 17^2 input level, decoded at steps 1, 64 and 512 (xyz residuals:
    // the codec's step / 2 bound holds per component).
    ngi::GeometryImage p, n;
    syntheticGeometryImage(65, 0.3f, p, n);
    const ngi::nn::TrainingImage t = ngi::nn::makeTrainingImage("s", p, n, 4, {{1, 64, 512}, 0});
    ASSERT_EQ(t.decodedPositions.size(), 3u);
    ASSERT_EQ(t.decodedNormals.size(), 3u);
    const int64_t s = t.coarsePositions.size(1);
    ASSERT_EQ(s, 17);
    const torch::Tensor quantized = torch::round(t.coarsePositions.clamp(0.0, 1.0) * 65535.0);
    // Step 1 is lossless: the u16 quantization of the input, exactly (float of u16 / 65535).
    EXPECT_LT((t.decodedPositions[0] * 65535.0 - quantized).abs().max().item<double>(), 1e-2);
    // Its normals are the reader's prediction from those positions (0 residual bits): the
    // codec's normalsFromPositions, either orientation, within the u16 encoding.
    std::vector<uint16_t> u16(size_t(s * s * 3));
    const torch::Tensor q = quantized.contiguous();
    for (int64_t i = 0; i < s * s; ++i)
        for (int c = 0; c < 3; ++c) u16[size_t(i * 3 + c)] = uint16_t(q[c].view(-1)[i].item<float>());
    double best = 1e9;
    for (bool flip : {false, true}) {
        const std::vector<uint16_t> predicted = ngi::normalsFromPositions(u16, uint32_t(s), flip);
        double worst = 0.0;
        for (int64_t i = 0; i < s * s; ++i) {
            glm::vec3 v;
            for (int c = 0; c < 3; ++c) v[c] = predicted[size_t(i * 3 + c)] / 65535.0f * 2.0f - 1.0f;
            v = glm::normalize(v);
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(double(v[c]) - t.decodedNormals[0][c].view(-1)[i].item<double>()));
        }
        best = std::min(best, worst);
    }
    EXPECT_LT(best, 1e-5);
    // Step q: every decoded sample within q / 2 units of the input's quantization, and the
    // coarse steps really move samples (the test would pass on a copy otherwise).
    const std::array<double, 3> steps{1, 64, 512};
    for (size_t v = 1; v < 3; ++v) {
        const double error = (t.decodedPositions[v] * 65535.0 - quantized).abs().max().item<double>();
        EXPECT_LE(error, steps[v] / 2 + 1e-2) << "step " << steps[v];
        EXPECT_GT(error, 1.0) << "step " << steps[v];
    }
    // Plain images have no variants, and patches draw from the variants when there are.
    EXPECT_TRUE(ngi::nn::makeTrainingImage("s", p, n, 4).decodedPositions.empty());
}

TEST(DecodedInputs, BadStepsAndTangentScalesAreErrors)
{
    ngi::GeometryImage p, n;
    syntheticGeometryImage(65, 0.3f, p, n);
    for (const ngi::nn::DecodedInputOptions& bad :
         {ngi::nn::DecodedInputOptions{{0}, 0}, ngi::nn::DecodedInputOptions{{1, 4097}, 0},
          ngi::nn::DecodedInputOptions{{64}, 17}}) {
        EXPECT_THROW(ngi::nn::validateDecodedInputOptions(bad), ngi::Error);
        EXPECT_THROW(ngi::nn::makeTrainingImage("s", p, n, 4, bad), ngi::Error);
    }
    EXPECT_NO_THROW(ngi::nn::validateDecodedInputOptions({{1, 4096}, 16}));
}

}  // namespace
