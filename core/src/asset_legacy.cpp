// The chunk codings of asset formats 3-8 that format 9 replaced (ngi/asset.h's version history):
// a raw SEAM chunk per chart, a raw XSEM chunk and a WebP BCOL chunk per chart, and the writer
// of those formats (ngi/asset_legacy.h). The readers of every format call these for files
// older than 9; ngi itself writes only format 9.
#include "ngi/asset_legacy.h"

#include "asset_format.h"
#include "ngi/color_codec.h"
#include "ngi/error.h"

namespace ngi {

std::vector<uint8_t> serializeLegacyAsset(const Asset& asset) { return detail::writeAsset(asset, true); }

namespace detail {

uint32_t legacyVersion(const Asset& a)
{
    bool gains = false, colors = false;
    for (const AssetChart& c : a.charts) {
        gains |= c.residualGain != 1.0f;
        colors |= !c.baseColor.empty();
    }
    return colors                                  ? 8u
        : !a.crossSeams.empty()                    ? 7u
        : gains                                    ? 6u
        : a.coding.pyramid && a.coding.progressive ? 5u
        : a.coding.pyramid                         ? 4u
                                                   : 3u;
}

std::vector<uint8_t> writeLegacySeams(const ChartSeams& seams)
{
    ByteWriter out;
    out.put<uint32_t>(seams.coarsestWatertightLevel);
    out.put<uint32_t>(uint32_t(seams.segments.size()));
    for (const SeamSegment& s : seams.segments) {
        out.put<uint32_t>(s.a);
        out.put<uint32_t>(s.b);
        out.put<uint32_t>(s.length);
    }
    return std::move(out.bytes);
}

void readLegacySeams(const AssetChunk& chunk, uint32_t chartIndex, AssetChart& chart, const std::string& name)
{
    const std::string what = "chunk SEAM of chart " + std::to_string(chartIndex);
    AssetReader r{chunk.bytes, 0, name, what.c_str()};
    if (chunk.encoding != kRaw) r.fail(what + " must be stored raw");
    chart.seams.matched = true;
    chart.seams.coarsestWatertightLevel = r.get<uint32_t>();
    const uint32_t count = r.get<uint32_t>();
    if (chunk.bytes.size() != 8 + size_t(count) * 12)
        r.fail(what + " holds " + std::to_string(chunk.bytes.size()) + " bytes, not the " + std::to_string(count) +
               " segments it declares");
    chart.seams.segments.resize(count);  // bounded: 12 bytes of the file each
    for (SeamSegment& s : chart.seams.segments) {
        s.a = r.get<uint32_t>();
        s.b = r.get<uint32_t>();
        s.length = r.get<uint32_t>();
    }
}

std::vector<uint8_t> writeLegacyCrossSeams(const std::vector<CrossSeamSegment>& segments)
{
    ByteWriter out;
    out.put<uint32_t>(uint32_t(segments.size()));
    for (const CrossSeamSegment& s : segments)
        for (uint32_t v : {s.chartA, s.a, s.chartB, s.b, s.length}) out.put<uint32_t>(v);
    return std::move(out.bytes);
}

std::vector<CrossSeamSegment> readLegacyCrossSeams(const AssetChunk& chunk, const std::string& name)
{
    AssetReader r{chunk.bytes, 0, name, "chunk XSEM"};
    if (chunk.encoding != kRaw) r.fail("chunk XSEM must be stored raw");
    const uint32_t count = r.get<uint32_t>();
    if (chunk.bytes.size() != 4 + size_t(count) * 20)
        r.fail("chunk XSEM holds " + std::to_string(chunk.bytes.size()) + " bytes, not the " + std::to_string(count) +
               " cross seams it declares");
    std::vector<CrossSeamSegment> segments(count);  // bounded: 20 bytes of the file each
    for (CrossSeamSegment& s : segments) {
        s.chartA = r.get<uint32_t>();
        s.a = r.get<uint32_t>();
        s.chartB = r.get<uint32_t>();
        s.b = r.get<uint32_t>();
        s.length = r.get<uint32_t>();
    }
    return segments;
}

std::vector<uint8_t> writeLegacyColor(const AssetChart& chart, uint32_t quality, const std::string& where)
{
    ByteWriter out;
    out.put<uint32_t>(chart.baseColorLevel);
    const std::vector<uint8_t> image = encodeColorImage(chart.baseColor, chart.baseColorSize(), quality, where);
    out.bytes.insert(out.bytes.end(), image.begin(), image.end());
    return std::move(out.bytes);
}

void readLegacyColor(const AssetChunk& chunk, std::vector<AssetChart>& charts, const std::string& name)
{
    const std::string where = name + ": chunk BCOL of chart " + std::to_string(chunk.chart);
    if (chunk.chart >= charts.size())
        throw Error(where + ": the asset has " + std::to_string(charts.size()) + " charts");
    if (!chunk.present) return;
    AssetChart& chart = charts[chunk.chart];
    AssetReader r{chunk.bytes, 0, where, "its level"};
    const uint32_t level = r.get<uint32_t>();
    if (level >= chart.levelCount())
        throw Error(where + ": colour level " + std::to_string(level) + " is not one of the chart's " +
                    std::to_string(chart.levelCount()) + " levels");
    chart.baseColorLevel = level;
    chart.baseColor = decodeColorImage(chunk.bytes.subspan(4), chart.baseColorSize(), where);
}

}  // namespace detail
}  // namespace ngi
