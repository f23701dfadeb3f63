// The .ngi asset: lossless round trip, atomic writes, and rejection of every corrupt file
// (exhaustive truncation and single-bit flips, in the manner of meshoptimizer's tests).
#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/asset_prefix.h"
#include "ngi/error.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace {

ngi::AssetChart makeChart(uint32_t resolution, uint32_t level, float phase = 0.0f)
{
    ngi::AssetChart a;
    a.fullResolution = resolution;
    a.storedLevel = level;
    ngi::GeometryImage pos(a.storedSize()), nrm(a.storedSize());
    for (uint32_t y = 0; y < pos.size; ++y)
        for (uint32_t x = 0; x < pos.size; ++x) {
            const float u = float(x) / float(pos.size - 1), v = float(y) / float(pos.size - 1);
            pos.at(x, y) = {u, v, 0.5f + 0.25f * std::sin(6.0f * u + phase) * std::cos(5.0f * v)};
            nrm.at(x, y) = glm::vec3(0.6f, 0.0f, 0.8f);
        }
    ngi::storeGeometryImage(a, pos, nrm);
    return a;
}

ngi::Asset makeAsset(uint32_t resolution, uint32_t level)
{
    ngi::Asset a;
    a.sourceName = "analytic:test";
    a.sourceHash = 1234;
    a.offset = {-1.0f, -2.0f, 0.5f};
    a.scale = {2.0f, 2.0f, 2.0f};
    a.parameterization = "analytic";
    a.metadataJson = R"({"note":"test"})";
    a.charts.push_back(makeChart(resolution, level));
    // A cylinder's seam: the bottom row is the top row (perimeter [0, R] against [2R, 3R]).
    a.charts[0].seams.matched = true;
    a.charts[0].seams.coarsestWatertightLevel = 1;
    a.charts[0].seams.segments = {{0, 2 * resolution, resolution}};
    return a;
}

// A format-version-1 file (one chart, its resolution in HEAD, raw samples), written by
// hand as the version-1 writer did.
std::vector<uint8_t> versionOneFile(const ngi::Asset& a)
{
    const ngi::AssetChart& c = a.charts.at(0);
    auto put = [](std::vector<uint8_t>& out, auto v) {
        const size_t at = out.size();
        out.resize(at + sizeof(v));
        std::memcpy(out.data() + at, &v, sizeof(v));
    };
    auto putString = [&](std::vector<uint8_t>& out, const std::string& s) {
        put(out, uint32_t(s.size()));
        out.insert(out.end(), s.begin(), s.end());
    };
    std::vector<uint8_t> head;
    put(head, c.fullResolution), put(head, c.storedLevel), put(head, c.storedSize());
    for (int i = 0; i < 3; ++i) put(head, a.offset[i]);
    for (int i = 0; i < 3; ++i) put(head, a.scale[i]);
    put(head, a.sourceHash), put(head, a.networkHash);
    putString(head, a.sourceName), putString(head, a.parameterization), putString(head, a.networkId);
    std::vector<uint8_t> meta(a.metadataJson.begin(), a.metadataJson.end());
    auto raw = [](const std::vector<uint16_t>& v) {
        std::vector<uint8_t> b(v.size() * 2);
        std::memcpy(b.data(), v.data(), b.size());
        return b;
    };
    const std::vector<std::pair<const char*, std::vector<uint8_t>>> chunks = {
        {"HEAD", head}, {"META", meta}, {"POSI", raw(c.positions)}, {"NORM", raw(c.normals)}};
    std::vector<uint8_t> table, payload;
    size_t offset = 24 + chunks.size() * 32;
    for (const auto& [code, bytes] : chunks) {
        offset = (offset + 7) & ~size_t(7);
        uint32_t fourcc;
        std::memcpy(&fourcc, code, 4);
        put(table, fourcc), put(table, uint32_t(0)), put(table, uint64_t(offset)), put(table, uint64_t(bytes.size()));
        put(table, uint32_t(crc32(0L, bytes.data(), uInt(bytes.size())))), put(table, uint32_t(0));
        offset += bytes.size();
    }
    std::vector<uint8_t> out = {0x89, 'N', 'G', 'I', '\r', '\n', 0x1a, '\n'};
    put(out, uint32_t(1)), put(out, uint32_t(chunks.size()));
    put(out, uint32_t(crc32(0L, table.data(), uInt(table.size())))), put(out, uint32_t(0));
    out.insert(out.end(), table.begin(), table.end());
    for (const auto& chunk : chunks) {
        out.resize((out.size() + 7) & ~size_t(7), 0);
        out.insert(out.end(), chunk.second.begin(), chunk.second.end());
    }
    return out;
}

