// The nested-pyramid coder (ngi/pyramid_codec.h): round trip within step / 2, lossless at
// step 1, hostile payloads rejected or decoded within bounds, predicted normals.
#include "ngi/error.h"
#include "ngi/pyramid_codec.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdlib>
#include <random>

namespace {

// A bumpy sphere patch on a size^2 grid, normalized to [0, 1], with a little noise so the
// coder sees non-trivial residuals; and its analytic normals in the asset's u16 encoding.
struct Level {
    uint32_t size;
    std::vector<uint16_t> positions, normals;
};

Level makeLevel(uint32_t size, uint32_t seed = 1)
{
    Level level{size, {}, {}};
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> noise(-3, 3);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const double u = double(x) / (size - 1) * 2.4 - 1.2, v = double(y) / (size - 1) * 2.4 - 1.2;
            const double r = 1.0 + 0.05 * std::sin(5 * u) * std::cos(4 * v);
            const glm::dvec3 d(std::cos(v) * std::sin(u), std::sin(v), std::cos(v) * std::cos(u));
            const glm::dvec3 p = d * r;
            for (int c = 0; c < 3; ++c)
                level.positions.push_back(
                    uint16_t(std::clamp<long>(std::lround((p[c] * 0.5 + 0.5) * 65535) + noise(rng), 0, 65535)));
            for (int c = 0; c < 3; ++c) level.normals.push_back(uint16_t(std::lround((d[c] * 0.5 + 0.5) * 65535)));
        }
    return level;
}

int maxAbsError(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b)
{
    int e = 0;
    for (size_t i = 0; i < a.size(); ++i) e = std::max(e, std::abs(int(a[i]) - int(b[i])));
    return e;
}

TEST(PyramidCodec, LevelCounts)
{
    EXPECT_EQ(ngi::pyramidLevelCount(2), 1u);
    EXPECT_EQ(ngi::pyramidLevelCount(3), 2u);
    EXPECT_EQ(ngi::pyramidLevelCount(129), 8u);
    EXPECT_THROW(ngi::pyramidLevelCount(4), ngi::Error);
    EXPECT_THROW(ngi::pyramidLevelCount(1), ngi::Error);
    EXPECT_THROW(ngi::pyramidLevelCount(8193), ngi::Error);
}

TEST(PyramidCodec, LosslessAtStepOne)
{
    for (uint32_t size : {2u, 3u, 5u, 33u, 65u}) {
        const Level level = makeLevel(size);
        const auto payload = ngi::encodePyramidPositions(level.positions, size, {.step = 1});
        EXPECT_EQ(ngi::decodePyramidPositions(payload, size, "test"), level.positions) << size;
    }
}

TEST(PyramidCodec, RoundTripWithinHalfAStepAndSmallerAtCoarserSteps)
{
    const Level level = makeLevel(65);
    size_t previous = SIZE_MAX;
    for (uint32_t k = 0; (1u << k) <= ngi::kMaxPyramidStep; k += 2) {
        const auto payload = ngi::encodePyramidPositions(level.positions, 65, {.step = 1u << k});
        const auto decoded = ngi::decodePyramidPositions(payload, 65, "test");
        EXPECT_LE(maxAbsError(decoded, level.positions), int(1u << k) / 2) << "step 2^" << k;
        EXPECT_LT(payload.size(), previous) << "step 2^" << k;
        previous = payload.size();
    }
    // A per-level step: the bound is the largest level's half step.
    ngi::PyramidCodecOptions options;
    options.levelSteps = {1, 2, 4, 8, 16, 32, 64};
    const auto decoded =
        ngi::decodePyramidPositions(ngi::encodePyramidPositions(level.positions, 65, options), 65, "t");
    EXPECT_LE(maxAbsError(decoded, level.positions), 32);
    // Any integer step, odd ones included.
    for (uint32_t q : {3u, 5u, 45u, 91u, 4096u}) {
        const auto d =
            ngi::decodePyramidPositions(ngi::encodePyramidPositions(level.positions, 65, {.step = q}), 65, "t");
        EXPECT_LE(maxAbsError(d, level.positions), int(q / 2)) << q;
    }
    EXPECT_THROW(ngi::encodePyramidPositions(level.positions, 65, {.step = 0}), ngi::Error);
}

