// Format 9's packed chunks (ngi/asset.h): every chart's matched seams in one SEAM chunk and the
// cross seams in XSEM, as LEB128 fields behind zlib, and every chart's base colour in one BCOL.
// Formats 3-8 spend 12 and 20 bytes per segment and one 32-byte chunk-table entry per chart's SEAM
// and BCOL; packed, an asset of 82 charts at 16 KB has 4.6 KB more for its positions
// (docs/FORMAT.md).
#include "asset_format.h"

#include "ngi/color_codec.h"
#include "ngi/error.h"

#include <zlib.h>

#include <cstring>
#include <limits>

namespace ngi::detail {
namespace {

// u32 unpacked bytes, then zlib of them.
std::vector<uint8_t> pack(const std::vector<uint8_t>& fields)
{
    uLongf packed = compressBound(uLong(fields.size()));
    std::vector<uint8_t> out(4 + packed);
    const uint32_t size = uint32_t(fields.size());
    std::memcpy(out.data(), &size, 4);
    if (compress2(out.data() + 4, &packed, fields.data(), uLong(fields.size()), 9) != Z_OK)
        throw Error("asset writer: zlib compression failed");
    out.resize(4 + packed);
    return out;
}

// Reads the LEB128 fields of a packed chunk (or of a chunk's own bytes); every failure names
// the chunk.
struct FieldReader {
    std::vector<uint8_t> unpacked;
    std::span<const uint8_t> fields;
    size_t at = 0;
    std::string where;  // "NAME: chunk SEAM"

    [[noreturn]] void fail(const std::string& problem) const { throw Error(where + " " + problem); }

    // The fields are `bytes` themselves.
    FieldReader(std::span<const uint8_t> bytes, std::string w) : fields(bytes), where(std::move(w)) {}

