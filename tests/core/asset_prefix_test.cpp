// Streaming an asset (format 5, ngi/asset_prefix.h): every prefix of the file that ends on a
// level boundary decodes to the coarser nested level, bitwise; one that ends between two
// boundaries decodes to the boundary before it; the whole-file reader still rejects every
// prefix; the level table and every level are CRC-checked; several charts stream coarse
// to fine together; the incremental reader agrees with the one-shot one.
#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/asset_prefix.h"
#include "ngi/error.h"
#include "ngi/pyramid_codec.h"
#include "ngi/seam.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <bit>
#include <cmath>
#include <numeric>

namespace {

// A chart of a bumpy cylinder whose bottom row is its top row (a matched seam).
ngi::AssetChart cylinderChart(uint32_t resolution, uint32_t level, float phase, bool seam)
{
    ngi::AssetChart c;
    c.fullResolution = resolution;
    c.storedLevel = level;
    const uint32_t n = c.storedSize();
    ngi::GeometryImage pos(n), nrm(n);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const float u = float(x) / float(n - 1), t = 6.2831853f * float(y % (n - 1)) / float(n - 1);
            const float r = 0.3f + 0.05f * std::sin(7.0f * u + phase) + 0.02f * std::cos(5.0f * t);
            pos.at(x, y) = {u, 0.5f + r * std::cos(t), 0.5f + r * std::sin(t)};
            nrm.at(x, y) = glm::vec3(0.0f, std::cos(t), std::sin(t));
        }
    ngi::storeGeometryImage(c, pos, nrm);
    if (seam) {
        c.seams.matched = true;
        c.seams.coarsestWatertightLevel = 1;
        c.seams.segments = {{0, 2 * resolution, resolution}};
    }
    return c;
}

ngi::Asset makeAsset(std::vector<ngi::AssetChart> charts, uint32_t normalBits = 0)
{
    ngi::Asset a;
    a.sourceName = "analytic:stream";
    a.parameterization = "analytic";
    a.metadataJson = R"({"note":"prefix test"})";
    a.offset = {-1.0f, 0.0f, 2.0f};
    a.scale = {3.0f, 3.0f, 3.0f};
    a.charts = std::move(charts);
    a.coding.pyramid = true;
    a.coding.positionStep = 32;
    a.coding.normalBits = normalBits;
    return a;
}

std::vector<uint16_t> nested(const std::vector<uint16_t>& s, uint32_t size, uint32_t shift)
{
    const uint32_t n = ((size - 1) >> shift) + 1;
    std::vector<uint16_t> out;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) out.push_back(s[((size_t(y) << shift) * size + (size_t(x) << shift)) * 3 + c]);
    return out;
}

uint32_t levelsOf(const ngi::AssetChart& c) { return ngi::pyramidLevelCount(c.storedSize()); }

// The byte counts at which a level completes, from the incremental reader fed byte by byte.
std::vector<size_t> levelBoundaries(const std::vector<uint8_t>& bytes)
{
    ngi::ProgressiveAssetReader reader("stream.ngi");
    std::vector<size_t> out;
    uint32_t levels = 0;
    for (size_t n = 0; n < bytes.size(); ++n) {
        reader.append(std::span(bytes).subspan(n, 1));
        if (reader.levelsDecoded() > levels) {
            EXPECT_EQ(reader.levelsDecoded(), levels + 1) << "two levels completed by one byte at " << n + 1;
            levels = reader.levelsDecoded();
            out.push_back(n + 1);
        }
    }
    EXPECT_TRUE(reader.complete());
    return out;
}