void expectSameAsset(const ngi::Asset& a, const ngi::Asset& b)
{
    EXPECT_EQ(a.sourceName, b.sourceName);
    EXPECT_EQ(a.sourceHash, b.sourceHash);
    EXPECT_EQ(a.offset, b.offset);
    EXPECT_EQ(a.scale, b.scale);
    EXPECT_EQ(a.parameterization, b.parameterization);
    EXPECT_EQ(a.networkId, b.networkId);
    EXPECT_EQ(a.metadataJson, b.metadataJson);
    ASSERT_EQ(a.charts.size(), b.charts.size());
    for (size_t c = 0; c < a.charts.size(); ++c) {
        EXPECT_EQ(a.charts[c].fullResolution, b.charts[c].fullResolution);
        EXPECT_EQ(a.charts[c].storedLevel, b.charts[c].storedLevel);
        EXPECT_EQ(a.charts[c].positions, b.charts[c].positions);
        EXPECT_EQ(a.charts[c].normals, b.charts[c].normals);
        EXPECT_EQ(a.charts[c].seams.matched, b.charts[c].seams.matched);
        EXPECT_EQ(a.charts[c].seams.coarsestWatertightLevel, b.charts[c].seams.coarsestWatertightLevel);
        ASSERT_EQ(a.charts[c].seams.segments.size(), b.charts[c].seams.segments.size());
        for (size_t k = 0; k < a.charts[c].seams.segments.size(); ++k) {
            EXPECT_EQ(a.charts[c].seams.segments[k].a, b.charts[c].seams.segments[k].a);
            EXPECT_EQ(a.charts[c].seams.segments[k].b, b.charts[c].seams.segments[k].b);
            EXPECT_EQ(a.charts[c].seams.segments[k].length, b.charts[c].seams.segments[k].length);
        }
    }
    EXPECT_EQ(a.weights, b.weights);
}

TEST(Asset, RoundTripIsLossless)
{
    ngi::Asset a = makeAsset(64, 3);
    a.weights = {1, 2, 3, 4, 5};
    a.networkId = "sr-x8";
    a.networkHash = 99;
    const auto bytes = ngi::serializeAsset(a);
    const ngi::Asset b = ngi::parseAsset(bytes, "mem.ngi");
    expectSameAsset(a, b);
    EXPECT_EQ(ngi::serializeAsset(b), bytes);
}

TEST(Asset, QuantizationErrorIsHalfAStep)
{
    ngi::Asset a = makeAsset(32, 2);
    const ngi::GeometryImage p = ngi::storedPositions(a.charts[0]);
    for (uint32_t y = 0; y < p.size; ++y)
        for (uint32_t x = 0; x < p.size; ++x) {
            const float u = float(x) / float(p.size - 1);
            EXPECT_NEAR(p.at(x, y).x, u, 0.5f / 65535.0f + 1e-7f);
        }
    const ngi::GeometryImage n = ngi::storedNormals(a.charts[0]);
    EXPECT_NEAR(n.at(3, 4).x, 0.6f, 1e-4f);
    EXPECT_NEAR(n.at(3, 4).z, 0.8f, 1e-4f);
}

