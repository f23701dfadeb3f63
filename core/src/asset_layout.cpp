// The .ngi chunk table and description chunks (HEAD, CHRT, META, SEAM), shared by the
// whole-file and the progressive readers. Layout and version history: ngi/asset.h.
#include "asset_format.h"
#include "ngi/color_codec.h"

#include "crc32.h"
#include "ngi/error.h"
#include "ngi/seam.h"

#include <cmath>
#include <cstring>

namespace ngi::detail {

std::string fourccName(uint32_t code)
{
    std::string s;
    for (int i = 0; i < 4; ++i) {
        char c = char((code >> (8 * i)) & 0xff);
        s += (c >= 32 && c < 127) ? c : '?';
    }
    return s;
}

std::string chartProblem(uint32_t fullResolution, uint32_t storedLevel)
{
    if (fullResolution < 1 || fullResolution > kMaxFullResolution || (fullResolution & (fullResolution - 1)))
        return "full resolution " + std::to_string(fullResolution) + " is not a power of two in [1, " +
            std::to_string(kMaxFullResolution) + "]";
    if (storedLevel > 14 || (fullResolution >> storedLevel) < 1)
        return "stored level " + std::to_string(storedLevel) + " is below the 2x2 level of resolution " +
            std::to_string(fullResolution);
    return "";
}

std::vector<uint32_t> storedMates(const AssetChart& chart)
{
    if (!chart.seams.matched) return {};
    const uint32_t level = chart.storedLevel, r = chart.fullResolution >> level, n = r + 1;
    const std::vector<uint32_t> table = seamWeldTable(chart.seams, chart.fullResolution);
    std::vector<uint32_t> mates(size_t(n) * n);
    for (uint32_t i = 0; i < mates.size(); ++i) mates[i] = i;
    const uint32_t mask = (1u << level) - 1;
    for (uint32_t t = 0; t < 4 * r; ++t) {
        const size_t full = size_t(t) << level;
        if (full >= table.size()) break;
        const uint32_t canonical = table[full];
        if ((canonical & mask) || (canonical >> level) >= 4 * r) continue;
        const glm::uvec2 s = perimeterSample(r, t), m = perimeterSample(r, canonical >> level);
        mates[size_t(s.y) * n + s.x] = m.y * n + m.x;
    }
    return mates;
}

const AssetChunk* AssetLayout::find(uint32_t code, uint32_t chart, bool required, const std::string& name) const
{
    for (const AssetChunk& e : chunks)
        if (e.code == code && e.chart == chart) return &e;
    if (required)
        throw Error(name + ": required chunk " + fourccName(code) +
                    (chart ? " of chart " + std::to_string(chart) : "") + " is missing");
    return nullptr;
}

std::optional<AssetLayout> readAssetLayout(std::span<const uint8_t> bytes, const std::string& name, bool prefix)
{
    AssetReader file{bytes, 0, name, "header"};
    const size_t magicBytes = prefix ? std::min<size_t>(bytes.size(), 8) : 8;
    if (bytes.size() < magicBytes || (magicBytes > 0 && std::memcmp(bytes.data(), kAssetMagic, magicBytes) != 0))
        file.fail("not an ngi asset (bad magic bytes)");
    if (prefix && bytes.size() < 12) return std::nullopt;
    file.at = 8;
    AssetLayout layout;
    const uint32_t version = layout.version = file.get<uint32_t>();
    if (version < 1 || version > kAssetFormatVersion)
        file.fail("unsupported asset format version " + std::to_string(version) + " (this build reads versions 1 to " +
                  std::to_string(kAssetFormatVersion) + ")");
    if (prefix && bytes.size() < kAssetHeaderBytes) return std::nullopt;
    const uint32_t chunkCount = file.get<uint32_t>();
    const uint32_t tableCrc = file.get<uint32_t>();
    if (file.get<uint32_t>() != 0) file.fail("reserved header field is not zero");
    if (chunkCount == 0 || chunkCount > kMaxChunks) file.fail("implausible chunk count " + std::to_string(chunkCount));
    if (bytes.size() - kAssetHeaderBytes < size_t(chunkCount) * kChunkEntryBytes) {
        if (prefix) return std::nullopt;
        file.fail("file is truncated (chunk table)");
    }
    const auto tableBytes = bytes.subspan(kAssetHeaderBytes, size_t(chunkCount) * kChunkEntryBytes);
    if (crc32Of(tableBytes) != tableCrc) file.fail("chunk table fails its CRC32 check");
    // Format 6 is 3, 4 or 5 with gains in CHRT: chart 0's POSI encoding says which (a file
    // without one fails below as format 5 does).
    layout.coding = version;
    if (version >= 6) {
        layout.coding = 5;
        AssetReader scan{tableBytes, 0, name, "chunk table"};
        for (uint32_t i = 0; i < chunkCount; ++i) {
            const uint32_t code = scan.get<uint32_t>(), encoding = scan.get<uint32_t>();
            scan.at += 20;  // offset, size, crc
            const uint32_t chart = scan.get<uint32_t>();
            if (code == kPosi && chart == 0) {
                layout.coding = encoding == kProgressivePositions ? 5 : encoding == kPyramid ? 4 : 3;
                break;
            }
        }
    }
    const uint32_t coding = layout.coding;

    // A chunk past the end of the file is only possible in a prefix; there its bounds are
    // bounded by what a file can hold, so that offset + size cannot overflow.
    constexpr uint64_t kMaxFileBytes = uint64_t(1) << 48;
    AssetReader table{tableBytes, 0, name, "chunk table"};
    for (uint32_t i = 0; i < chunkCount; ++i) {
        AssetChunk e;
        e.code = table.get<uint32_t>();
        e.encoding = table.get<uint32_t>();
        e.offset = table.get<uint64_t>();
        e.size = table.get<uint64_t>();
        e.crc = table.get<uint32_t>();
        e.chart = table.get<uint32_t>();
        const bool perChart = (e.code == kPosi && coding <= 4) || e.code == kNorm ||
            (((e.code == kSeam && coding >= 3) || e.code == kBcol) && version < 9);
        if (e.code == kXsem && version < 7)
            file.fail("chunk XSEM needs format 7 (this file is format " + std::to_string(version) + ")");
        if (e.code == kBcol && version < 8)
            file.fail("chunk BCOL needs format 8 (this file is format " + std::to_string(version) + ")");
        if (e.chart != 0 && (version == 1 || !perChart)) file.fail("reserved chunk-table field is not zero");
        const std::string chunk =
            "chunk " + fourccName(e.code) + (perChart && e.chart ? " of chart " + std::to_string(e.chart) : "");
        if (e.offset > kMaxFileBytes || e.size > kMaxFileBytes) file.fail("file is truncated (" + chunk + ")");
        e.present = e.offset <= bytes.size() && e.size <= bytes.size() - e.offset;
        if (!e.present && !prefix) file.fail("file is truncated (" + chunk + ")");
        const uint32_t newest = coding <= 3 ? kPredictedDeflate
            : coding == 4                   ? kPredictedNormals
                                            : kProgressivePositions;
        // BCOL: one WebP image per chart (formats 8), every chart's in one chunk (format 9).
        if (e.code == kBcol && e.encoding != (version >= 9 ? kPackedWebp : kWebp))
            file.fail(chunk + " has encoding " + std::to_string(e.encoding) +
                      (version >= 9 ? " (format 9 packs BCOL with 7)" : " (BCOL is coded with 5: WebP)"));
        // Format 9 packs the description chunks SEAM and XSEM (encoding 6), and nothing else.
        const bool packable = version >= 9 && (e.code == kSeam || e.code == kXsem);
        if (packable != (e.encoding == kPacked))
            file.fail(chunk + " has encoding " + std::to_string(e.encoding) +
                      (packable ? " (format 9 packs SEAM and XSEM with 6)" : ""));
        if (e.code != kBcol && !packable &&
            (e.encoding > newest || (coding >= 5 && (e.encoding == kPredictedDeflate || e.encoding == kPyramid))))
            file.fail(chunk + " has unknown encoding " + std::to_string(e.encoding));
        if (e.present) {
            e.bytes = bytes.subspan(size_t(e.offset), size_t(e.size));
            if (crc32Of(e.bytes) != e.crc) file.fail(chunk + " fails its CRC32 check");
        }
        for (const AssetChunk& other : layout.chunks)
            if (other.code == e.code && other.chart == e.chart) file.fail("duplicate " + chunk);
        layout.fileBytes = std::max(layout.fileBytes, e.end());
        layout.chunks.push_back(e);
    }
    if (coding >= 5) {
        // Streaming order: the description before the positions, the optional rest after them.
        const AssetChunk* posi = layout.find(kPosi, 0, true, name);
        if (posi->encoding != kProgressivePositions)
            file.fail("chunk POSI has encoding " + std::to_string(posi->encoding) + ", format " +
                      std::to_string(version) + " codes positions with 4");
        for (const AssetChunk& e : layout.chunks) {
            if (&e == posi) continue;
            if (e.end() > posi->offset && e.offset < posi->end())
                file.fail("chunk " + fourccName(e.code) + " overlaps chunk POSI");
            const bool before = e.end() <= posi->offset;
            if ((e.code == kHead || e.code == kChrt || e.code == kMeta || e.code == kSeam || e.code == kXsem) != before)
                file.fail("chunk " + fourccName(e.code) + " is " + (before ? "before" : "after") +
                          " chunk POSI (format 5 puts HEAD, CHRT, META, SEAM and XSEM first)");
        }
    }
    return layout;
}

Asset readAssetDescription(const AssetLayout& layout, const std::string& name)
{
    const uint32_t version = layout.version;
    auto fail = [&](const std::string& problem) -> void { throw Error(name + ": " + problem); };
    auto present = [&](uint32_t code, uint32_t chart, bool required) {
        const AssetChunk* e = layout.find(code, chart, required, name);
        if (e && !e->present) fail("chunk " + fourccName(code) + " is truncated");
        return e;
    };
    Asset a;
    const AssetChunk* headEntry = present(kHead, 0, true);
    if (headEntry->encoding != kRaw) fail("chunk HEAD must be stored raw");
    AssetReader head{headEntry->bytes, 0, name, "chunk HEAD"};
    // The chart table: in HEAD for version 1 (one chart), in CHRT for version 2.
    struct ChartEntry {
        uint32_t fullResolution, storedLevel, storedSize;
        float residualGain = 1.0f;
    };
    std::vector<ChartEntry> chartTable;
    if (version == 1) {
        ChartEntry c;
        c.fullResolution = head.get<uint32_t>();
        c.storedLevel = head.get<uint32_t>();
        c.storedSize = head.get<uint32_t>();
        chartTable.push_back(c);
    } else {
        const uint32_t chartCount = head.get<uint32_t>();
        if (chartCount == 0 || chartCount > kMaxCharts)
            fail("chart count " + std::to_string(chartCount) + " is not in [1, " + std::to_string(kMaxCharts) + "]");
        const AssetChunk* chrt = present(kChrt, 0, true);
        if (chrt->encoding != kRaw) fail("chunk CHRT must be stored raw");
        const size_t entryBytes = version >= 6 ? kChartEntryBytesWithGain : kChartEntryBytes;
        if (chrt->bytes.size() != size_t(chartCount) * entryBytes)
            fail("chunk CHRT holds " + std::to_string(chrt->bytes.size()) + " bytes, not the " +
                 std::to_string(chartCount) + " charts HEAD declares");
        AssetReader r{chrt->bytes, 0, name, "chunk CHRT"};
        for (uint32_t c = 0; c < chartCount; ++c) {
            ChartEntry e;
            e.fullResolution = r.get<uint32_t>();
            e.storedLevel = r.get<uint32_t>();
            e.storedSize = r.get<uint32_t>();
            if (version >= 6) e.residualGain = r.get<float>();
            chartTable.push_back(e);
        }
    }
    for (int i = 0; i < 3; ++i) a.offset[i] = head.get<float>();
    for (int i = 0; i < 3; ++i) a.scale[i] = head.get<float>();
    a.sourceHash = head.get<uint64_t>();
    a.networkHash = head.get<uint64_t>();
    a.sourceName = head.getString();
    a.parameterization = head.getString();
    a.networkId = head.getString();
    // Every size is checked against the limits before any sample is allocated.
    uint64_t totalSamples = 0;
    for (size_t c = 0; c < chartTable.size(); ++c) {
        const ChartEntry& e = chartTable[c];
        const std::string where = version == 1 ? std::string() : "chart " + std::to_string(c) + ": ";
        const std::string problem = chartProblem(e.fullResolution, e.storedLevel);
        if (!problem.empty()) fail(where + problem);
        if (!(e.residualGain >= 0.0f && e.residualGain <= 1.0f))
            fail(where + "residual gain " + std::to_string(e.residualGain) + " is not in [0, 1]");
        if (e.storedSize != (e.fullResolution >> e.storedLevel) + 1)
            fail(where + "stored size " + std::to_string(e.storedSize) + " does not match resolution " +
                 std::to_string(e.fullResolution) + " at level " + std::to_string(e.storedLevel));
        totalSamples += uint64_t(e.fullResolution + 1) * (e.fullResolution + 1);
    }
    if (totalSamples > kMaxTotalFullSamples)
        fail("the charts' full images would hold " + std::to_string(totalSamples) +
             " samples, more than the limit of " + std::to_string(kMaxTotalFullSamples));
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(a.offset[i]) || !std::isfinite(a.scale[i]) || !(a.scale[i] > 0.0f))
            fail("de-normalization offset/scale is not finite and positive");

