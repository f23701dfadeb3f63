// The .ngi asset: lossless round trip, atomic writes, and rejection of every corrupt file
// (exhaustive truncation and single-bit flips, in the manner of meshoptimizer's tests).
#include "ngi/asset.h"
#include "ngi/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

ngi::Asset makeAsset(uint32_t resolution, uint32_t level)
{
    ngi::Asset a;
    a.sourceName = "analytic:test";
    a.sourceHash = 1234;
    a.offset = {-1.0f, -2.0f, 0.5f};
    a.scale = {2.0f, 2.0f, 2.0f};
    a.fullResolution = resolution;
    a.storedLevel = level;
    a.parameterization = "analytic";
    a.metadataJson = R"({"note":"test"})";
    ngi::GeometryImage pos(a.storedSize()), nrm(a.storedSize());
    for (uint32_t y = 0; y < pos.size; ++y)
        for (uint32_t x = 0; x < pos.size; ++x) {
            const float u = float(x) / float(pos.size - 1), v = float(y) / float(pos.size - 1);
            pos.at(x, y) = {u, v, 0.5f + 0.25f * std::sin(6.0f * u) * std::cos(5.0f * v)};
            nrm.at(x, y) = glm::vec3(0.6f, 0.0f, 0.8f);
        }
    ngi::storeGeometryImage(a, pos, nrm);
    return a;
}

void expectSameAsset(const ngi::Asset& a, const ngi::Asset& b)
{
    EXPECT_EQ(a.sourceName, b.sourceName);
    EXPECT_EQ(a.sourceHash, b.sourceHash);
    EXPECT_EQ(a.offset, b.offset);
    EXPECT_EQ(a.scale, b.scale);
    EXPECT_EQ(a.fullResolution, b.fullResolution);
    EXPECT_EQ(a.storedLevel, b.storedLevel);
    EXPECT_EQ(a.parameterization, b.parameterization);
    EXPECT_EQ(a.networkId, b.networkId);
    EXPECT_EQ(a.metadataJson, b.metadataJson);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
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
    const ngi::GeometryImage p = ngi::storedPositions(a);
    for (uint32_t y = 0; y < p.size; ++y)
        for (uint32_t x = 0; x < p.size; ++x) {
            const float u = float(x) / float(p.size - 1);
            EXPECT_NEAR(p.at(x, y).x, u, 0.5f / 65535.0f + 1e-7f);
        }
    const ngi::GeometryImage n = ngi::storedNormals(a);
    EXPECT_NEAR(n.at(3, 4).x, 0.6f, 1e-4f);
    EXPECT_NEAR(n.at(3, 4).z, 0.8f, 1e-4f);
}

TEST(Asset, CompressesSmoothImages)
{
    const ngi::Asset a = makeAsset(256, 1);  // 129^2 stored samples
    const size_t raw = a.positions.size() * 2 + a.normals.size() * 2;
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
    wrongVersion[8] = 7;
    try {
        ngi::parseAsset(wrongVersion, "b.ngi");
        FAIL();
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("unsupported asset format version 7"), std::string::npos);
    }
}

TEST(Asset, WriterRejectsInconsistentAssets)
{
    ngi::Asset a = makeAsset(16, 1);
    a.positions.pop_back();
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error);
    ngi::Asset b = makeAsset(16, 1);
    b.fullResolution = 24;
    EXPECT_THROW(ngi::serializeAsset(b), ngi::Error);
    ngi::Asset c = makeAsset(16, 1);
    c.scale.x = NAN;
    EXPECT_THROW(ngi::serializeAsset(c), ngi::Error);
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
    bad.normals.clear();
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

} // namespace