TEST(Asset, CompressesSmoothImages)
{
    const ngi::Asset a = makeAsset(256, 1);  // 129^2 stored samples
    const size_t raw = a.charts[0].positions.size() * 2 + a.charts[0].normals.size() * 2;
    EXPECT_LT(ngi::serializeAsset(a).size(), raw / 2);
}

TEST(Asset, RejectsEveryTruncation)
{
    const auto bytes = ngi::serializeAsset(makeAsset(16, 1));
    for (size_t n = 0; n < bytes.size(); ++n) {
        std::span<const uint8_t> cut(bytes.data(), n);
        EXPECT_THROW(ngi::parseAsset(cut, "cut.ngi"), ngi::Error) << "accepted a file cut at " << n;
    }
}

TEST(Asset, RejectsOrIgnoresEverySingleBitFlip)
{
    const ngi::Asset original = makeAsset(16, 1);
    const auto bytes = ngi::serializeAsset(original);
    size_t rejected = 0, total = 0;
    for (size_t i = 0; i < bytes.size(); ++i)
        for (int bit = 0; bit < 8; ++bit) {
            auto flipped = bytes;
            flipped[i] ^= uint8_t(1u << bit);
            ++total;
            try {
                const ngi::Asset b = ngi::parseAsset(flipped, "flip.ngi");
                // Only alignment padding is outside every check; the content must be intact.
                expectSameAsset(original, b);
            } catch (const ngi::Error& e) {
                ++rejected;
                EXPECT_NE(std::string(e.what()).find("flip.ngi: "), std::string::npos);
            }
        }
    EXPECT_GT(rejected, total * 95 / 100);
}

TEST(Asset, RejectsBadMagicAndVersionWithClearMessages)
{
    auto bytes = ngi::serializeAsset(makeAsset(16, 1));
    auto wrongMagic = bytes;
    wrongMagic[1] = 'X';
    try {
        ngi::parseAsset(wrongMagic, "a.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_STREQ(e.what(), "a.ngi: not an ngi asset (bad magic bytes)");
    }
    auto wrongVersion = bytes;
    wrongVersion[8] = uint8_t(ngi::kAssetFormatVersion + 1);
    try {
        ngi::parseAsset(wrongVersion, "b.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("unsupported asset format version " +
                                             std::to_string(ngi::kAssetFormatVersion + 1)),
                  std::string::npos)
            << e.what();
    }
}

TEST(Asset, WriterRejectsInconsistentAssets)
{
    ngi::Asset a = makeAsset(16, 1);
    a.charts[0].positions.pop_back();
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error);
    ngi::Asset b = makeAsset(16, 1);
    b.charts[0].fullResolution = 24;
    EXPECT_THROW(ngi::serializeAsset(b), ngi::Error);
    ngi::Asset c = makeAsset(16, 1);
    c.scale.x = NAN;
    EXPECT_THROW(ngi::serializeAsset(c), ngi::Error);
    ngi::Asset d = makeAsset(16, 1);
    d.charts.clear();
    EXPECT_THROW(ngi::serializeAsset(d), ngi::Error);
}

TEST(Asset, SeveralChartsRoundTripAndMapOneLod)
{
    ngi::Asset a = makeAsset(64, 3);
    a.charts.push_back(makeChart(32, 3, 1.0f));
    a.charts.push_back(makeChart(8, 3, 2.0f));
    const ngi::Asset b = ngi::parseAsset(ngi::serializeAsset(a), "three.ngi");
    expectSameAsset(a, b);
    EXPECT_EQ(b.fullResolution(), 64u);
    // One LoD for the asset: every chart draws the same level index, so a chart of half the
    // resolution (a quarter of the area) has half the cells per side: the same density.
    for (int level : {0, 2, 3})
        for (size_t c = 0; c < b.charts.size(); ++c)
            EXPECT_EQ(ngi::chartLevelForAssetLevel(b, b.charts[c], level), level);
}

