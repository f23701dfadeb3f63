// Format 5's POSI chunk: every chart's positions level by level (pyramid codec 2), ordered
// coarse to fine across the charts, with a level table so that a reader knows where each
// level ends before it has the rest (ngi/asset.h gives the layout; ngi/asset_prefix.h reads
// prefixes).
#include "asset_format.h"

#include "crc32.h"
#include "ngi/error.h"

#include <algorithm>

namespace ngi::detail {
namespace {

constexpr uint8_t kLayoutVersion = 1;
constexpr uint8_t kFlagNormalsFlipped = 1;

// Reads from the chunk's first bytes; `short_` once a read would pass them (the table is not
// complete yet), which leaves every later read failing too.
struct TableReader {
    std::span<const uint8_t> bytes;
    size_t at = 0;
    bool short_ = false;
    bool has(size_t n)
    {
        if (short_ || bytes.size() - at < n) short_ = true;
        return !short_;
    }
    uint8_t u8() { return has(1) ? bytes[at++] : 0; }
    uint32_t u32()
    {
        if (!has(4)) return 0;
        uint32_t v = uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
            uint32_t(bytes[at + 3]) << 24;
        at += 4;
        return v;
    }
    // LEB128 of at most 7 bytes (< 2^49); `tooLong` when it has more.
    uint64_t leb128(bool& tooLong)
    {
        uint64_t v = 0;
        for (int i = 0; i < 7; ++i) {
            const uint8_t b = u8();
            if (short_) return 0;
            v |= uint64_t(b & 0x7f) << (7 * i);
            if (!(b & 0x80)) return v;
        }
        tooLong = true;
        return 0;
    }
    std::span<const uint8_t> take(size_t n)
    {
        if (!has(n)) return {};
        const auto s = bytes.subspan(at, n);
        at += n;
        return s;
    }
};

}  // namespace

std::vector<uint8_t> encodeProgressivePositions(const std::vector<PyramidLevels>& charts,
                                                const std::vector<bool>& normalsFlipped)
{
    size_t rounds = 0;
    for (const PyramidLevels& c : charts) rounds = std::max(rounds, c.levels.size());
    if (charts.empty() || charts.size() != normalsFlipped.size() || rounds > 255)
        throw Error("asset writer: inconsistent progressive positions");
    std::vector<uint8_t> out = {kLayoutVersion, uint8_t(rounds)};
    for (size_t c = 0; c < charts.size(); ++c) {
        out.push_back(normalsFlipped[c] ? kFlagNormalsFlipped : 0);
        out.insert(out.end(), charts[c].header.begin(), charts[c].header.end());
    }
    std::vector<std::vector<uint8_t>> roundBytes(rounds);
    for (size_t r = 0; r < rounds; ++r)
        for (const PyramidLevels& c : charts)
            if (r < c.levels.size()) roundBytes[r].insert(roundBytes[r].end(), c.levels[r].begin(), c.levels[r].end());
    for (const auto& bytes : roundBytes) putLeb128(out, bytes.size());
    for (const auto& bytes : roundBytes) {
        const uint32_t crc = crc32Of(bytes);
        for (int i = 0; i < 4; ++i) out.push_back(uint8_t(crc >> (8 * i)));
    }
    const uint32_t tableCrc = crc32Of(out);
    for (int i = 0; i < 4; ++i) out.push_back(uint8_t(tableCrc >> (8 * i)));
    for (const auto& bytes : roundBytes) out.insert(out.end(), bytes.begin(), bytes.end());
    return out;
}

ProgressivePositions::ProgressivePositions(const Asset& description, std::string where, uint64_t chunkBytes)
    : where_(std::move(where)), chunkBytes_(chunkBytes)
{
    for (const AssetChart& chart : description.charts) {
        sizes_.push_back(chart.storedSize());
        mates_.push_back(storedMates(chart));
    }
}

void ProgressivePositions::readTable(std::span<const uint8_t> available)
{
    auto fail = [&](const std::string& problem) {
        failed_ = true;
        throw Error(where_ + ": " + problem);
    };
    TableReader r{available};
    const uint8_t version = r.u8();
    const uint8_t rounds = r.u8();
    if (r.short_) return;
    if (version != kLayoutVersion) fail("unknown level-table version " + std::to_string(version));
    uint32_t levels = 0;
    for (uint32_t size : sizes_) levels = std::max(levels, pyramidLevelCount(size));
    if (rounds != levels)
        fail("the level table declares " + std::to_string(rounds) + " levels, the charts have " +
             std::to_string(levels));
    std::vector<std::span<const uint8_t>> headers;
    std::vector<bool> flipped;
    for (uint32_t size : sizes_) {
        const uint8_t flags = r.u8();
        headers.push_back(r.take(pyramidLevelsHeaderBytes(size)));
        if (r.short_) return;
        if (flags & ~kFlagNormalsFlipped) fail("unknown chart flags " + std::to_string(flags));
        flipped.push_back(flags & kFlagNormalsFlipped);
    }
    std::vector<uint64_t> roundBytes(rounds);
    bool tooLong = false;
    for (uint64_t& b : roundBytes) b = r.leb128(tooLong);
    if (tooLong) fail("a level length in the level table is too long");
    std::vector<uint32_t> crcs(rounds);
    for (uint32_t& c : crcs) c = r.u32();
    const size_t covered = r.at;
    const uint32_t tableCrc = r.u32();
    if (r.short_) return;
    if (crc32Of(available.first(covered)) != tableCrc) fail("the level table fails its CRC32 check");
    uint64_t total = r.at;
    for (uint64_t b : roundBytes) total += b;
    if (total != chunkBytes_)
        fail("the level table and its levels take " + std::to_string(total) + " bytes, the chunk holds " +
             std::to_string(chunkBytes_));
    // Only now, with the table intact, the decoders (each holds its whole stored level).
    decoders_.reserve(sizes_.size());
    try {
        for (size_t c = 0; c < sizes_.size(); ++c)
            decoders_.emplace_back(headers[c], sizes_[c], where_ + " of chart " + std::to_string(c), mates_[c]);
    } catch (const Error&) {
        failed_ = true;
        throw;
    }
    flipped_ = std::move(flipped);
    roundCrcs_ = std::move(crcs);
    roundBytes_ = std::move(roundBytes);
    tableBytes_ = nextRoundAt_ = r.at;
}

void ProgressivePositions::advance(std::span<const uint8_t> available)
{
    if (failed_) throw Error(where_ + ": an earlier part failed to decode");
    if (available.size() > chunkBytes_) available = available.first(size_t(chunkBytes_));
    if (!tableRead()) readTable(available);
    if (!tableRead()) return;
    auto fail = [&](const std::string& problem) {
        failed_ = true;
        throw Error(where_ + ", level " + std::to_string(decoded_) + ": " + problem);
    };
    while (decoded_ < roundCount() && roundBytes_[decoded_] <= available.size() - nextRoundAt_) {
        const auto round = available.subspan(size_t(nextRoundAt_), size_t(roundBytes_[decoded_]));
        if (crc32Of(round) != roundCrcs_[decoded_]) fail("fails its CRC32 check");
        size_t at = 0;
        try {
            for (PyramidLevelDecoder& d : decoders_)
                if (d.levelsDecoded() < d.levelCount() && d.levelsDecoded() == decoded_)
                    at += d.decodeLevel(round.subspan(at));
        } catch (const Error&) {
            failed_ = true;
            throw;
        }
        if (at != round.size())
            fail("its streams take " + std::to_string(at) + " of the " + std::to_string(round.size()) +
                 " bytes the table gives it");
        nextRoundAt_ += roundBytes_[decoded_];
        ++decoded_;
    }
}

uint64_t ProgressivePositions::bytesForNextRound() const
{
    if (!tableRead()) {
        // At least: the fixed fields, the chart headers, one-byte lengths, CRCs.
        uint64_t bytes = 2 + 4;
        uint32_t levels = 0;
        for (uint32_t size : sizes_) {
            bytes += 1 + pyramidLevelsHeaderBytes(size);
            levels = std::max(levels, pyramidLevelCount(size));
        }
        return bytes + 5 * uint64_t(levels);
    }
    if (decoded_ == roundCount()) return chunkBytes_;
    return nextRoundAt_ + roundBytes_[decoded_];
}

void finishProgressiveAsset(const AssetLayout& layout, const ProgressivePositions& positions, Asset& a,
                            const std::string& name)
{
    a.coding.pyramid = true;
    a.coding.progressive = true;
    a.coding.normalBits = 0;
    for (uint32_t c = 0; c < a.charts.size(); ++c) {
        AssetChart& chart = a.charts[c];
        const PyramidLevelDecoder& decoder = positions.decoder(c);
        const uint32_t levels = decoder.levelsDecoded();
        if (levels == 0) throw Error(name + ": chart " + std::to_string(c) + " has no decoded level");
        chart.storedLevel += decoder.levelCount() - levels;
        chart.positions = decoder.decodedLevel();
        if (c == 0) {
            a.coding.positionStep = decoder.steps()[levels - 1];
            a.coding.positionTangentScale = decoder.tangentScale();
            a.coding.positionStepGrade = stepGradeOf(std::span(decoder.steps()).first(levels));
        }
        const uint32_t n = chart.storedSize();
        const std::vector<uint32_t> mates = storedMates(chart);
        const AssetChunk* norm = layout.find(kNorm, c, false, name);
        if (norm && norm->present && levels == decoder.levelCount()) {
            const std::string where = name + ": chunk NORM of chart " + std::to_string(c);
            if (norm->encoding != kPredictedNormals)
                throw Error(where + " has encoding " + std::to_string(norm->encoding) +
                            ", format 5 codes normals with 3");
            if (norm->bytes.size() >= 3 && bool(norm->bytes[1] & 1) != positions.normalsFlipped(c))
                throw Error(where + ": its orientation differs from chunk POSI's");
            chart.normals = decodePredictedNormals(norm->bytes, chart.positions, n, where, mates);
            if (c == 0) a.coding.normalBits = norm->bytes[2];
        } else {
            chart.normals = normalsFromPositions(chart.positions, n, positions.normalsFlipped(c), mates);
        }
    }
}

}  // namespace ngi::detail