// Checks a prefix asset against the whole file's decode: every chart at min(levels, its
// levels) levels, its positions the nested level of the full positions, bitwise.
void expectNestedPrefix(const ngi::Asset& full, const ngi::Asset& prefix, uint32_t levels)
{
    EXPECT_EQ(prefix.sourceName, full.sourceName);
    EXPECT_EQ(prefix.metadataJson, full.metadataJson);
    EXPECT_EQ(prefix.offset, full.offset);
    EXPECT_EQ(prefix.scale, full.scale);
    ASSERT_EQ(prefix.charts.size(), full.charts.size());
    for (size_t c = 0; c < full.charts.size(); ++c) {
        const ngi::AssetChart &f = full.charts[c], &p = prefix.charts[c];
        const uint32_t missing = levelsOf(f) - std::min(levels, levelsOf(f));
        EXPECT_EQ(p.fullResolution, f.fullResolution);
        EXPECT_EQ(p.storedLevel, f.storedLevel + missing) << "chart " << c << " at " << levels << " levels";
        EXPECT_EQ(p.positions, nested(f.positions, f.storedSize(), missing))
            << "chart " << c << " at " << levels << " levels";
        EXPECT_EQ(p.seams.matched, f.seams.matched);
        EXPECT_EQ(p.seams.segments.size(), f.seams.segments.size());
        ASSERT_EQ(p.normals.size(), p.positions.size());
    }
}

TEST(AssetPrefix, EveryBoundaryPrefixIsTheNestedLevelAndOthersTheBoundaryBefore)
{
    const ngi::Asset input = makeAsset({cylinderChart(64, 1, 0.0f, true)});  // 33^2 stored, 6 levels
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const ngi::Asset full = ngi::parseAsset(bytes, "stream.ngi");
    const std::vector<size_t> boundaries = levelBoundaries(bytes);
    ASSERT_EQ(boundaries.size(), 6u);
    EXPECT_EQ(boundaries.back(), bytes.size());  // no NORM: the finest level ends the file
    size_t next = 0;
    for (size_t n = 0; n <= bytes.size(); ++n) {
        while (next < boundaries.size() && boundaries[next] <= n) ++next;
        const auto cut = std::span(bytes).first(n);
        if (next == 0) {
            // Before the coarsest level: an error that says how far the prefix got.
            try {
                ngi::readAssetPrefix(cut, "stream.ngi");
                ADD_FAILURE() << "accepted " << n << " bytes";
            } catch (const ngi::Error& e) {
                EXPECT_EQ(std::string(e.what()).rfind("stream.ngi: ", 0), 0u) << e.what();
            }
            continue;
        }
        const ngi::AssetPrefix p = ngi::readAssetPrefix(cut, "stream.ngi");
        EXPECT_EQ(p.levelsDecoded, next) << n;
        EXPECT_EQ(p.levelCount, 6u);
        EXPECT_EQ(p.boundaryBytes, boundaries[next - 1]) << n;
        EXPECT_EQ(p.nextBoundaryBytes, next < boundaries.size() ? boundaries[next] : bytes.size()) << n;
        EXPECT_EQ(p.complete, n == bytes.size());
        if (n == boundaries[next - 1] || n == bytes.size()) expectNestedPrefix(full, p.asset, next);
        // The whole-file reader never accepts a prefix.
        if (n < bytes.size()) {
            EXPECT_THROW(ngi::parseAsset(cut, "stream.ngi"), ngi::Error) << n;
        }
    }
    // The whole file through the prefix reader is the whole asset.
    const ngi::AssetPrefix whole = ngi::readAssetPrefix(bytes, "stream.ngi");
    EXPECT_EQ(whole.asset.charts[0].positions, full.charts[0].positions);
    EXPECT_EQ(whole.asset.charts[0].normals, full.charts[0].normals);
    EXPECT_EQ(whole.asset.charts[0].storedLevel, full.charts[0].storedLevel);
}

