// ngi tests: format 9 packs the description chunks (one SEAM for every chart, XSEM) as zlib of
// LEB128 fields. They round trip, take a fraction of formats 3-8's bytes, and every malformed
// packed chunk is refused with a message naming the file and the chunk.
#include "asset_format.h"
#include "crc32.h"

#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/asset_prefix.h"
#include "ngi/error.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace {

ngi::AssetChart chart(uint32_t resolution, uint32_t level)
{
    ngi::AssetChart a;
    a.fullResolution = resolution;
    a.storedLevel = level;
    ngi::GeometryImage pos(a.storedSize()), nrm(a.storedSize());
    for (uint32_t y = 0; y < pos.size; ++y)
        for (uint32_t x = 0; x < pos.size; ++x) {
            const float u = float(x) / float(pos.size - 1), v = float(y) / float(pos.size - 1);
            pos.at(x, y) = {u, v, 0.5f + 0.2f * std::sin(5.0f * u) * std::cos(4.0f * v)};
            nrm.at(x, y) = glm::vec3(0.0f, 0.6f, 0.8f);
        }
    ngi::storeGeometryImage(a, pos, nrm);
    return a;
}

// `count` charts of 32^2 stored at level 2, each a cylinder (bottom side = top side), chart c's
// left side shared with chart c + 1's right side; a chart with no matched seam in the middle.
ngi::Asset splitAsset(uint32_t count)
{
    ngi::Asset a;
    a.sourceName = "analytic:split";
    a.offset = {0.0f, 0.0f, 0.0f};
    a.scale = {1.0f, 1.0f, 1.0f};
    a.coding.pyramid = true;
    a.coding.positionStep = 64;
    for (uint32_t c = 0; c < count; ++c) {
        a.charts.push_back(chart(32, 2));
        ngi::ChartSeams& seams = a.charts.back().seams;
        if (c == count / 2) continue;
        seams.matched = true;
        seams.coarsestWatertightLevel = 2;
        seams.segments = {{0, 64, 32}};
        if (c + 1 < count && c + 1 != count / 2 && c != count / 2) a.crossSeams.push_back({c, 96, c + 1, 32, 32});
    }
    return a;
}

struct Chunk {
    uint32_t code, encoding, chart;
    std::vector<uint8_t> bytes;
};

std::vector<Chunk> chunksOf(const std::vector<uint8_t>& file)
{
    std::vector<Chunk> chunks;
    for (const ngi::AssetChunkSize& e : ngi::assetChunkSizes(file)) {
        uint32_t code;
        std::memcpy(&code, e.name.data(), 4);
        chunks.push_back(
            {code, e.encoding, e.chart,
             std::vector<uint8_t>(file.begin() + long(e.offset), file.begin() + long(e.offset + e.bytes))});
    }
    return chunks;
}

// The file laid out again (as the writer lays it out: 8-byte aligned, CRCs) with `chunks`.
std::vector<uint8_t> fileOf(uint32_t version, const std::vector<Chunk>& chunks)
{
    std::vector<uint8_t> out(24 + 32 * chunks.size(), 0);
    std::memcpy(out.data(), "\x89NGI\r\n\x1a\n", 8);
    const uint32_t count = uint32_t(chunks.size());
    std::memcpy(out.data() + 8, &version, 4);
    std::memcpy(out.data() + 12, &count, 4);
    for (size_t i = 0; i < chunks.size(); ++i) {
        out.resize((out.size() + 7) & ~size_t(7), 0);
        const uint64_t offset = out.size(), size = chunks[i].bytes.size();
        const uint32_t crc = ngi::detail::crc32Of(chunks[i].bytes);
        uint8_t* e = out.data() + 24 + 32 * i;
        std::memcpy(e, &chunks[i].code, 4);
        std::memcpy(e + 4, &chunks[i].encoding, 4);
        std::memcpy(e + 8, &offset, 8);
        std::memcpy(e + 16, &size, 8);
        std::memcpy(e + 24, &crc, 4);
        std::memcpy(e + 28, &chunks[i].chart, 4);
        out.insert(out.end(), chunks[i].bytes.begin(), chunks[i].bytes.end());
    }
    const uint32_t tableCrc = ngi::detail::crc32Of(std::span(out).subspan(24, 32 * chunks.size()));
    std::memcpy(out.data() + 16, &tableCrc, 4);
    return out;
}

size_t count(const std::vector<Chunk>& chunks, const char (&code)[5])
{
    size_t n = 0;
    for (const Chunk& c : chunks) n += c.code == ngi::detail::fourcc(code);
    return n;
}