// Graded steps (gradedLevelSteps): each coarser level sqrt 2 finer, rounded, at least 1;
// stepGradeOf finds the grade back from the steps; a graded stream decodes every level within
// its own half step, and costs more bytes than the uniform one at its finest step but less than
// coding every level at the graded coarse step.
TEST(PyramidCodec, GradedStepsAreFinerTowardsTheCoarseLevels)
{
    const double root2 = ngi::kPyramidStepGrades[1];
    EXPECT_EQ(ngi::gradedLevelSteps(64, 7, root2), (std::vector<uint16_t>{8, 11, 16, 23, 32, 45, 64}));
    EXPECT_EQ(ngi::gradedLevelSteps(1, 4, root2), (std::vector<uint16_t>{1, 1, 1, 1}));
    EXPECT_EQ(ngi::gradedLevelSteps(4096, 3, 2.0), (std::vector<uint16_t>{1024, 2048, 4096}));
    EXPECT_EQ(ngi::gradedLevelSteps(64, 3, 1.0), (std::vector<uint16_t>{64, 64, 64}));
    EXPECT_EQ(ngi::stepGradeOf(ngi::gradedLevelSteps(149, 9, root2)), root2);
    EXPECT_EQ(ngi::stepGradeOf(ngi::gradedLevelSteps(149, 9, 1.0)), 1.0);
    const std::vector<uint16_t> foreign = {5, 64, 64};
    EXPECT_EQ(ngi::stepGradeOf(foreign), 0.0);
    EXPECT_THROW(ngi::gradedLevelSteps(64, 3, 0.5), ngi::Error);
    EXPECT_THROW(ngi::gradedLevelSteps(64, 3, std::nan("")), ngi::Error);
    EXPECT_THROW(ngi::gradedLevelSteps(0, 3, root2), ngi::Error);

    const Level level = makeLevel(65);
    ngi::PyramidCodecOptions graded;
    graded.levelSteps = ngi::gradedLevelSteps(64, 7, root2);
    const auto payload = ngi::encodePyramidPositions(level.positions, 65, graded);
    EXPECT_EQ(ngi::pyramidPayloadInfo(payload).steps, graded.levelSteps);
    EXPECT_EQ(ngi::pyramidPayloadInfo(payload).finestStep, 64u);
    const auto decoded = ngi::decodePyramidPositions(payload, 65, "graded");
    // Level l's new samples sit at odd multiples of 2^(6 - l) (level 0: the corners).
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const uint32_t spacing = std::min<uint32_t>(64, std::min(x ? x & (~x + 1) : 64, y ? y & (~y + 1) : 64));
            uint32_t l = 6;
            for (uint32_t s = spacing; s > 1; s >>= 1) --l;
            const size_t i = (size_t(y) * 65 + x) * 3;
            for (int c = 0; c < 3; ++c)
                ASSERT_LE(std::abs(int(decoded[i + c]) - int(level.positions[i + c])), graded.levelSteps[l] / 2)
                    << x << "," << y << " level " << l;
        }
    const size_t uniform = ngi::encodePyramidPositions(level.positions, 65, {.step = 64}).size();
    EXPECT_GT(payload.size(), uniform);
}

TEST(PyramidCodec, SmoothSurfaceCostsFewBitsPerSample)
{
    // The smooth part of the test surface at step 2^6 (2^-10 of the box): a few bits per sample.
    const Level level = makeLevel(129);
    const auto payload = ngi::encodePyramidPositions(level.positions, 129, {.step = 64});
    EXPECT_LT(payload.size() * 8.0 / (129.0 * 129.0), 4.0);
}