// The chunk table as assetChunkSizes reads it: one entry per chunk in file order, each
// payload after the 24-byte header and the 32-byte table entries (ngi/asset.h) and after the
// chunk before it, so the sizes add up to the file less the header, the table and the
// alignment (under 8 bytes per chunk); a per-chart chunk names its chart. Every truncation
// and a bad magic throw.
TEST(Asset, ChunkSizesAddUpToTheFileAndRejectTruncation)
{
    for (const bool pyramid : {false, true}) {
        ngi::Asset a = makeAsset(64, 3);
        a.charts.push_back(makeChart(32, 3, 1.0f));
        a.coding.pyramid = pyramid;
        const std::vector<uint8_t> bytes = ngi::serializeAsset(a);
        const std::vector<ngi::AssetChunkSize> chunks = ngi::assetChunkSizes(bytes, "two.ngi");
        ASSERT_FALSE(chunks.empty());
        EXPECT_EQ(chunks.front().name, "HEAD");
        const uint64_t headerAndTable = 24 + 32 * chunks.size();
        uint64_t sum = 0, end = headerAndTable;
        for (const ngi::AssetChunkSize& chunk : chunks) {
            EXPECT_GE(chunk.offset, end) << chunk.name;
            EXPECT_LT(chunk.offset, end + 8) << chunk.name;
            end = chunk.offset + chunk.bytes;
            sum += chunk.bytes;
        }
        EXPECT_EQ(end, bytes.size());
        EXPECT_LE(sum, bytes.size() - headerAndTable);
        EXPECT_GT(sum + 8 * chunks.size(), bytes.size() - headerAndTable);
        if (!pyramid) {  // format 3: one POSI per chart
            EXPECT_NE(std::find_if(chunks.begin(), chunks.end(),
                                   [](const ngi::AssetChunkSize& c) { return c.name == "POSI" && c.chart == 1; }),
                      chunks.end());
        }

        for (size_t n = 0; n < bytes.size(); n += 7)
            EXPECT_THROW(ngi::assetChunkSizes(std::span(bytes.data(), n), "cut.ngi"), ngi::Error) << "cut at " << n;
        std::vector<uint8_t> text = bytes;
        text[4] = '\n';
        try {
            ngi::assetChunkSizes(text, "text.ngi");
            ADD_FAILURE() << "accepted a bad magic";
        } catch (const ngi::Error& e) {
            EXPECT_NE(std::string(e.what()).find("text.ngi: "), std::string::npos) << e.what();
        }
    }
}

