// ngi core (private): the pieces of the .ngi layout (ngi/asset.h) that the whole-file reader
// (asset.cpp), the progressive reader (asset_prefix.cpp) and the format-5 position stream
// (asset_progressive.cpp) share: constants, the chunk table, the description chunks (HEAD,
// CHRT, META, SEAM) and the seam mates of a stored level.
#pragma once

#include "byte_stream.h"
#include "ngi/asset.h"
#include "ngi/pyramid_codec.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ngi::detail {

inline constexpr uint8_t kAssetMagic[8] = {0x89, 'N', 'G', 'I', '\r', '\n', 0x1a, '\n'};
inline constexpr size_t kAssetHeaderBytes = 24;
inline constexpr size_t kChunkEntryBytes = 32;
inline constexpr uint32_t kMaxChunks = 4 * kMaxCharts + 9;  // HEAD CHRT META WGHT XSEM + POSI/NORM/SEAM/BCOL per chart
inline constexpr size_t kChartEntryBytes = 12;              // formats 2-5
inline constexpr size_t kChartEntryBytesWithGain = 16;      // format 6: + f32 residual gain
inline constexpr size_t kMaxAssetString = 65536;

// Chunk encodings (the table's u32 encoding field).
enum ChunkEncoding : uint32_t {
    kRaw = 0,
    kPredictedDeflate = 1,      // zlib of parallelogram-predicted u16 samples (formats 1-3)
    kPyramid = 2,               // POSI of one chart, one stream (format 4, pyramid codec 1)
    kPredictedNormals = 3,      // NORM predicted from the decoded positions (formats 4, 5)
    kProgressivePositions = 4,  // the one POSI of format 5: every chart, level by level
    kWebp = 5,                  // BCOL (format 8): u32 level + one WebP image (color_codec.h)
    kPacked = 6,                // SEAM and XSEM of format 9: u32 unpacked bytes, zlib of LEB128 fields
    kPackedWebp = 7             // the one BCOL of format 9: per chart LEB128 fields and a WebP image
};

constexpr uint32_t fourcc(const char (&s)[5])
{
    return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
        uint32_t(uint8_t(s[3])) << 24;
}
inline constexpr uint32_t kHead = fourcc("HEAD"), kMeta = fourcc("META"), kPosi = fourcc("POSI"),
                          kNorm = fourcc("NORM"), kWght = fourcc("WGHT"), kChrt = fourcc("CHRT"),
                          kSeam = fourcc("SEAM"), kXsem = fourcc("XSEM"), kBcol = fourcc("BCOL");

std::string fourccName(uint32_t code);

// The asset reader names the part being read ("header", "chunk HEAD", ...) in its errors.
struct AssetReader : ByteReader {
    const char* what;
    AssetReader(std::span<const uint8_t> b, size_t offset, const std::string& n, const char* w)
        : ByteReader{b, offset, n}, what(w)
    {}
    template <class T> T get() { return ByteReader::get<T>(what); }
    std::string getString() { return ByteReader::getString((std::string(what) + " string").c_str(), kMaxAssetString); }
};

struct AssetChunk {
    uint32_t code = 0, encoding = 0, chart = 0;
    uint64_t offset = 0, size = 0;
    uint32_t crc = 0;
    bool present = false;            // wholly inside the bytes read (and its CRC checked)
    std::span<const uint8_t> bytes;  // the payload when present
    uint64_t end() const { return offset + size; }
};

struct AssetLayout {
    uint32_t version = 0;
    // The version whose layout rules the file follows: `version`, except for format 6, which
    // follows 3, 4 or 5 as its chart 0 POSI's encoding tells (1: 3, 2: 4, 4: 5; ngi/asset.h).
    uint32_t coding = 0;
    std::vector<AssetChunk> chunks;  // in table order
    uint64_t fileBytes = 0;          // the end of the chunk that ends last
    // The chunk (code, chart), or null; with `required` an ngi::Error naming it when missing.
    const AssetChunk* find(uint32_t code, uint32_t chart, bool required, const std::string& name) const;
};