TEST(PyramidCodec, RejectsBadArguments)
{
    const Level level = makeLevel(9);
    EXPECT_THROW(ngi::encodePyramidPositions(level.positions, 17, {}), ngi::Error);
    EXPECT_THROW(ngi::encodePyramidPositions(level.positions, 9, {.step = 4097}), ngi::Error);
    ngi::PyramidCodecOptions wrongCount;
    wrongCount.levelSteps = {1, 2};
    EXPECT_THROW(ngi::encodePyramidPositions(level.positions, 9, wrongCount), ngi::Error);
    const auto payload = ngi::encodePyramidPositions(level.positions, 9, {.step = 4});
    EXPECT_THROW(ngi::decodePyramidPositions(payload, 17, "test"), ngi::Error);  // level count differs
    EXPECT_THROW(ngi::decodePyramidPositions(payload, 10, "test"), ngi::Error);
}

TEST(PyramidCodec, EveryTruncationIsRejected)
{
    const Level level = makeLevel(17);
    const auto payload = ngi::encodePyramidPositions(level.positions, 17, {.step = 8});
    for (size_t n = 0; n < payload.size(); ++n) {
        const std::vector<uint8_t> prefix(payload.begin(), payload.begin() + n);
        EXPECT_THROW(ngi::decodePyramidPositions(prefix, 17, "test"), ngi::Error) << n << " of " << payload.size();
    }
    std::vector<uint8_t> longer = payload;
    longer.push_back(0);
    EXPECT_THROW(ngi::decodePyramidPositions(longer, 17, "test"), ngi::Error);
}

TEST(PyramidCodec, EveryBitFlipIsRejectedOrDecodesWithinRange)
{
    const Level level = makeLevel(17);
    const auto payload = ngi::encodePyramidPositions(level.positions, 17, {.step = 8});
    size_t rejected = 0;
    for (size_t bit = 0; bit < payload.size() * 8; ++bit) {
        std::vector<uint8_t> flipped = payload;
        flipped[bit / 8] ^= uint8_t(1u << (bit % 8));
        try {
            const auto decoded = ngi::decodePyramidPositions(flipped, 17, "test");
            EXPECT_EQ(decoded.size(), level.positions.size());  // u16: every value is in range
        } catch (const ngi::Error& e) {
            EXPECT_NE(std::string(e.what()).find("test: "), std::string::npos);
            ++rejected;
        }
    }
    EXPECT_GT(rejected, 0u);
}

TEST(PyramidCodec, RandomBytesNeverCrash)
{
    std::mt19937 rng(7);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<uint8_t> bytes(size_t(rng() % 64));
        for (uint8_t& b : bytes) b = uint8_t(rng());
        if (bytes.size() >= 2 && trial % 2) bytes[0] = 1, bytes[1] = 6;  // past the header
        if (bytes.size() >= 8 && trial % 2)
            for (int i = 2; i < 8; ++i) bytes[size_t(i)] %= 13;
        try {
            EXPECT_EQ(ngi::decodePyramidPositions(bytes, 33, "test").size(), 33u * 33u * 3u);
        } catch (const ngi::Error&) {}
    }
}

double maxAngleDegrees(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b)
{
    double worst = 0.0;
    for (size_t i = 0; i < a.size(); i += 3) {
        glm::dvec3 u, v;
        for (int c = 0; c < 3; ++c) u[c] = a[i + c] / 65535.0 * 2 - 1, v[c] = b[i + c] / 65535.0 * 2 - 1;
        worst = std::max(worst, std::acos(std::clamp(glm::dot(glm::normalize(u), glm::normalize(v)), -1.0, 1.0)));
    }
    return worst * 180.0 / M_PI;
}

TEST(PredictedNormals, PredictionAloneFollowsTheSurfaceAndResidualBitsRefineIt)
{
    const Level level = makeLevel(33);
    const auto positions =
        ngi::decodePyramidPositions(ngi::encodePyramidPositions(level.positions, 33, {.step = 4}), 33, "t");
    const auto predictionOnly = ngi::encodePredictedNormals(positions, level.normals, 33, 0);
    EXPECT_EQ(predictionOnly.size(), 3u);
    const auto predicted = ngi::decodePredictedNormals(predictionOnly, positions, 33, "t");
    EXPECT_LT(maxAngleDegrees(predicted, level.normals), 20.0);  // the bumps tilt the analytic sphere normal
    const auto payload = ngi::encodePredictedNormals(positions, level.normals, 33, 10);
    const auto refined = ngi::decodePredictedNormals(payload, positions, 33, "t");
    EXPECT_LT(maxAngleDegrees(refined, level.normals), 0.3);
    for (size_t n = 0; n < payload.size(); ++n)
        EXPECT_THROW(ngi::decodePredictedNormals(std::span(payload).first(n), positions, 33, "t"), ngi::Error) << n;
}

}  // namespace