TEST(AssetPrefix, SeamMatesStayIdenticalAndNormalsArePredictedFromThePrefix)
{
    const ngi::Asset input = makeAsset({cylinderChart(128, 1, 0.5f, true)}, 8);  // 65^2, a normal residual
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const ngi::Asset full = ngi::parseAsset(bytes, "stream.ngi");
    const std::vector<size_t> boundaries = levelBoundaries(bytes);
    ASSERT_EQ(boundaries.size(), 7u);
    EXPECT_LT(boundaries.back(), bytes.size());  // NORM follows the positions
    ngi::Asset predictionOnly = input;
    predictionOnly.coding.normalBits = 0;
    const ngi::Asset predictedFull = ngi::parseAsset(ngi::serializeAsset(predictionOnly), "p.ngi");
    double previousMean = 180.0;
    for (size_t l = 0; l < boundaries.size(); ++l) {
        const ngi::AssetPrefix p = ngi::readAssetPrefix(std::span(bytes).first(boundaries[l]), "stream.ngi");
        expectNestedPrefix(full, p.asset, uint32_t(l + 1));
        const ngi::AssetChart& c = p.asset.charts[0];
        const uint32_t n = c.storedSize();
        // The seam (row 0 = row n-1) holds at every level, positions and normals.
        for (uint32_t x = 0; x < n; ++x)
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(c.positions[x * 3 + k], c.positions[(size_t(n - 1) * n + x) * 3 + k]) << l << " " << x;
                if (n > 2) {
                    EXPECT_EQ(c.normals[x * 3 + k], c.normals[(size_t(n - 1) * n + x) * 3 + k]) << l << " " << x;
                }
            }
        // Normals: the prediction from the prefix's own positions (no residual in a prefix
        // that ends before NORM), the seam's second row copying its first, and in the mean
        // close to the prediction from the full positions at those samples (the coarser
        // grid's differences span more of the bumps).
        EXPECT_EQ(p.asset.coding.normalBits, 0u);
        std::vector<uint32_t> mates(size_t(n) * n);
        std::iota(mates.begin(), mates.end(), 0u);
        for (uint32_t x = 0; x < n; ++x) mates[size_t(n - 1) * n + x] = x;
        if (n > 2) {
            EXPECT_TRUE(c.normals == ngi::normalsFromPositions(c.positions, n, false, mates) ||
                        c.normals == ngi::normalsFromPositions(c.positions, n, true, mates))
                << "level " << l;
        }
        if (n >= 17) {
            const auto fullNormals =
                nested(predictedFull.charts[0].normals, full.charts[0].storedSize(), 6 - uint32_t(l));
            double sum = 0.0;
            for (size_t i = 0; i < c.normals.size(); i += 3) {
                glm::dvec3 a, b;
                for (int k = 0; k < 3; ++k)
                    a[k] = c.normals[i + k] / 65535.0 * 2 - 1, b[k] = fullNormals[i + k] / 65535.0 * 2 - 1;
                sum += std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
            }
            const double meanDegrees = sum / double(c.normals.size() / 3) * 180.0 / M_PI;
            // Measured 7.5, 1.8, 0 degrees at 17^2, 33^2, 65^2: closer at every finer level.
            EXPECT_LT(meanDegrees, 10.0) << "level " << l;
            EXPECT_LT(meanDegrees, previousMean + 1e-9) << "level " << l;
            previousMean = meanDegrees;
        }
    }
    // With NORM in, the residual's normals: the whole asset.
    const ngi::AssetPrefix whole = ngi::readAssetPrefix(bytes, "stream.ngi");
    EXPECT_TRUE(whole.complete);
    EXPECT_EQ(whole.asset.coding.normalBits, 8u);
    EXPECT_EQ(whole.asset.charts[0].normals, full.charts[0].normals);
    // All of POSI but part of NORM: the finest positions, predicted normals.
    const ngi::AssetPrefix finest = ngi::readAssetPrefix(std::span(bytes).first(bytes.size() - 1), "stream.ngi");
    EXPECT_FALSE(finest.complete);
    EXPECT_EQ(finest.levelsDecoded, 7u);
    EXPECT_EQ(finest.asset.charts[0].positions, full.charts[0].positions);
    EXPECT_EQ(finest.asset.charts[0].normals, predictedFull.charts[0].normals);
}