// Format 6: a per-chart residual gain in CHRT, written with each coding (3: zlib, 4: pyramid,
// 5: progressive) only when a gain is not 1; the samples are those of the same coding without
// gains, every truncation is rejected, and the writer refuses a gain outside [0, 1].
TEST(Asset, ResidualGainsRoundTripAsFormat6WithEveryCoding)
{
    for (int coding = 3; coding <= 5; ++coding) {
        ngi::Asset a = makeAsset(32, 2);
        a.charts.push_back(makeChart(16, 2, 1.0f));
        a.coding.pyramid = coding >= 4;
        a.coding.progressive = coding == 5;
        const std::vector<uint8_t> plain = ngi::serializeLegacyAsset(a);
        EXPECT_EQ(plain[8], uint8_t(coding)) << "a gain of 1 keeps the format";
        a.charts[0].residualGain = 0.25f;
        a.charts[1].residualGain = 0.0f;
        const std::vector<uint8_t> bytes = ngi::serializeLegacyAsset(a);
        EXPECT_EQ(bytes[8], 6u) << coding;
        EXPECT_EQ(bytes.size(), plain.size() + 8) << "4 bytes per chart";
        const ngi::Asset b = ngi::parseAsset(bytes, "gain.ngi"), p = ngi::parseAsset(plain, "plain.ngi");
        ASSERT_EQ(b.charts.size(), 2u);
        EXPECT_EQ(b.charts[0].residualGain, 0.25f);
        EXPECT_EQ(b.charts[1].residualGain, 0.0f);
        EXPECT_EQ(p.charts[0].residualGain, 1.0f);
        for (size_t c = 0; c < 2; ++c) {
            EXPECT_EQ(b.charts[c].positions, p.charts[c].positions) << coding;
            EXPECT_EQ(b.charts[c].normals, p.charts[c].normals) << coding;
        }
        EXPECT_EQ(b.coding.pyramid, coding >= 4);
        EXPECT_EQ(ngi::serializeLegacyAsset(b), bytes) << coding;
        for (size_t n = 0; n < bytes.size(); n += 7)
            EXPECT_THROW(ngi::parseAsset(std::span(bytes.data(), n), "cut.ngi"), ngi::Error)
                << coding << " cut at " << n;
        if (coding == 5) {  // the streaming reader reads the gains with the description
            const ngi::AssetPrefix prefix = ngi::readAssetPrefix(bytes, "gain.ngi");
            EXPECT_EQ(prefix.asset.charts[0].residualGain, 0.25f);
        }
    }
    // Every single bit flip of a format-6 file is rejected or leaves its content (gain included).
    ngi::Asset flipped = makeAsset(16, 1);
    flipped.charts[0].residualGain = 0.5f;
    const std::vector<uint8_t> six = ngi::serializeLegacyAsset(flipped);
    size_t rejected = 0;
    for (size_t i = 0; i < six.size(); ++i)
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<uint8_t> f = six;
            f[i] ^= uint8_t(1u << bit);
            try {
                const ngi::Asset b = ngi::parseAsset(f, "flip.ngi");
                expectSameAsset(flipped, b);
                EXPECT_EQ(b.charts[0].residualGain, 0.5f);
            } catch (const ngi::Error&) {
                ++rejected;
            }
        }
    EXPECT_GT(rejected, six.size() * 8 * 95 / 100);
    ngi::Asset bad = makeAsset(16, 1);
    for (float gain : {1.5f, -0.1f, NAN}) {
        bad.charts[0].residualGain = gain;
        EXPECT_THROW(ngi::serializeLegacyAsset(bad), ngi::Error) << gain;
    }
}

TEST(Asset, ReadsFormatVersionOne)
{
    ngi::Asset a = makeAsset(32, 2);
    a.charts[0].seams = {};  // version 1 had no seam chunk
    const ngi::Asset b = ngi::parseAsset(versionOneFile(a), "old.ngi");
    expectSameAsset(a, b);
}