namespace {

TEST(PyramidCodec, SeamMatesDecodeBitwiseIdentical)
{
    // Mates: the left and right columns are one cut (sample (0, y) is (n-1, n-1-y)), as a
    // folded seam; the classes' ids are the left column's indices.
    const uint32_t n = 33;
    Level level = makeLevel(n);
    std::vector<uint32_t> mates(n * n);
    for (uint32_t i = 0; i < n * n; ++i) mates[i] = i;
    for (uint32_t y = 0; y < n; ++y) mates[(n - 1 - y) * n + (n - 1)] = y * n;
    ngi::PyramidCodecOptions options{.step = 32};
    options.mates = mates;
    const auto payload = ngi::encodePyramidPositions(level.positions, n, options);
    const auto decoded = ngi::decodePyramidPositions(payload, n, "t", mates);
    for (uint32_t y = 0; y < n; ++y)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(decoded[(y * n) * 3 + c], decoded[((n - 1 - y) * n + n - 1) * 3 + c]) << y;
    // The test's mates are not one point: each pair decodes to the input of the side coded
    // first, within the bound; the interior keeps its own bound.
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 1; x + 1 < n; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_LE(std::abs(int(decoded[(y * n + x) * 3 + c]) - int(level.positions[(y * n + x) * 3 + c])), 16);
    for (uint32_t y = 0; y < n; ++y)
        for (int c = 0; c < 3; ++c) {
            const int v = decoded[(y * n) * 3 + c];
            EXPECT_LE(std::min(std::abs(v - int(level.positions[(y * n) * 3 + c])),
                               std::abs(v - int(level.positions[((n - 1 - y) * n + n - 1) * 3 + c]))),
                      16);
        }
    const auto normals = ngi::decodePredictedNormals(ngi::encodePredictedNormals(decoded, level.normals, n, 8, mates),
                                                     decoded, n, "t", mates);
    for (uint32_t y = 0; y < n; ++y)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(normals[(y * n) * 3 + c], normals[((n - 1 - y) * n + n - 1) * 3 + c]);
    std::vector<uint32_t> bad = mates;
    bad[5] = n * n;
    EXPECT_THROW(ngi::decodePyramidPositions(payload, n, "t", bad), ngi::Error);
}

}  // namespace

namespace {

TEST(PyramidCodec, NormalTangentFrameBoundsTheNormalErrorAndSavesBytes)
{
    const Level level = makeLevel(65);
    const auto xyz = ngi::encodePyramidPositions(level.positions, 65, {.step = 32});
    for (uint32_t t : {1u, 4u}) {
        const auto payload = ngi::encodePyramidPositions(level.positions, 65, {.step = 32, .tangentScale = t});
        const auto decoded = ngi::decodePyramidPositions(payload, 65, "t");
        // Per sample the error is within half a step along the frame's normal and t half steps
        // along its tangents (plus the fixed-point frame's rounding): bound it per axis.
        EXPECT_LE(maxAbsError(decoded, level.positions), int(std::ceil(16 * std::sqrt(1.0 + 2.0 * t * t))) + 2) << t;
        if (t == 4) {
            EXPECT_LT(payload.size(), xyz.size());
        }
        for (size_t n = 0; n < payload.size(); n += 7)
            EXPECT_THROW(ngi::decodePyramidPositions(std::span(payload).first(n), 65, "t"), ngi::Error);
    }
    EXPECT_THROW(ngi::encodePyramidPositions(level.positions, 65, {.step = 32, .tangentScale = 17}), ngi::Error);
}

}  // namespace
