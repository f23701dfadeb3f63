// The level-by-level form of the nested-pyramid coder (ngi/pyramid_codec.h, codec 2): the
// same samples as the one-stream form, each level's stream decodes on its own once the
// coarser ones are in and gives the nested level bitwise, a stream's end is found by
// decoding it, the flushes cost a few bytes a level, hostile streams are rejected cleanly.
#include "ngi/error.h"
#include "ngi/pyramid_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

namespace {

// A wavy height field with a little noise on a size^2 grid (u16, RGB).
std::vector<uint16_t> wavyLevel(uint32_t size, uint32_t seed = 3)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> noise(-5, 5);
    std::vector<uint16_t> out;
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const double u = double(x) / (size - 1), v = double(y) / (size - 1);
            const double h = 0.5 + 0.2 * std::sin(7 * u + 1) * std::cos(5 * v) + 0.05 * std::sin(23 * u * v);
            for (double c : {u, v, h})
                out.push_back(uint16_t(std::clamp<long>(std::lround(c * 65535) + noise(rng), 0, 65535)));
        }
    return out;
}

// Every 2^shift-th sample of a size^2 RGB level: the nested level that many levels coarser.
std::vector<uint16_t> nested(const std::vector<uint16_t>& s, uint32_t size, uint32_t shift)
{
    const uint32_t n = ((size - 1) >> shift) + 1;
    std::vector<uint16_t> out;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) out.push_back(s[((size_t(y) << shift) * size + (size_t(x) << shift)) * 3 + c]);
    return out;
}

std::vector<uint8_t> concatenated(const ngi::PyramidLevels& levels)
{
    std::vector<uint8_t> out;
    for (const auto& l : levels.levels) out.insert(out.end(), l.begin(), l.end());
    return out;
}

// Mates of a folded seam: the right column is the left one reversed.
std::vector<uint32_t> foldedMates(uint32_t n)
{
    std::vector<uint32_t> mates(size_t(n) * n);
    std::iota(mates.begin(), mates.end(), 0u);
    for (uint32_t y = 0; y < n; ++y) mates[size_t(n - 1 - y) * n + (n - 1)] = y * n;
    return mates;
}

TEST(PyramidLevels, DecodesToTheSameSamplesAsOneStream)
{
    const uint32_t n = 65;
    const auto samples = wavyLevel(n);
    const std::vector<uint32_t> mates = foldedMates(n);
    for (uint32_t tangentScale : {0u, 4u})
        for (bool withMates : {false, true}) {
            ngi::PyramidCodecOptions options{.step = 16, .tangentScale = tangentScale};
            if (withMates) options.mates = mates;
            const auto one =
                ngi::decodePyramidPositions(ngi::encodePyramidPositions(samples, n, options), n, "t", options.mates);
            const ngi::PyramidLevels levels = ngi::encodePyramidLevels(samples, n, options);
            EXPECT_EQ(levels.header.size(), ngi::pyramidLevelsHeaderBytes(n));
            ASSERT_EQ(levels.levels.size(), ngi::pyramidLevelCount(n));
            EXPECT_EQ(ngi::decodePyramidLevels(levels, n, "t", options.mates), one) << tangentScale << withMates;
        }
}

TEST(PyramidLevels, EachLevelIsTheNestedLevelBitwiseAndEndsWhereItsStreamEnds)
{
    const uint32_t n = 129;
    const auto samples = wavyLevel(n);
    const std::vector<uint32_t> mates = foldedMates(n);
    ngi::PyramidCodecOptions options{.step = 32};
    options.mates = mates;
    const ngi::PyramidLevels levels = ngi::encodePyramidLevels(samples, n, options);
    const auto full = ngi::decodePyramidLevels(levels, n, "t", mates);
    // The streams back to back, no lengths: each decodeLevel finds its own end.
    const std::vector<uint8_t> stream = concatenated(levels);
    ngi::PyramidLevelDecoder decoder(levels.header, n, "t", mates);
    EXPECT_THROW(decoder.decodedLevel(), ngi::Error);
    size_t at = 0;
    for (uint32_t l = 0; l < decoder.levelCount(); ++l) {
        const size_t used = decoder.decodeLevel(std::span(stream).subspan(at));
        EXPECT_EQ(used, levels.levels[l].size()) << l;
        at += used;
        const uint32_t shift = decoder.levelCount() - 1 - l;
        EXPECT_EQ(decoder.decodedSize(), ((n - 1) >> shift) + 1);
        EXPECT_EQ(decoder.decodedLevel(), nested(full, n, shift)) << "level " << l;
        // A level decoded alone from a fresh decoder given only levels 0..l agrees too.
        ngi::PyramidLevels prefix{levels.header, {levels.levels.begin(), levels.levels.begin() + l + 1}};
        EXPECT_EQ(ngi::decodePyramidLevels(prefix, n, "t", mates), nested(full, n, shift)) << "level " << l;
    }
    EXPECT_EQ(at, stream.size());
    EXPECT_THROW(decoder.decodeLevel({}), ngi::Error);  // every level is decoded
}