// Sizes beyond the documented limits are refused from the header alone, before the
// samples are allocated (a 4096^2 chart is the most; the charts together at most twice it).
TEST(Asset, RejectsSizesBeyondTheLimitsBeforeAllocating)
{
    // Patches chart table entries (CHRT is the second chunk) and fixes the CRCs, so that only
    // the declared sizes are wrong.
    auto expectProblem = [](const ngi::Asset& a, std::vector<std::pair<size_t, uint32_t>> patches,
                            const std::string& problem) {
        auto bytes = ngi::serializeAsset(a);
        uint64_t offset, size;
        std::memcpy(&offset, bytes.data() + 24 + 32 + 8, 8);
        std::memcpy(&size, bytes.data() + 24 + 32 + 16, 8);
        const size_t entry = bytes[8] >= 6 ? 16 : 12;  // format 6 and later: + the residual gain
        for (auto [chart, resolution] : patches) {
            std::memcpy(bytes.data() + offset + chart * entry, &resolution, 4);
            const uint32_t storedSize = (resolution >> a.charts[chart].storedLevel) + 1;
            std::memcpy(bytes.data() + offset + chart * entry + 8, &storedSize, 4);
        }
        const uint32_t crc = uint32_t(crc32(0L, bytes.data() + offset, uInt(size)));
        std::memcpy(bytes.data() + 24 + 32 + 24, &crc, 4);
        uint32_t chunkCount;
        std::memcpy(&chunkCount, bytes.data() + 12, 4);
        const uint32_t tableCrc = uint32_t(crc32(0L, bytes.data() + 24, uInt(chunkCount * 32)));
        std::memcpy(bytes.data() + 16, &tableCrc, 4);
        try {
            ngi::parseAsset(bytes, "huge.ngi");
            ADD_FAILURE() << "accepted " << problem;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("huge.ngi: ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
        }
    };
    expectProblem(makeAsset(16, 1), {{0, 8192}}, "not a power of two in [1, 4096]");
    expectProblem(makeAsset(16, 1), {{0, 16384}}, "not a power of two in [1, 4096]");
    // One chart at the limit is allowed: then its tiny payload cannot hold 2049^2 samples.
    expectProblem(makeAsset(16, 1), {{0, 4096}},
                  "chunk POSI of chart 0 is too small for the samples its header declares");
    ngi::Asset three = makeAsset(16, 1);
    three.charts.push_back(makeChart(16, 1));
    three.charts.push_back(makeChart(16, 1));
    expectProblem(three, {{0, 4096}, {1, 4096}, {2, 4096}}, "more than the limit of");
    // The writer holds itself to the same limits.
    ngi::Asset writerCheck = makeAsset(16, 1);
    writerCheck.charts[0] = makeChart(8192, 12);
    EXPECT_THROW(ngi::serializeAsset(writerCheck), ngi::Error);
}

TEST(Asset, FileWriteIsAtomicAndReadNamesThePath)
{
    const auto dir = std::filesystem::temp_directory_path() / "ngi_asset_test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto path = dir / "a.ngi";
    const ngi::Asset a = makeAsset(16, 1);
    ngi::writeAsset(a, path);
    expectSameAsset(a, ngi::readAsset(path));
    // A failing write leaves the old file intact and no temporary behind.
    ngi::Asset bad = a;
    bad.charts[0].normals.clear();
    EXPECT_THROW(ngi::writeAsset(bad, path), ngi::Error);
    expectSameAsset(a, ngi::readAsset(path));
    size_t files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
    try {
        ngi::readAsset(dir / "missing.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.ngi: cannot open file"), std::string::npos);
    }
    std::filesystem::remove_all(dir);
}

// Format 7: the curves two charts share (a split component, XSEM) round trip with every coding,
// make the file format 7 only when present, come with the description in a prefix, and every
// truncation, single bit flip and inconsistent seam is rejected with a message.
ngi::Asset splitAsset()
{
    ngi::Asset a = makeAsset(32, 2);
    a.charts.push_back(makeChart(32, 2, 1.0f));
    for (ngi::AssetChart& chart : a.charts) {
        chart.seams.matched = true;
        chart.seams.coarsestWatertightLevel = 2;
        chart.seams.segments.clear();
    }
    // Chart 0's bottom side is chart 1's top side, the other way round.
    a.crossSeams = {{0, 0, 1, 64, 32}};
    return a;
}

