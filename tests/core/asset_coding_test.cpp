// The pyramid-coded asset (formats 5 and 4, ngi/asset.h AssetCoding): what a reader gets is
// what applyAssetCoding gives, within half a step, idempotent, seam mates bitwise identical,
// older formats still written without the coder (or without the streaming layout), every
// corruption rejected cleanly.
#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/error.h"
#include "ngi/pyramid_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace {

ngi::Asset makeAsset(uint32_t resolution, uint32_t level)
{
    ngi::Asset a;
    a.sourceName = "analytic:coded";
    a.parameterization = "analytic";
    ngi::AssetChart& c = a.charts.emplace_back();
    c.fullResolution = resolution;
    c.storedLevel = level;
    const uint32_t n = c.storedSize();
    ngi::GeometryImage pos(n), nrm(n);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            // A cylinder: row 0 and row n-1 are the same points (the seam below).
            const float u = float(x) / float(n - 1), t = 6.2831853f * float(y) / float(n - 1);
            const float r = 0.3f + 0.05f * std::sin(7.0f * u);
            pos.at(x, y) = {u, 0.5f + r * std::cos(t), 0.5f + r * std::sin(t)};
            nrm.at(x, y) = glm::vec3(0.0f, std::cos(t), std::sin(t));
        }
    for (uint32_t x = 0; x < n; ++x) pos.at(x, n - 1) = pos.at(x, 0), nrm.at(x, n - 1) = nrm.at(x, 0);
    ngi::storeGeometryImage(c, pos, nrm);
    // The bottom row is the top row (perimeter [0, R] against [2R, 3R]).
    c.seams.matched = true;
    c.seams.coarsestWatertightLevel = 1;
    c.seams.segments = {{0, 2 * resolution, resolution}};
    a.coding.pyramid = true;
    a.coding.positionStep = 32;
    return a;
}

uint32_t version(const std::vector<uint8_t>& bytes)
{
    uint32_t v;
    std::memcpy(&v, bytes.data() + 8, 4);
    return v;
}

TEST(AssetCoding, ReaderGetsTheAppliedCodingWithinHalfAStep)
{
    const ngi::Asset input = makeAsset(256, 2);
    ngi::Asset applied = input;
    ngi::applyAssetCoding(applied);
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    EXPECT_EQ(version(bytes), 9u);
    EXPECT_EQ(version(ngi::serializeLegacyAsset(input)), 5u);
    const ngi::Asset read = ngi::parseAsset(bytes, "coded.ngi");
    EXPECT_TRUE(read.coding.pyramid);
    EXPECT_TRUE(read.coding.progressive);
    EXPECT_EQ(read.coding.positionStep, 32u);
    EXPECT_EQ(read.coding.normalBits, 0u);
    EXPECT_EQ(read.charts[0].positions, applied.charts[0].positions);
    EXPECT_EQ(read.charts[0].normals, applied.charts[0].normals);
    for (size_t i = 0; i < input.charts[0].positions.size(); ++i)
        ASSERT_LE(std::abs(int(read.charts[0].positions[i]) - int(input.charts[0].positions[i])), 16) << i;
    // Idempotent: the read asset writes the same bytes.
    EXPECT_EQ(ngi::serializeAsset(read), bytes);
    // Far smaller than the lossless format.
    ngi::Asset lossless = input;
    lossless.coding.pyramid = false;
    const std::vector<uint8_t> zlib = ngi::serializeAsset(lossless);
    EXPECT_EQ(version(zlib), 9u);
    EXPECT_EQ(version(ngi::serializeLegacyAsset(lossless)), 3u);
    EXPECT_LT(bytes.size() * 2, zlib.size());
}

TEST(AssetCoding, SeamMatesStayBitwiseIdentical)
{
    const ngi::Asset read = ngi::parseAsset(ngi::serializeAsset(makeAsset(256, 2)), "coded.ngi");
    const ngi::AssetChart& c = read.charts[0];
    const uint32_t n = c.storedSize();
    for (uint32_t x = 0; x < n; ++x)
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(c.positions[x * 3 + k], c.positions[(size_t(n - 1) * n + x) * 3 + k]) << x;
            EXPECT_EQ(c.normals[x * 3 + k], c.normals[(size_t(n - 1) * n + x) * 3 + k]) << x;
        }
}

TEST(AssetCoding, NormalResidualBitsBringNormalsCloser)
{
    ngi::Asset a = makeAsset(128, 1);
    a.coding.normalBits = 10;
    const ngi::Asset read = ngi::parseAsset(ngi::serializeAsset(a), "coded.ngi");
    EXPECT_EQ(read.coding.normalBits, 10u);
    double worst = 0.0;
    for (size_t i = 0; i < a.charts[0].normals.size(); ++i)
        worst = std::max(worst,
                         std::abs(double(read.charts[0].normals[i]) - double(a.charts[0].normals[i])) / 65535.0 * 2.0);
    EXPECT_LT(worst, 0.01);
}