// Several charts: round r holds level r of every chart that has more than r levels, so the
// charts grow together, coarsest first (the same samples per side each round).
TEST(AssetPrefix, SeveralChartsStreamCoarseToFineTogether)
{
    // 65^2 (7 levels), 17^2 (5 levels, half the resolution), 9^2 (4 levels).
    const ngi::Asset input = makeAsset(
        {cylinderChart(128, 1, 0.0f, true), cylinderChart(64, 2, 1.0f, false), cylinderChart(32, 2, 2.0f, true)});
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const ngi::Asset full = ngi::parseAsset(bytes, "three.ngi");
    const std::vector<size_t> boundaries = levelBoundaries(bytes);
    ASSERT_EQ(boundaries.size(), 7u);
    for (size_t l = 0; l < boundaries.size(); ++l) {
        const ngi::AssetPrefix p = ngi::readAssetPrefix(std::span(bytes).first(boundaries[l]), "three.ngi");
        EXPECT_EQ(p.levelsDecoded, l + 1);
        expectNestedPrefix(full, p.asset, uint32_t(l + 1));
        // Every chart not yet complete sits at the same asset level (same sample density).
        for (size_t c = 0; c < p.asset.charts.size(); ++c) {
            const ngi::AssetChart& chart = p.asset.charts[c];
            if (levelsOf(full.charts[c]) <= l) continue;
            const int assetLevel = int(chart.storedLevel) + int(std::countr_zero(p.asset.fullResolution())) -
                int(std::countr_zero(chart.fullResolution));
            EXPECT_EQ(assetLevel, int(std::countr_zero(p.asset.fullResolution())) - int(l)) << "chart " << c;
        }
        // A prefix asset is itself a valid asset: it writes and reads back.
        EXPECT_NO_THROW(ngi::parseAsset(ngi::serializeAsset(p.asset), "rewritten.ngi"));
    }
}

// Single-bit flips in the prefix up to the second level boundary: a flip in the level table
// or in a level is caught by its CRC32; in the chunk table or a description chunk by theirs;
// only alignment padding is outside every check (then the same asset decodes).
TEST(AssetPrefix, EveryBitFlipInAPrefixIsRejectedOrHarmless)
{
    const ngi::Asset input = makeAsset({cylinderChart(16, 0, 0.0f, true)});  // 17^2
    const std::vector<uint8_t> bytes = ngi::serializeAsset(input);
    const std::vector<size_t> boundaries = levelBoundaries(bytes);
    ASSERT_GE(boundaries.size(), 2u);
    const std::vector<uint8_t> prefix(bytes.begin(), bytes.begin() + ptrdiff_t(boundaries[1]));
    const ngi::AssetPrefix clean = ngi::readAssetPrefix(prefix, "flip.ngi");
    // The POSI chunk starts where the first level's level table does.
    uint64_t posiOffset = 0;
    for (const ngi::AssetChunkSize& chunk : ngi::assetChunkSizes(bytes, "flip.ngi"))
        if (chunk.name == "POSI") posiOffset = chunk.offset;
    ASSERT_GT(posiOffset, 0u);
    size_t harmless = 0;
    for (size_t bit = 0; bit < prefix.size() * 8; ++bit) {
        std::vector<uint8_t> flipped = prefix;
        flipped[bit / 8] ^= uint8_t(1u << (bit % 8));
        try {
            const ngi::AssetPrefix p = ngi::readAssetPrefix(flipped, "flip.ngi");
            EXPECT_LT(bit / 8, posiOffset) << "a flip in the positions at byte " << bit / 8 << " was accepted";
            EXPECT_EQ(p.levelsDecoded, clean.levelsDecoded);
            EXPECT_EQ(p.asset.charts[0].positions, clean.asset.charts[0].positions);
            EXPECT_EQ(p.asset.metadataJson, clean.asset.metadataJson);
            ++harmless;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("flip.ngi: ", 0), 0u) << e.what();
        }
    }
    EXPECT_LT(harmless, 8u * 8u * 6u);  // at most the padding between six chunks
}