    if (const AssetChunk* meta = present(kMeta, 0, false)) {
        if (meta->encoding != kRaw) fail("chunk META must be stored raw");
        a.metadataJson.assign(reinterpret_cast<const char*>(meta->bytes.data()), meta->bytes.size());
    }
    for (const AssetChunk& e : layout.chunks)
        if ((e.code == kPosi || e.code == kNorm || e.code == kSeam) && e.chart >= chartTable.size())
            fail("chunk " + fourccName(e.code) + " belongs to chart " + std::to_string(e.chart) + " of " +
                 std::to_string(chartTable.size()));
    a.charts.resize(chartTable.size());
    for (uint32_t c = 0; c < chartTable.size(); ++c) {
        AssetChart& chart = a.charts[c];
        chart.fullResolution = chartTable[c].fullResolution;
        chart.storedLevel = chartTable[c].storedLevel;
        chart.residualGain = chartTable[c].residualGain;
        if (version >= 9) continue;  // one packed SEAM for every chart, below
        if (const AssetChunk* e = present(kSeam, c, false)) {
            readLegacySeams(*e, c, chart, name);
            validateSeams(chart.seams, chart.fullResolution, chart.levelCount(), name + ": chart " + std::to_string(c));
        }
    }
    if (version >= 9)
        if (const AssetChunk* e = present(kSeam, 0, false)) {
            unpackSeams(e->bytes, a.charts, name);
            for (uint32_t c = 0; c < a.charts.size(); ++c)
                if (a.charts[c].seams.matched)
                    validateSeams(a.charts[c].seams, a.charts[c].fullResolution, a.charts[c].levelCount(),
                                  name + ": chart " + std::to_string(c));
        }
    if (const AssetChunk* e = present(kXsem, 0, false)) {
        a.crossSeams = version >= 9 ? unpackCrossSeams(e->bytes, a.charts, name) : readLegacyCrossSeams(*e, name);
        std::vector<ChartSeams> seams;
        std::vector<uint32_t> resolutions;
        for (const AssetChart& chart : a.charts)
            seams.push_back(chart.seams), resolutions.push_back(chart.fullResolution);
        validateCrossSeams(a.crossSeams, seams, resolutions, name);
    }
    return a;
}

void readChartColors(const AssetLayout& layout, Asset& a, const std::string& name)
{
    for (const AssetChunk& e : layout.chunks) {
        if (e.code != kBcol) continue;
        if (layout.version >= 9) {  // every chart's colour in one chunk
            if (e.present) unpackColors(e.bytes, a.charts, name);
            continue;
        }
        readLegacyColor(e, a.charts, name);  // format 8: one per chart
    }
}

}  // namespace ngi::detail