TEST(Asset, CrossSeamsRoundTripAsFormat7WithEveryCoding)
{
    for (int coding = 3; coding <= 5; ++coding) {
        ngi::Asset a = splitAsset();
        a.coding.pyramid = coding >= 4;
        a.coding.progressive = coding == 5;
        const std::vector<uint8_t> bytes = ngi::serializeLegacyAsset(a);
        EXPECT_EQ(bytes[8], 7u) << coding;
        const ngi::Asset b = ngi::parseAsset(bytes, "split.ngi");
        ASSERT_EQ(b.crossSeams.size(), 1u);
        EXPECT_EQ(b.crossSeams[0].chartA, 0u);
        EXPECT_EQ(b.crossSeams[0].b, 64u);
        EXPECT_EQ(b.crossSeams[0].length, 32u);
        EXPECT_EQ(ngi::serializeLegacyAsset(b), bytes) << coding;
        ngi::Asset without = a;
        without.crossSeams.clear();
        EXPECT_EQ(ngi::serializeLegacyAsset(without)[8], uint8_t(coding)) << "no cross seam keeps the format";
        for (size_t n = 0; n < bytes.size(); n += 5)
            EXPECT_THROW(ngi::parseAsset(std::span(bytes.data(), n), "cut.ngi"), ngi::Error)
                << coding << " cut at " << n;
        if (coding == 5) {
            const ngi::AssetPrefix prefix = ngi::readAssetPrefix(bytes, "split.ngi");
            EXPECT_EQ(prefix.asset.crossSeams.size(), 1u) << "XSEM comes with the description";
        }
    }
    // A format-7 file relabelled 6 (the version is not under a CRC) is refused for its XSEM.
    std::vector<uint8_t> relabelled = ngi::serializeLegacyAsset(splitAsset());
    relabelled[8] = 6;
    try {
        ngi::parseAsset(relabelled, "six.ngi");
        ADD_FAILURE() << "accepted XSEM in format 6";
    } catch (const ngi::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("six.ngi: ", 0), 0u) << "the message names the file: " << e.what();
        EXPECT_NE(std::string(e.what()).find("chunk XSEM needs format 7"), std::string::npos) << e.what();
    }
    size_t rejected = 0, total = 0;
    const ngi::Asset original = splitAsset();
    const std::vector<uint8_t> seven = ngi::serializeLegacyAsset(original);
    for (size_t i = 0; i < seven.size(); i += 3)
        for (int bit = 0; bit < 8; ++bit, ++total) {
            std::vector<uint8_t> f = seven;
            f[i] ^= uint8_t(1u << bit);
            try {
                const ngi::Asset b = ngi::parseAsset(f, "flip.ngi");
                ASSERT_EQ(b.crossSeams.size(), 1u);
                EXPECT_EQ(b.crossSeams[0].length, 32u);
            } catch (const ngi::Error&) {
                ++rejected;
            }
        }
    EXPECT_GT(rejected, total * 95 / 100);
}

TEST(Asset, InconsistentCrossSeamsAreRefusedNamingTheProblem)
{
    auto expectRefused = [](ngi::Asset a, const char* needle) {
        try {
            ngi::serializeAsset(a);
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const ngi::Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    ngi::Asset a = splitAsset();
    a.crossSeams[0].chartB = 2;
    expectRefused(a, "joins charts 0 and 2 of 2");
    a = splitAsset();
    std::swap(a.crossSeams[0].chartA, a.crossSeams[0].chartB);
    expectRefused(a, "needs chartA < chartB");
    a = splitAsset();
    a.charts[1].seams.matched = false;
    expectRefused(a, "not matched");
    a = splitAsset();
    a.charts[1].seams.coarsestWatertightLevel = 1;
    expectRefused(a, "coarsest watertight levels 2 and 1");
    a = splitAsset();
    a.crossSeams[0].length = 0;
    expectRefused(a, "is empty");
    a = splitAsset();
    a.crossSeams[0].b = 100;
    expectRefused(a, "runs past a border");
    a = splitAsset();
    a.crossSeams[0].a = 2;
    expectRefused(a, "does not end on samples of level 2");
}

}  // namespace

namespace {

// An asset whose chart has a base colour over its level-1 grid: a smooth gradient (what WebP
// codes well) with a sharp stripe, alpha opaque unless `translucent`.
ngi::Asset colouredAsset(bool translucent)
{
    ngi::Asset a = makeAsset(32, 2);
    ngi::AssetChart& c = a.charts[0];
    c.baseColorLevel = 1;
    const uint32_t n = c.baseColorSize();
    c.baseColor.resize(size_t(n) * n * 4);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            uint8_t* t = &c.baseColor[(size_t(y) * n + x) * 4];
            t[0] = uint8_t(40 + 6 * x);
            t[1] = uint8_t(200 - 5 * y);
            t[2] = x == 8 ? 250 : 60;
            t[3] = translucent ? uint8_t(128 + 4 * y) : 255;
        }
    return a;
}

}  // namespace