TEST(AssetCoding, RejectsEveryTruncationAndSurvivesEveryBitFlip)
{
    ngi::Asset a = makeAsset(32, 1);
    a.coding.normalBits = 6;
    const std::vector<uint8_t> bytes = ngi::serializeAsset(a);
    for (size_t n = 0; n < bytes.size(); ++n)
        EXPECT_THROW(ngi::parseAsset(std::span(bytes).first(n), "cut.ngi"), ngi::Error) << n;
    for (size_t bit = 0; bit < bytes.size() * 8; ++bit) {
        std::vector<uint8_t> flipped = bytes;
        flipped[bit / 8] ^= uint8_t(1u << (bit % 8));
        try {
            const ngi::Asset b = ngi::parseAsset(flipped, "flip.ngi");
            EXPECT_EQ(b.charts.size(), 1u);
        } catch (const ngi::Error&) {}
    }
}

// Format 4 (one stream per chart, no level table) is still written on request and read; it
// decodes to the very samples format 5 does, in a few bytes less (the flushes and the table).
// So does format 9 with either layout.
TEST(AssetCoding, FormatFourStillReadsAndDecodesLikeFormatFive)
{
    for (uint32_t normalBits : {0u, 8u}) {
        ngi::Asset input = makeAsset(256, 2);
        input.coding.normalBits = normalBits;
        ngi::Asset four = input;
        four.coding.progressive = false;
        const std::vector<uint8_t> fourBytes = ngi::serializeLegacyAsset(four),
                                   fiveBytes = ngi::serializeLegacyAsset(input);
        EXPECT_EQ(version(fourBytes), 4u);
        EXPECT_EQ(version(fiveBytes), 5u);
        for (const ngi::Asset* layout : {&four, &input}) {
            const ngi::Asset nine = ngi::parseAsset(ngi::serializeAsset(*layout), "nine.ngi");
            EXPECT_EQ(nine.coding.progressive, layout->coding.progressive);
            EXPECT_EQ(nine.charts[0].positions, ngi::parseAsset(fiveBytes, "five.ngi").charts[0].positions);
        }
        const ngi::Asset a = ngi::parseAsset(fourBytes, "four.ngi"), b = ngi::parseAsset(fiveBytes, "five.ngi");
        EXPECT_FALSE(a.coding.progressive);
        EXPECT_EQ(a.coding.normalBits, normalBits);
        EXPECT_EQ(b.coding.normalBits, normalBits);
        EXPECT_EQ(a.charts[0].positions, b.charts[0].positions);
        EXPECT_EQ(a.charts[0].normals, b.charts[0].normals);
        // Rewriting a format-4 asset keeps format 4, byte for byte.
        EXPECT_EQ(ngi::serializeLegacyAsset(a), fourBytes);
        // 65^2 stored: 7 levels. Format 5 adds the flushes (~4 B a level) and the level table
        // (~40 B) and drops a prediction-only NORM chunk (its 32 B table entry and 3 B).
        const long extra = long(fiveBytes.size()) - long(fourBytes.size());
        EXPECT_GT(extra, normalBits ? 40 : 0) << normalBits;
        EXPECT_LT(extra, normalBits ? 120 : 80) << normalBits;
    }
}

// A graded asset (AssetCoding::positionStepGrade sqrt 2): the payload carries the graded steps,
// the reader reports the grade and what applyAssetCoding gives, and rewriting it writes the same
// bytes. Finer coarse levels cost bytes: more than uniform steps at the same finest step.
TEST(AssetCoding, GradedStepsRoundTripAndTheReaderReportsTheGrade)
{
    ngi::Asset input = makeAsset(256, 2);
    input.coding.positionStepGrade = ngi::kPyramidStepGrades[1];
    ngi::Asset applied = input;
    ngi::applyAssetCoding(applied);
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const ngi::Asset read = ngi::parseAsset(bytes, "graded.ngi");
    EXPECT_EQ(read.coding.positionStepGrade, ngi::kPyramidStepGrades[1]);
    EXPECT_EQ(read.coding.positionStep, 32u);
    EXPECT_EQ(read.charts[0].positions, applied.charts[0].positions);
    for (size_t i = 0; i < input.charts[0].positions.size(); ++i)
        ASSERT_LE(std::abs(int(read.charts[0].positions[i]) - int(input.charts[0].positions[i])), 16) << i;
    EXPECT_EQ(ngi::serializeAsset(read), bytes);
    ngi::Asset uniform = input;
    uniform.coding.positionStepGrade = 1.0;
    const std::vector<uint8_t> uniformBytes = ngi::serializeAsset(uniform);
    EXPECT_EQ(ngi::parseAsset(uniformBytes, "uniform.ngi").coding.positionStepGrade, 1.0);
    EXPECT_GT(bytes.size(), uniformBytes.size());
    // Hostile grades are refused by the writer.
    for (double bad : {0.5, 4.5, std::nan("")}) {
        ngi::Asset a = input;
        a.coding.positionStepGrade = bad;
        EXPECT_THROW(ngi::serializeAsset(a), ngi::Error) << bad;
    }
}

TEST(AssetCoding, WriterRejectsStepsBeyondTheCoder)
{
    ngi::Asset a = makeAsset(32, 1);
    a.coding.positionStep = 4097;
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error);
    a.coding.positionStep = 16;
    a.coding.normalBits = 17;
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error);
}

}  // namespace