// Reads the header and the chunk table and checks every chunk's bounds, encoding and CRC.
// Whole file (prefix false): every chunk must lie inside `bytes`; ngi::Error otherwise.
// Prefix: returns nullopt while `bytes` ends before the table does (after checking the magic
// and version it has); a chunk that ends past `bytes` is kept with present = false (its CRC
// unchecked; the caller decides what a missing chunk means: format 5 streams, the others
// need the whole file). Format 5 (and 6 with a format-5 POSI; layout.coding says which rules apply) (both modes): one POSI (chart 0, encoding 4), HEAD, CHRT,
// META and SEAM wholly before it, every other chunk wholly after it.
std::optional<AssetLayout> readAssetLayout(std::span<const uint8_t> bytes, const std::string& name, bool prefix);

// HEAD, CHRT, META and SEAM (which must be present) into an asset whose charts have their
// sizes and seams but no samples yet, every size checked against the limits.
Asset readAssetDescription(const AssetLayout& layout, const std::string& name);

// The seam mate classes of a chart's stored level for the pyramid coder: for each stored
// sample the stored index of its canonical mate (seamWeldTable), or its own index. Empty
// without a matched seam. Mates whose canonical is not a stored sample (a stored level
// coarser than the watertight level) are left alone.
std::vector<uint32_t> storedMates(const AssetChart& chart);

// The limits of one chart's resolution and level; "" if they hold, else the problem.
std::string chartProblem(uint32_t fullResolution, uint32_t storedLevel);

// The charts' base colours from their BCOL chunks (format 8; the one of format 9), each checked and decoded; a chunk
// not present (a prefix that ends before it) leaves its chart without colour. ngi::Error
// naming the chunk on anything malformed.
void readChartColors(const AssetLayout& layout, Asset& a, const std::string& name);

// Both writers: serializeAsset (legacy false: format 9) and serializeLegacyAsset (the oldest
// of formats 3-8 that holds the asset, with the chunk codings below).
std::vector<uint8_t> writeAsset(const Asset& a, bool legacy);

// ---- The chunk codings of formats 3-8 that format 9 replaced (asset_legacy.cpp) ----

// The version serializeLegacyAsset gives `a` (ngi/asset_legacy.h).
uint32_t legacyVersion(const Asset& a);
// Formats 3-8: one raw SEAM chunk per chart with a matched seam: u32 coarsest watertight
// level, u32 segment count, count x {u32 a, u32 b, u32 length}.
std::vector<uint8_t> writeLegacySeams(const ChartSeams& seams);
// Into `chart` (its seams, not yet validated). ngi::Error naming the chunk if it is not raw or
// its size is not what its count declares.
void readLegacySeams(const AssetChunk& chunk, uint32_t chartIndex, AssetChart& chart, const std::string& name);
// Formats 7 and 8: the raw XSEM chunk: u32 count, count x {chartA, a, chartB, b, length}.
std::vector<uint8_t> writeLegacyCrossSeams(const std::vector<CrossSeamSegment>& segments);
std::vector<CrossSeamSegment> readLegacyCrossSeams(const AssetChunk& chunk, const std::string& name);
// Format 8: one BCOL chunk per coloured chart (encoding 5): u32 level, then one WebP image at
// `quality`. `where` names the chart in encoder errors.
std::vector<uint8_t> writeLegacyColor(const AssetChart& chart, uint32_t quality, const std::string& where);
// Into charts[chunk.chart] (a chunk not present leaves it without colour). ngi::Error naming
// the chunk on a chart or level the asset does not have, or an image that does not decode.
void readLegacyColor(const AssetChunk& chunk, std::vector<AssetChart>& charts, const std::string& name);

// ---- Format 9's packed description chunks (encoding 6; asset_packed.cpp) ----

// Every chart's matched seams in one chunk: per chart LEB128 m (0: no matched seam, else 1 +
// its coarsest watertight level), then where m > 0 the segment count and each segment's a, b
// and length; the whole as u32 unpacked bytes + zlib of them.
std::vector<uint8_t> packSeams(const std::vector<AssetChart>& charts);
// Into `charts` (sized already): each chart's seams.matched, coarsestWatertightLevel and
// segments. ngi::Error "NAME: chunk SEAM ..." on a malformed chunk (bad zlib stream, unpacked size
// other than declared or more than the charts' borders can need, a field past the end or above
// 2^32, bytes left over). The segments are not validated (validateSeams does that).
void unpackSeams(std::span<const uint8_t> bytes, std::vector<AssetChart>& charts, const std::string& name);