TEST(Asset, BaseColoursRoundTripAsFormat8WithEveryCoding)
{
    for (bool translucent : {false, true})
        for (int coding = 3; coding <= 5; ++coding) {
            ngi::Asset a = colouredAsset(translucent);
            a.coding.pyramid = coding >= 4;
            a.coding.progressive = coding == 5;
            a.coding.colorQuality = 101;  // lossless: the texels come back exactly
            const std::vector<uint8_t> bytes = ngi::serializeLegacyAsset(a);
            EXPECT_EQ(bytes[8], 8u) << coding;
            const ngi::Asset b = ngi::parseAsset(bytes, "colour.ngi");
            EXPECT_EQ(b.charts[0].baseColorLevel, 1u);
            EXPECT_EQ(b.charts[0].baseColor, a.charts[0].baseColor) << coding << " " << translucent;
            ngi::Asset without = a;
            without.charts[0].baseColor.clear();
            EXPECT_EQ(ngi::serializeLegacyAsset(without)[8], uint8_t(coding)) << "no colour keeps the format";
            for (size_t cut = 0; cut < bytes.size(); cut += 7)
                EXPECT_THROW(ngi::parseAsset(std::span(bytes.data(), cut), "cut.ngi"), ngi::Error);
        }
}

TEST(Asset, LossyBaseColourIsCloseAndApplyCodingMatchesTheFile)
{
    ngi::Asset a = colouredAsset(false);
    a.coding.pyramid = true;
    a.coding.colorQuality = 90;
    const std::vector<uint8_t> bytes = ngi::serializeAsset(a);
    const ngi::Asset b = ngi::parseAsset(bytes, "lossy.ngi");
    double error = 0.0;
    for (size_t i = 0; i < a.charts[0].baseColor.size(); ++i)
        error += std::abs(int(a.charts[0].baseColor[i]) - int(b.charts[0].baseColor[i]));
    // WebP at quality 90 on a 17^2 gradient: a few levels of 255 per channel on average.
    EXPECT_LT(error / double(a.charts[0].baseColor.size()), 6.0);
    ngi::Asset applied = a;
    ngi::applyAssetCoding(applied);
    EXPECT_EQ(applied.charts[0].baseColor, b.charts[0].baseColor) << "the in-memory asset is what a reader gets";
    // A progressive prefix that ends before BCOL has the shape without the colour; the whole
    // file has both.
    EXPECT_EQ(ngi::readAssetPrefix(bytes, "whole.ngi").asset.charts[0].baseColor, b.charts[0].baseColor);
}

TEST(Asset, MalformedBaseColoursAreRefusedNamingTheProblem)
{
    ngi::Asset a = colouredAsset(false);
    a.charts[0].baseColor.pop_back();
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error) << "a colour image of the wrong size";
    a = colouredAsset(false);
    a.charts[0].baseColorLevel = 9;
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error) << "a colour level the chart does not have";
    // Format 8 relabelled 7 (the version is not under a CRC): refused for its BCOL.
    std::vector<uint8_t> relabelled = ngi::serializeLegacyAsset(colouredAsset(false));
    relabelled[8] = 7;
    try {
        ngi::parseAsset(relabelled, "seven.ngi");
        ADD_FAILURE() << "accepted BCOL in format 7";
    } catch (const ngi::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("seven.ngi: ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("chunk BCOL needs format 8"), std::string::npos) << e.what();
    }
    // Single bit flips anywhere: refused (CRCs) or read with the same colour, never a crash.
    const ngi::Asset original = colouredAsset(false);
    const std::vector<uint8_t> eight = ngi::serializeLegacyAsset(original);
    const ngi::Asset clean = ngi::parseAsset(eight, "eight.ngi");
    size_t rejected = 0, total = 0;
    for (size_t i = 0; i < eight.size(); i += 5)
        for (int bit = 0; bit < 8; bit += 3, ++total) {
            std::vector<uint8_t> f = eight;
            f[i] ^= uint8_t(1u << bit);
            try {
                const ngi::Asset b = ngi::parseAsset(f, "flip.ngi");
                EXPECT_EQ(b.charts[0].baseColor, clean.charts[0].baseColor) << "byte " << i;
            } catch (const ngi::Error&) {
                ++rejected;
            }
        }
    EXPECT_GT(rejected, total * 95 / 100);
}