// The cost of streaming: one flush per level, about 4 bytes (the pending low bytes of the
// range coder) each, against the one stream's single final flush.
TEST(PyramidLevels, FlushesCostAFewBytesPerLevel)
{
    for (uint32_t n : {33u, 129u, 257u}) {
        const auto samples = wavyLevel(n);
        for (uint32_t step : {8u, 64u}) {
            std::vector<size_t> oneLevels, flushedLevels;
            const auto one = ngi::encodePyramidPositions(samples, n, {.step = step, .levelBytes = &oneLevels});
            const ngi::PyramidLevels levels =
                ngi::encodePyramidLevels(samples, n, {.step = step, .levelBytes = &flushedLevels});
            const size_t levelCount = ngi::pyramidLevelCount(n);
            const long extra = long(concatenated(levels).size() + levels.header.size()) - long(one.size());
            EXPECT_GE(extra, long(3 * (levelCount - 1))) << n << " " << step;
            EXPECT_LE(extra, long(5 * (levelCount - 1))) << n << " " << step;
            ASSERT_EQ(flushedLevels.size(), levelCount);
            for (size_t l = 0; l < levelCount; ++l) EXPECT_EQ(flushedLevels[l], levels.levels[l].size());
        }
    }
}

TEST(PyramidLevels, TruncatedOrCorruptStreamsAreRejectedCleanly)
{
    const uint32_t n = 17;
    const ngi::PyramidLevels levels = ngi::encodePyramidLevels(wavyLevel(n), n, {.step = 8});
    // A header of the wrong size, version or level count.
    EXPECT_THROW(ngi::PyramidLevelDecoder(std::span(levels.header).first(levels.header.size() - 1), n, "t"),
                 ngi::Error);
    EXPECT_THROW(ngi::PyramidLevelDecoder(levels.header, 33, "t"), ngi::Error);
    std::vector<uint8_t> oneStreamHeader = levels.header;
    oneStreamHeader[0] = 1;
    EXPECT_THROW(ngi::PyramidLevelDecoder(oneStreamHeader, n, "t"), ngi::Error);
    // Every truncation of every level's stream runs past its bytes.
    for (size_t l = 0; l < levels.levels.size(); ++l)
        for (size_t cut = 0; cut < levels.levels[l].size(); ++cut) {
            ngi::PyramidLevelDecoder d(levels.header, n, "t");
            for (size_t k = 0; k < l; ++k) d.decodeLevel(levels.levels[k]);
            EXPECT_THROW(d.decodeLevel(std::span(levels.levels[l]).first(cut)), ngi::Error) << l << " " << cut;
            EXPECT_THROW(d.decodeLevel(levels.levels[l]), ngi::Error);  // refused after a failure
        }
    // A flipped bit: rejected, or samples that are still a full level (u16 values are in range
    // by type); decodePyramidLevels insists each stream ends on its last byte.
    const std::vector<uint8_t> last = levels.levels.back();
    size_t rejected = 0;
    for (size_t bit = 0; bit < last.size() * 8; ++bit) {
        ngi::PyramidLevels flipped = levels;
        flipped.levels.back()[bit / 8] ^= uint8_t(1u << (bit % 8));
        try {
            EXPECT_EQ(ngi::decodePyramidLevels(flipped, n, "t").size(), size_t(n) * n * 3);
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("t: ", 0), 0u) << e.what();
            ++rejected;
        }
    }
    EXPECT_GT(rejected, 0u);
}

}  // namespace