TEST(AssetPrefix, IncrementalReaderAgreesWithTheOneShotReader)
{
    const ngi::Asset input = makeAsset({cylinderChart(128, 1, 0.3f, true), cylinderChart(64, 1, 1.0f, true)}, 6);
    ngi::Asset withWeights = input;
    withWeights.weights = {9, 8, 7, 6, 5};
    const std::vector<uint8_t> bytes = ngi::serializeAsset(withWeights);
    ngi::ProgressiveAssetReader reader("inc.ngi");
    EXPECT_THROW(reader.current(), ngi::Error);
    uint32_t seen = 0;
    for (size_t at = 0; at < bytes.size(); at += 97) {
        const auto piece = std::span(bytes).subspan(at, std::min<size_t>(97, bytes.size() - at));
        const bool refined = reader.append(piece);
        EXPECT_EQ(refined, reader.levelsDecoded() > seen || (reader.complete() && at + piece.size() == bytes.size()));
        EXPECT_GE(reader.bytesForNextLevel(),
                  reader.bytesReceived() < bytes.size() ? reader.bytesReceived() + 1 : bytes.size());
        if (reader.levelsDecoded() == 0) continue;
        seen = reader.levelsDecoded();
        const ngi::AssetPrefix a = reader.current(),
                               b = ngi::readAssetPrefix(std::span(bytes).first(at + piece.size()), "inc.ngi");
        EXPECT_EQ(a.levelsDecoded, b.levelsDecoded);
        for (size_t c = 0; c < a.asset.charts.size(); ++c) {
            EXPECT_EQ(a.asset.charts[c].positions, b.asset.charts[c].positions);
            EXPECT_EQ(a.asset.charts[c].normals, b.asset.charts[c].normals);
        }
        EXPECT_EQ(a.asset.weights.empty(), !a.complete);  // WGHT is the last chunk
    }
    ASSERT_TRUE(reader.complete());
    const ngi::Asset full = ngi::parseAsset(bytes, "inc.ngi"), streamed = reader.current().asset;
    for (size_t c = 0; c < full.charts.size(); ++c) {
        EXPECT_EQ(streamed.charts[c].positions, full.charts[c].positions);
        EXPECT_EQ(streamed.charts[c].normals, full.charts[c].normals);
    }
    EXPECT_EQ(streamed.weights, full.weights);
    EXPECT_EQ(ngi::serializeAsset(streamed), bytes);
    // Bytes past the file's end are ignored.
    EXPECT_FALSE(reader.append(std::vector<uint8_t>(5, 0)));
    EXPECT_EQ(reader.bytesReceived(), bytes.size());
}

TEST(AssetPrefix, OlderFormatsDoNotStreamButReadWhole)
{
    ngi::Asset four = makeAsset({cylinderChart(64, 1, 0.0f, true)});
    four.coding.progressive = false;
    const std::vector<uint8_t> bytes = ngi::serializeLegacyAsset(four);
    const ngi::AssetPrefix whole = ngi::readAssetPrefix(bytes, "four.ngi");
    EXPECT_TRUE(whole.complete);
    EXPECT_EQ(whole.levelsDecoded, 6u);
    EXPECT_EQ(whole.asset.charts[0].positions, ngi::parseAsset(bytes, "four.ngi").charts[0].positions);
    try {
        ngi::readAssetPrefix(std::span(bytes).first(bytes.size() - 10), "four.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("format 4 assets do not stream"), std::string::npos) << e.what();
    }
    // Format 9 with format 4's layout (one stream per chart) does not stream either.
    const std::vector<uint8_t> nine = ngi::serializeAsset(four);
    try {
        ngi::readAssetPrefix(std::span(nine).first(nine.size() - 10), "nine.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("format 9 assets laid out as format 4 do not stream"), std::string::npos)
            << e.what();
    }
    // Not an asset at all: said at once, from the first bytes.
    const std::vector<uint8_t> text = {'p', 'l', 'y', '\n'};
    ngi::ProgressiveAssetReader reader("text.ngi");
    EXPECT_THROW(reader.append(text), ngi::Error);
    EXPECT_THROW(reader.append(text), ngi::Error);  // and again after
}

}  // namespace