Chunk* find(std::vector<Chunk>& chunks, const char (&code)[5])
{
    for (Chunk& c : chunks)
        if (c.code == ngi::detail::fourcc(code)) return &c;
    return nullptr;
}

void expectRefused(const std::vector<uint8_t>& file, const std::string& problem)
{
    try {
        ngi::parseAsset(file, "packed.ngi");
        ADD_FAILURE() << "accepted a file with " << problem;
    } catch (const ngi::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("packed.ngi: ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
}

TEST(AssetPacked, SeamsAndCrossSeamsRoundTripInOneChunkEachAndTakeFarFewerBytes)
{
    for (bool progressive : {true, false}) {
        ngi::Asset a = splitAsset(9);
        a.coding.progressive = progressive;
        const std::vector<uint8_t> nine = ngi::serializeAsset(a), old = ngi::serializeLegacyAsset(a);
        EXPECT_EQ(nine[8], 9u);
        EXPECT_EQ(old[8], 7u);
        std::vector<Chunk> chunks = chunksOf(nine);
        EXPECT_EQ(count(chunks, "SEAM"), 1u) << "one SEAM for every chart";
        EXPECT_EQ(find(chunks, "SEAM")->encoding, 6u);
        EXPECT_EQ(find(chunks, "SEAM")->chart, 0u);
        EXPECT_EQ(find(chunks, "XSEM")->encoding, 6u);
        // 8 matched charts: 7 fewer chunk-table entries of 32 bytes; SEAM 8 x 20 and XSEM 4 + 6 x 20
        // bytes raw. Measured: format 9 is 480 (progressive) and 481 bytes smaller than 7 here.
        EXPECT_LT(nine.size() + 400, old.size()) << progressive;
        const ngi::Asset b = ngi::parseAsset(nine, "nine.ngi"), c = ngi::parseAsset(old, "seven.ngi");
        ASSERT_EQ(b.charts.size(), 9u);
        for (size_t i = 0; i < b.charts.size(); ++i) {
            EXPECT_EQ(b.charts[i].seams.matched, a.charts[i].seams.matched) << i;
            EXPECT_EQ(b.charts[i].seams.coarsestWatertightLevel, c.charts[i].seams.coarsestWatertightLevel) << i;
            ASSERT_EQ(b.charts[i].seams.segments.size(), a.charts[i].seams.segments.size()) << i;
            for (size_t k = 0; k < b.charts[i].seams.segments.size(); ++k) {
                EXPECT_EQ(b.charts[i].seams.segments[k].b, a.charts[i].seams.segments[k].b);
                EXPECT_EQ(b.charts[i].seams.segments[k].length, a.charts[i].seams.segments[k].length);
            }
            EXPECT_EQ(b.charts[i].positions, c.charts[i].positions) << "the same samples as format 7";
        }
        ASSERT_EQ(b.crossSeams.size(), a.crossSeams.size());
        for (size_t k = 0; k < b.crossSeams.size(); ++k) {
            EXPECT_EQ(b.crossSeams[k].chartB, a.crossSeams[k].chartB);
            EXPECT_EQ(b.crossSeams[k].a, a.crossSeams[k].a);
        }
        EXPECT_EQ(ngi::serializeAsset(b), nine) << "idempotent";
        for (size_t n = 0; n < nine.size(); n += 11)
            EXPECT_THROW(ngi::parseAsset(std::span(nine.data(), n), "cut.ngi"), ngi::Error) << n;
        if (progressive) {
            const ngi::AssetPrefix prefix = ngi::readAssetPrefix(nine, "nine.ngi");
            EXPECT_EQ(prefix.asset.crossSeams.size(), a.crossSeams.size()) << "XSEM comes with the description";
            EXPECT_TRUE(prefix.asset.charts[0].seams.matched);
        }
    }
}

TEST(AssetPacked, MalformedPackedChunksAreRefusedNamingTheProblem)
{
    const ngi::Asset a = splitAsset(5);
    const std::vector<uint8_t> nine = ngi::serializeAsset(a);
    const std::vector<Chunk> chunks = chunksOf(nine);
    auto withSeam = [&](std::vector<uint8_t> payload, uint32_t encoding = 6, uint32_t version = 9) {
        std::vector<Chunk> c = chunks;
        find(c, "SEAM")->bytes = std::move(payload);
        find(c, "SEAM")->encoding = encoding;
        return fileOf(version, c);
    };
    // The helper lays the file out as the writer does.
    ASSERT_EQ(fileOf(9, chunks), nine);
    // Fields of the right kind, packed: SEAM holds charts 0, 1 matched (m = 3, one segment), ...
    auto packed = [](const std::vector<uint8_t>& fields) {
        uLongf n = compressBound(uLong(fields.size()));
        std::vector<uint8_t> out(4 + n);
        const uint32_t size = uint32_t(fields.size());
        std::memcpy(out.data(), &size, 4);
        compress2(out.data() + 4, &n, fields.data(), uLong(fields.size()), 9);
        out.resize(4 + n);
        return out;
    };
    const std::vector<uint8_t> good = {3, 1, 0, 64, 32, 3, 1, 0, 64, 32, 0, 3, 1, 0, 64, 32, 3, 1, 0, 64, 32};
    ASSERT_NO_THROW(ngi::parseAsset(withSeam(packed(good)), "packed.ngi"));
    std::vector<uint8_t> trailing = good;
    trailing.push_back(0);
    expectRefused(withSeam(packed(trailing)), "chunk SEAM has 1 bytes past its last field");
    expectRefused(withSeam(packed(std::vector<uint8_t>(good.begin(), good.end() - 1))),
                  "chunk SEAM declares 1 seam segments, more than its bytes hold");
    std::vector<uint8_t> cut = good;  // the last segment's b as two bytes (1000), its length cut off
    cut[cut.size() - 2] = 0xe8, cut.back() = 0x07;
    expectRefused(withSeam(packed(cut)), "chunk SEAM ends inside a seam segment");
    std::vector<uint8_t> huge = good;
    huge[1] = 0xff, huge[2] = 0xff, huge[3] = 0x7f;  // a segment count of 2^21 - 1
    expectRefused(withSeam(packed(huge)), "seam segments, more than its bytes hold");
    std::vector<uint8_t> wide = good;
    wide.insert(wide.begin() + 3, {0xff, 0xff, 0xff, 0xff, 0x7f});  // a field of 35 bits
    wide.erase(wide.begin() + 2);
    expectRefused(withSeam(packed(wide)), "chunk SEAM has a seam segment above 2^32");
    // A declared unpacked size no deflate stream of this length can give (a zip bomb), and one
    // beyond what the charts' borders can need.
    std::vector<uint8_t> bomb = packed(good);
    const uint32_t big = 1u << 30;
    std::memcpy(bomb.data(), &big, 4);
    expectRefused(withSeam(bomb), "unpacked bytes, more than its");
    std::vector<uint8_t> zeros(200000, 0);
    expectRefused(withSeam(packed(zeros)), "more than the charts' borders need");
    std::vector<uint8_t> liar = packed(good);
    const uint32_t less = uint32_t(good.size() - 1);
    std::memcpy(liar.data(), &less, 4);
    expectRefused(withSeam(liar), "does not unpack to the");
    expectRefused(withSeam({1, 0, 0}), "chunk SEAM is truncated");
    // A segment outside the chart's border: validated as formats 3-8 validate it.
    std::vector<uint8_t> outside = good;
    outside[3] = 0x80, outside.insert(outside.begin() + 4, 0x08);  // b = 1024 on a 32-sample chart
    EXPECT_THROW(ngi::parseAsset(withSeam(packed(outside)), "packed.ngi"), ngi::Error);
    // Encodings: format 9 packs SEAM and XSEM; raw ones there and packed ones below 9 are refused.
    expectRefused(withSeam(packed(good), 0), "chunk SEAM has encoding 0 (format 9 packs SEAM and XSEM with 6)");
    expectRefused(withSeam(packed(good), 6, 8), "chunk SEAM has encoding 6");
    // A bad XSEM: a cross seam naming a chart the asset does not have.
    std::vector<Chunk> c = chunks;
    find(c, "XSEM")->bytes = packed({1, 0, 96, 7, 32, 32});
    expectRefused(fileOf(9, c), "cross seam 0 joins charts 0 and 7 of 5");
}

// `splitAsset(count)` with a lossless base colour at level 1 on every chart but the second.
ngi::Asset colouredAsset(uint32_t count)
{
    ngi::Asset a = splitAsset(count);
    a.coding.colorQuality = 101;
    for (uint32_t c = 0; c < count; ++c) {
        if (c == 1) continue;
        ngi::AssetChart& chart = a.charts[c];
        chart.baseColorLevel = 1;
        const uint32_t n = chart.baseColorSize();
        chart.baseColor.resize(size_t(n) * n * 4);
        for (size_t i = 0; i < chart.baseColor.size(); ++i)
            chart.baseColor[i] = i % 4 == 3 ? 255 : uint8_t((i * 7 + c * 40) % 256);
    }
    return a;
}

TEST(AssetPacked, BaseColoursRoundTripInOneChunkAfterTheShape)
{
    const ngi::Asset a = colouredAsset(6);
    const std::vector<uint8_t> nine = ngi::serializeAsset(a), eight = ngi::serializeLegacyAsset(a);
    EXPECT_EQ(nine[8], 9u);
    EXPECT_EQ(eight[8], 8u);
    std::vector<Chunk> chunks = chunksOf(nine);
    EXPECT_EQ(count(chunks, "BCOL"), 1u);
    EXPECT_EQ(find(chunks, "BCOL")->encoding, 7u);
    EXPECT_GT(chunks.size(), 3u);
    ngi::Asset b = ngi::parseAsset(nine, "nine.ngi");
    for (size_t c = 0; c < a.charts.size(); ++c) {
        EXPECT_EQ(b.charts[c].baseColor, a.charts[c].baseColor) << c;
        EXPECT_EQ(b.charts[c].baseColorLevel, a.charts[c].baseColorLevel) << c;
    }
    b.coding.colorQuality = a.coding.colorQuality;  // the file keeps the images, not the quality
    EXPECT_EQ(ngi::serializeAsset(b), nine);
    // The colours come after the shape: a prefix that ends before BCOL has the shape only.
    size_t colourAt = 0;
    for (const ngi::AssetChunkSize& c : ngi::assetChunkSizes(nine))
        if (c.name == "BCOL") colourAt = size_t(c.offset);
    const ngi::AssetPrefix shape = ngi::readAssetPrefix(std::span(nine).first(colourAt), "prefix.ngi");
    EXPECT_TRUE(shape.asset.charts[0].baseColor.empty());
    EXPECT_GT(shape.levelsDecoded, 0u);
    // Malformed: a level the chart does not have, an image cut short, bytes left over, an image
    // that is not WebP, and BCOL in format 9 with format 8's encoding.
    auto withColour = [&](std::vector<uint8_t> payload, uint32_t encoding = 7) {
        std::vector<Chunk> c = chunks;
        find(c, "BCOL")->bytes = std::move(payload);
        find(c, "BCOL")->encoding = encoding;
        return fileOf(9, c);
    };
    ASSERT_EQ(withColour(find(chunks, "BCOL")->bytes), nine);
    std::vector<uint8_t> payload = find(chunks, "BCOL")->bytes;
    std::vector<uint8_t> level = payload;
    level[0] = 40;  // level 39 of a 32-cell chart
    expectRefused(withColour(level), "chunk BCOL gives chart 0 colour level 39, not one of its 6 levels");
    expectRefused(withColour(std::vector<uint8_t>(payload.begin(), payload.end() - 5)), "chunk BCOL ends inside");
    std::vector<uint8_t> extra = payload;
    extra.push_back(0);
    expectRefused(withColour(extra), "chunk BCOL has 1 bytes past its last field");
    std::vector<uint8_t> garbage = payload;
    for (size_t i = 3; i < 40; ++i) garbage[i] = 0x55;  // inside chart 0's image
    EXPECT_THROW(ngi::parseAsset(withColour(garbage), "packed.ngi"), ngi::Error);
    expectRefused(withColour(payload, 5), "chunk BCOL has encoding 5 (format 9 packs BCOL with 7)");
    // A format-8 file keeps one BCOL per chart (5 coloured charts here) and its 32-byte entries.
    EXPECT_EQ(count(chunksOf(eight), "BCOL"), 5u);
}

TEST(AssetPacked, UnpackingSurvivesEveryBitFlipAndTruncation)
{
    const ngi::Asset a = splitAsset(6);
    const std::vector<uint8_t> seams = ngi::detail::packSeams(a.charts);
    const std::vector<uint8_t> cross = ngi::detail::packCrossSeams(a.crossSeams);
    for (const std::vector<uint8_t>* packed : {&seams, &cross})
        for (size_t n = 0; n <= packed->size(); ++n)
            for (int bit = -1; bit < 8; ++bit) {
                std::vector<uint8_t> f(packed->begin(), packed->begin() + long(n));
                if (bit >= 0 && n > 0) f[n / 2] ^= uint8_t(1u << bit);
                std::vector<ngi::AssetChart> charts = a.charts;
                try {
                    if (packed == &seams)
                        ngi::detail::unpackSeams(f, charts, "flip.ngi");
                    else
                        ngi::detail::unpackCrossSeams(f, charts, "flip.ngi");
                } catch (const ngi::Error& e) {
                    EXPECT_EQ(std::string(e.what()).rfind("flip.ngi: chunk ", 0), 0u) << e.what();
                }
            }
}

}  // namespace