    // The fields are `bytes` unpacked; `most`: the most unpacked bytes the asset's charts can need.
    FieldReader(std::span<const uint8_t> bytes, std::string w, uint64_t most) : where(std::move(w))
    {
        if (bytes.size() < 4) fail("is truncated (no unpacked size)");
        uint32_t size = 0;
        std::memcpy(&size, bytes.data(), 4);
        // Deflate expands at most ~1032:1: a larger declared size is refused before allocating.
        if (uint64_t(size) > (uint64_t(bytes.size()) - 4) * 1032 + 64)
            fail("declares " + std::to_string(size) + " unpacked bytes, more than its " +
                 std::to_string(bytes.size() - 4) + " packed bytes can hold");
        if (size > most)
            fail("declares " + std::to_string(size) + " unpacked bytes, more than the charts' borders need (" +
                 std::to_string(most) + ")");
        unpacked.resize(size);
        uLongf length = uLongf(size);
        const int rc = uncompress(unpacked.data(), &length, bytes.data() + 4, uLong(bytes.size() - 4));
        if (rc != Z_OK || length != size) fail("does not unpack to the " + std::to_string(size) + " bytes it declares");
        fields = unpacked;
    }
    uint32_t next(const char* what)
    {
        uint64_t v = 0;
        for (int i = 0; i < 5; ++i) {
            if (at >= fields.size()) fail(std::string("ends inside ") + what);
            const uint8_t b = fields[at++];
            v |= uint64_t(b & 0x7f) << (7 * i);
            if (!(b & 0x80)) {
                if (v > std::numeric_limits<uint32_t>::max()) break;
                return uint32_t(v);
            }
        }
        fail(std::string("has ") + what + " above 2^32");
    }
    // A count of items of at least `minBytes` unpacked bytes each: bounded by what is left.
    uint32_t count(const char* what, size_t minBytes)
    {
        const uint32_t n = next(what);
        if (uint64_t(n) * minBytes > fields.size() - at)
            fail("declares " + std::to_string(n) + " " + what + ", more than its bytes hold");
        return n;
    }
    // The next n bytes as they are.
    std::span<const uint8_t> take(uint32_t n, const char* what)
    {
        if (n > fields.size() - at) fail(std::string("ends inside ") + what);
        const std::span<const uint8_t> out = fields.subspan(at, n);
        at += n;
        return out;
    }
    void finish() const
    {
        if (at != fields.size()) fail("has " + std::to_string(fields.size() - at) + " bytes past its last field");
    }
};

// The most LEB128 bytes a chart's border can need: a segment per border sample of the full
// resolution, each of at most three 5-byte fields (a generous bound; it only caps allocation).
uint64_t borderFieldBytes(const std::vector<AssetChart>& charts, uint64_t fieldsPerSegment)
{
    uint64_t most = 5;
    for (const AssetChart& chart : charts) most += 10 + 4 * uint64_t(chart.fullResolution) * fieldsPerSegment * 5;
    return most;
}

}  // namespace

std::vector<uint8_t> packSeams(const std::vector<AssetChart>& charts)
{
    std::vector<uint8_t> fields;
    for (const AssetChart& chart : charts) {
        if (!chart.seams.matched) {
            putLeb128(fields, 0);
            continue;
        }
        putLeb128(fields, uint64_t(chart.seams.coarsestWatertightLevel) + 1);
        putLeb128(fields, chart.seams.segments.size());
        for (const SeamSegment& s : chart.seams.segments) {
            putLeb128(fields, s.a);
            putLeb128(fields, s.b);
            putLeb128(fields, s.length);
        }
    }
    return pack(fields);
}

void unpackSeams(std::span<const uint8_t> bytes, std::vector<AssetChart>& charts, const std::string& name)
{
    FieldReader r(bytes, name + ": chunk SEAM", borderFieldBytes(charts, 3));
    for (AssetChart& chart : charts) {
        const uint32_t m = r.next("a chart's seam header");
        chart.seams = ChartSeams{};
        if (m == 0) continue;
        chart.seams.matched = true;
        chart.seams.coarsestWatertightLevel = m - 1;
        chart.seams.segments.resize(r.count("seam segments", 3));
        for (SeamSegment& s : chart.seams.segments) {
            s.a = r.next("a seam segment");
            s.b = r.next("a seam segment");
            s.length = r.next("a seam segment");
        }
    }
    r.finish();
}

std::vector<uint8_t> packCrossSeams(const std::vector<CrossSeamSegment>& segments)
{
    std::vector<uint8_t> fields;
    putLeb128(fields, segments.size());
    for (const CrossSeamSegment& s : segments)
        for (uint32_t v : {s.chartA, s.a, s.chartB, s.b, s.length}) putLeb128(fields, v);
    return pack(fields);
}

std::vector<CrossSeamSegment> unpackCrossSeams(std::span<const uint8_t> bytes, const std::vector<AssetChart>& charts,
                                               const std::string& name)
{
    FieldReader r(bytes, name + ": chunk XSEM", borderFieldBytes(charts, 5));
    std::vector<CrossSeamSegment> segments(r.count("cross seams", 5));
    for (CrossSeamSegment& s : segments) {
        s.chartA = r.next("a cross seam");
        s.a = r.next("a cross seam");
        s.chartB = r.next("a cross seam");
        s.b = r.next("a cross seam");
        s.length = r.next("a cross seam");
    }
    r.finish();
    return segments;
}

std::vector<uint8_t> packColors(const std::vector<AssetChart>& charts, uint32_t quality, const std::string& name)
{
    std::vector<uint8_t> out;
    for (size_t c = 0; c < charts.size(); ++c) {
        const AssetChart& chart = charts[c];
        if (chart.baseColor.empty()) {
            putLeb128(out, 0);
            continue;
        }
        putLeb128(out, uint64_t(chart.baseColorLevel) + 1);
        const std::vector<uint8_t> image =
            encodeColorImage(chart.baseColor, chart.baseColorSize(), quality, name + ": chart " + std::to_string(c));
        putLeb128(out, image.size());
        out.insert(out.end(), image.begin(), image.end());
    }
    return out;
}

void unpackColors(std::span<const uint8_t> bytes, std::vector<AssetChart>& charts, const std::string& name)
{
    FieldReader r(bytes, name + ": chunk BCOL");
    for (size_t c = 0; c < charts.size(); ++c) {
        AssetChart& chart = charts[c];
        const uint32_t m = r.next("a chart's colour header");
        if (m == 0) continue;
        if (m - 1 >= chart.levelCount())
            r.fail("gives chart " + std::to_string(c) + " colour level " + std::to_string(m - 1) + ", not one of its " +
                   std::to_string(chart.levelCount()) + " levels");
        chart.baseColorLevel = m - 1;
        const std::span<const uint8_t> image = r.take(r.next("a colour image's length"), "a colour image");
        chart.baseColor = decodeColorImage(image, chart.baseColorSize(), r.where + " of chart " + std::to_string(c));
    }
    r.finish();
}

}  // namespace ngi::detail