// The cross seams: LEB128 count, then each segment's chartA, a, chartB, b and length; packed as
// packSeams packs.
std::vector<uint8_t> packCrossSeams(const std::vector<CrossSeamSegment>& segments);
// `charts` (their resolutions) bound the unpacked size.
std::vector<CrossSeamSegment> unpackCrossSeams(std::span<const uint8_t> bytes, const std::vector<AssetChart>& charts,
                                               const std::string& name);

// Every chart's base colour in one chunk (encoding 7): per chart LEB128 m (0: no colour, else
// 1 + its colour level), then where m > 0 LEB128 n and n bytes of one WebP image (color_codec.h)
// at `quality`. `name` names the asset in encoder errors.
std::vector<uint8_t> packColors(const std::vector<AssetChart>& charts, uint32_t quality, const std::string& name);
// Into `charts` (sized, with their resolutions): each chart's baseColorLevel and decoded
// baseColor. ngi::Error "NAME: chunk BCOL ..." on a malformed chunk (a field past the end or
// above 2^32, a level the chart does not have, an image that does not decode to the chart's
// colour size, bytes left over).
void unpackColors(std::span<const uint8_t> bytes, std::vector<AssetChart>& charts, const std::string& name);

// ---- Format 5's POSI chunk (encoding 4; asset_progressive.cpp) ----

// Every chart's PyramidLevels (encodePyramidLevels) and normal orientation, into the chunk.
std::vector<uint8_t> encodeProgressivePositions(const std::vector<PyramidLevels>& charts,
                                                const std::vector<bool>& normalsFlipped);

// Decodes format 5's POSI chunk as its bytes arrive, round by round (round r holds level r of
// every chart that has more than r levels). `description` gives the charts' stored sizes and
// seams (readAssetDescription); the decoder keeps no reference to it.
class ProgressivePositions {
public:
    ProgressivePositions(const Asset& description, std::string where, uint64_t chunkBytes);

    // `available`: the chunk's first bytes (all of it for a whole file). Parses the level
    // table once it is complete, then decodes every round wholly inside `available` that is
    // not decoded yet, checking its CRC and length. ngi::Error "WHERE: problem" on anything
    // malformed; after one the decoder is unusable.
    void advance(std::span<const uint8_t> available);

    bool tableRead() const { return !roundBytes_.empty(); }
    uint32_t roundCount() const { return uint32_t(roundBytes_.size()); }
    uint32_t roundsDecoded() const { return decoded_; }
    // Bytes of the chunk needed to decode one more round (the table first); the chunk's size
    // once every round is decoded.
    uint64_t bytesForNextRound() const;
    // Bytes of the chunk the decoded rounds end at (0 before the table is read).
    uint64_t decodedBytes() const { return nextRoundAt_; }
    // Chart c's finest decoded level: its samples (stored size of the decoded levels), the
    // number of levels decoded, its normal orientation, its steps.
    std::vector<uint16_t> positions(size_t c) const { return decoders_.at(c).decodedLevel(); }
    uint32_t chartLevelsDecoded(size_t c) const { return decoders_.at(c).levelsDecoded(); }
    bool normalsFlipped(size_t c) const { return flipped_.at(c); }
    const PyramidLevelDecoder& decoder(size_t c) const { return decoders_.at(c); }

private:
    void readTable(std::span<const uint8_t> available);

    std::string where_;
    uint64_t chunkBytes_;
    std::vector<uint32_t> sizes_;                // stored size per chart
    std::vector<std::vector<uint32_t>> mates_;   // per chart (the decoders hold spans into them)
    std::vector<PyramidLevelDecoder> decoders_;  // once the table is read
    std::vector<bool> flipped_;
    std::vector<uint64_t> roundBytes_;  // per round, once the table is read
    std::vector<uint32_t> roundCrcs_;
    uint64_t tableBytes_ = 0, nextRoundAt_ = 0;  // chunk offsets
    uint32_t decoded_ = 0;
    bool failed_ = false;
};

// Fills the charts of `a` (readAssetDescription's) from what `positions` decoded: each chart
// at its finest decoded level (storedLevel coarser where not every level is decoded), its
// normals from its NORM chunk where that is present and the chart complete, else predicted
// from the positions (the prediction's orientation from POSI, seam mates of that level
// copied); and a.coding as the file codes it.
void finishProgressiveAsset(const AssetLayout& layout, const ProgressivePositions& positions, Asset& a,
                            const std::string& name);

}  // namespace ngi::detail
