// The .ngi asset file: writer and validating reader.
// Layout and version history are documented in ngi/asset.h.
#include "ngi/asset.h"

#include "byte_stream.h"
#include "crc32.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/pyramid_codec.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

static_assert(std::endian::native == std::endian::little, "ngi assets are little-endian");

namespace ngi {
namespace {

constexpr uint8_t kMagic[8] = {0x89, 'N', 'G', 'I', '\r', '\n', 0x1a, '\n'};
constexpr size_t kHeaderBytes = 24;
constexpr size_t kTableEntryBytes = 32;
constexpr uint32_t kMaxChunks = 3 * kMaxCharts + 8;  // HEAD CHRT META WGHT + POSI/NORM/SEAM per chart
constexpr size_t kChartEntryBytes = 12;
constexpr size_t kMaxString = 65536;

enum Encoding : uint32_t { kRaw = 0, kPredictedDeflate = 1, kPyramid = 2, kPredictedNormals = 3 };

constexpr uint32_t fourcc(const char (&s)[5])
{
    return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
           uint32_t(uint8_t(s[3])) << 24;
}
constexpr uint32_t kHead = fourcc("HEAD"), kMeta = fourcc("META"), kPosi = fourcc("POSI"),
                   kNorm = fourcc("NORM"), kWght = fourcc("WGHT"), kChrt = fourcc("CHRT"),
                   kSeam = fourcc("SEAM");

std::string fourccName(uint32_t code)
{
    std::string s;
    for (int i = 0; i < 4; ++i) {
        char c = char((code >> (8 * i)) & 0xff);
        s += (c >= 32 && c < 127) ? c : '?';
    }
    return s;
}

using detail::crc32Of;

using Writer = detail::ByteWriter;

// The asset reader names the part being read ("header", "chunk HEAD", ...) in its errors.
struct Reader : detail::ByteReader {
    const char* what;
    Reader(std::span<const uint8_t> b, size_t offset, const std::string& n, const char* w)
        : ByteReader{b, offset, n}, what(w) {}
    template <class T> T get() { return ByteReader::get<T>(what); }
    std::string getString() { return ByteReader::getString((std::string(what) + " string").c_str(), kMaxString); }
};

// Parallelogram prediction + zlib for 16-bit geometry images: a smooth surface sampled on a
// grid is locally close to a plane, so left + up - upleft predicts each sample well. The
// residuals are zigzag-mapped (small magnitudes -> small codes) and split into low and high
// byte planes, which deflate well. `rowSamples` = samples per image row (width * 3).
uint16_t predictSample(const uint16_t* s, size_t i, size_t rowSamples)
{
    const size_t x = i % rowSamples;
    const bool left = x >= 3, up = i >= rowSamples;
    if (left && up) return uint16_t(s[i - 3] + s[i - rowSamples] - s[i - rowSamples - 3]);
    if (left) return s[i - 3];
    if (up) return s[i - rowSamples];
    return 0;
}

uint16_t zigzag(uint16_t d) { return uint16_t((d << 1) ^ (int16_t(d) >> 15)); }
uint16_t unzigzag(uint16_t z) { return uint16_t((z >> 1) ^ uint16_t(-(z & 1))); }

std::vector<uint8_t> encodeSamples(const std::vector<uint16_t>& samples, uint32_t rowSamples)
{
    const size_t n = samples.size();
    std::vector<uint8_t> planes(n * 2);
    for (size_t i = 0; i < n; ++i) {
        const uint16_t z = zigzag(uint16_t(samples[i] - predictSample(samples.data(), i, rowSamples)));
        planes[i] = uint8_t(z & 0xff);
        planes[n + i] = uint8_t(z >> 8);
    }
    uLongf packed = compressBound(uLong(planes.size()));
    std::vector<uint8_t> out(packed);
    if (compress2(out.data(), &packed, planes.data(), uLong(planes.size()), 9) != Z_OK)
        throw Error("asset writer: zlib compression failed");
    out.resize(packed);
    return out;
}

std::vector<uint16_t> decodeSamples(std::span<const uint8_t> stored, size_t count, uint32_t rowSamples,
                                    const Reader& r)
{
    // Deflate expands at most ~1032:1: a smaller payload cannot hold the declared samples,
    // so it is refused before the planes are allocated.
    if (uint64_t(stored.size()) * 1032 + 64 < uint64_t(count) * 2)
        r.fail(std::string(r.what) + " is too small for the samples its header declares");
    std::vector<uint8_t> planes(count * 2);
    uLongf rawBytes = uLongf(planes.size());
    const int rc = uncompress(planes.data(), &rawBytes, stored.data(), uLong(stored.size()));
    if (rc != Z_OK || rawBytes != planes.size())
        r.fail(std::string(r.what) + " does not decompress to the size its header declares");
    std::vector<uint16_t> samples(count);
    for (size_t i = 0; i < count; ++i)
        samples[i] = uint16_t(predictSample(samples.data(), i, rowSamples) +
                              unzigzag(uint16_t(planes[i] | (planes[count + i] << 8))));
    return samples;
}

// The seam mate classes of a chart's stored level for the pyramid coder: for each stored
// sample the stored index of its canonical mate (seamWeldTable), or its own index. Empty
// without a matched seam. Mates whose canonical is not a stored sample (a stored level
// coarser than the watertight level) are left alone.
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

// One chart's stored level through the pyramid coder: the payloads and what a reader decodes.
struct CodedChart {
    std::vector<uint8_t> positionBytes, normalBytes;
    std::vector<uint16_t> positions, normals;
};

CodedChart codeChart(const AssetChart& chart, const AssetCoding& coding)
{
    CodedChart out;
    const uint32_t n = chart.storedSize();
    const std::vector<uint32_t> mates = storedMates(chart);
    PyramidCodecOptions options{.step = coding.positionStep, .tangentScale = coding.positionTangentScale};
    options.mates = mates;
    out.positionBytes = encodePyramidPositions(chart.positions, n, options);
    out.positions = decodePyramidPositions(out.positionBytes, n, "asset writer", mates);
    out.normalBytes = encodePredictedNormals(out.positions, chart.normals, n, coding.normalBits, mates);
    out.normals = decodePredictedNormals(out.normalBytes, out.positions, n, "asset writer", mates);
    return out;
}

// The limits of one chart's resolution and level; "" if they hold, else the problem.
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

void checkFields(const Asset& a, const std::string& where)
{
    auto fail = [&](const std::string& p) { throw Error(where + ": " + p); };
    if (a.charts.empty()) fail("the asset has no chart");
    if (a.charts.size() > kMaxCharts)
        fail(std::to_string(a.charts.size()) + " charts exceed the limit of " + std::to_string(kMaxCharts));
    uint64_t totalSamples = 0;
    for (size_t c = 0; c < a.charts.size(); ++c) {
        const AssetChart& chart = a.charts[c];
        const std::string problem = chartProblem(chart.fullResolution, chart.storedLevel);
        if (!problem.empty()) fail("chart " + std::to_string(c) + ": " + problem);
        totalSamples += uint64_t(chart.fullSize()) * chart.fullSize();
        const size_t expect = size_t(chart.storedSize()) * chart.storedSize() * 3;
        if (chart.positions.size() != expect) fail("chart " + std::to_string(c) + ": position level has the wrong number of samples");
        if (chart.normals.size() != expect) fail("chart " + std::to_string(c) + ": normal level has the wrong number of samples");
        if (chart.seams.matched) validateSeams(chart.seams, chart.fullResolution, chart.levelCount(), where + ": chart " + std::to_string(c));
    }
    if (totalSamples > kMaxTotalFullSamples) fail("the charts' full images exceed " + std::to_string(kMaxTotalFullSamples) + " samples");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(a.offset[i]) || !std::isfinite(a.scale[i]) || !(a.scale[i] > 0.0f))
            fail("de-normalization offset/scale is not finite and positive");
    for (const std::string* s : {&a.sourceName, &a.parameterization, &a.networkId, &a.metadataJson})
        if (s->size() > kMaxString * 64) fail("a metadata string is too long");
    for (const std::string* s : {&a.sourceName, &a.parameterization, &a.networkId})
        if (s->size() > kMaxString) fail("a header string is longer than 64 KiB");
    if (a.coding.pyramid && (a.coding.positionStep < 1 || a.coding.positionStep > kMaxPyramidStep || a.coding.normalBits > 16))
        fail("coding: position step " + std::to_string(a.coding.positionStep) + " or " + std::to_string(a.coding.normalBits) +
             " normal bits outside [1, " + std::to_string(kMaxPyramidStep) + "] / [0, 16]");
}

} // namespace

uint32_t AssetChart::levelCount() const
{
    return isNestedGridSize(fullSize()) ? mipLevelCount(fullSize()) : 1;
}

uint32_t AssetChart::coarsestDrawnLevel() const
{
    return ngi::coarsestDrawnLevel(seams, levelCount());
}

uint32_t Asset::fullResolution() const
{
    uint32_t r = 0;
    for (const AssetChart& c : charts) r = std::max(r, c.fullResolution);
    return r;
}

int chartLevelForAssetLevel(const Asset& asset, const AssetChart& chart, int assetLevel)
{
    const int offset = std::countr_zero(asset.fullResolution()) - std::countr_zero(chart.fullResolution);
    return assetLevel - offset;
}

void storeGeometryImage(AssetChart& chart, const GeometryImage& positions, const GeometryImage& normals)
{
    const uint32_t n = chart.storedSize();
    if (positions.size != n || normals.size != n)
        throw Error("asset: stored level must have " + std::to_string(n) + " samples per side");
    auto quantize = [](float v) { return uint16_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f)); };
    chart.positions.resize(size_t(n) * n * 3);
    chart.normals.resize(size_t(n) * n * 3);
    for (size_t i = 0; i < positions.texels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float p = positions.texels[i][c], q = normals.texels[i][c];
            chart.positions[i * 3 + c] = quantize(std::isfinite(p) ? p : 0.0f);
            chart.normals[i * 3 + c] = quantize(std::isfinite(q) ? q * 0.5f + 0.5f : 0.5f);
        }
}

GeometryImage storedPositions(const AssetChart& chart)
{
    GeometryImage image(chart.storedSize());
    for (size_t i = 0; i < image.texels.size() && i * 3 + 2 < chart.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) image.texels[i][c] = chart.positions[i * 3 + c] / 65535.0f;
    return image;
}

GeometryImage storedNormals(const AssetChart& chart)
{
    GeometryImage image(chart.storedSize());
    for (size_t i = 0; i < image.texels.size() && i * 3 + 2 < chart.normals.size(); ++i) {
        glm::vec3 n;
        for (int c = 0; c < 3; ++c) n[c] = chart.normals[i * 3 + c] / 65535.0f * 2.0f - 1.0f;
        const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        image.texels[i] = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
    }
    return image;
}

void applyAssetCoding(Asset& asset)
{
    if (!asset.coding.pyramid) return;
    checkFields(asset, asset.sourceName.empty() ? "asset" : asset.sourceName);
    for (AssetChart& chart : asset.charts) {
        CodedChart coded = codeChart(chart, asset.coding);
        chart.positions = std::move(coded.positions);
        chart.normals = std::move(coded.normals);
    }
}

std::vector<uint8_t> serializeAsset(const Asset& a)
{
    checkFields(a, a.sourceName.empty() ? "asset" : a.sourceName);

    struct Chunk { uint32_t code; uint32_t encoding; std::vector<uint8_t> bytes; uint32_t chart = 0; };
    std::vector<Chunk> chunks;

    Writer head;
    head.put<uint32_t>(uint32_t(a.charts.size()));
    for (int i = 0; i < 3; ++i) head.put<float>(a.offset[i]);
    for (int i = 0; i < 3; ++i) head.put<float>(a.scale[i]);
    head.put<uint64_t>(a.sourceHash);
    head.put<uint64_t>(a.networkHash);
    head.putString(a.sourceName);
    head.putString(a.parameterization);
    head.putString(a.networkId);
    chunks.push_back({kHead, kRaw, std::move(head.bytes)});
    Writer table;
    for (const AssetChart& c : a.charts) {
        table.put<uint32_t>(c.fullResolution);
        table.put<uint32_t>(c.storedLevel);
        table.put<uint32_t>(c.storedSize());
    }
    chunks.push_back({kChrt, kRaw, std::move(table.bytes)});
    chunks.push_back({kMeta, kRaw, std::vector<uint8_t>(a.metadataJson.begin(), a.metadataJson.end())});
    // Coarse to fine would be the streaming order; for now chart by chart, largest first.
    for (uint32_t c = 0; c < a.charts.size(); ++c) {
        const AssetChart& chart = a.charts[c];
        const uint32_t row = chart.storedSize() * 3;
        if (a.coding.pyramid) {
            CodedChart coded = codeChart(chart, a.coding);
            chunks.push_back({kPosi, kPyramid, std::move(coded.positionBytes), c});
            chunks.push_back({kNorm, kPredictedNormals, std::move(coded.normalBytes), c});
        } else {
            chunks.push_back({kPosi, kPredictedDeflate, encodeSamples(chart.positions, row), c});
            chunks.push_back({kNorm, kPredictedDeflate, encodeSamples(chart.normals, row), c});
        }
        if (chart.seams.matched) {
            Writer seam;
            seam.put<uint32_t>(chart.seams.coarsestWatertightLevel);
            seam.put<uint32_t>(uint32_t(chart.seams.segments.size()));
            for (const SeamSegment& s : chart.seams.segments) {
                seam.put<uint32_t>(s.a);
                seam.put<uint32_t>(s.b);
                seam.put<uint32_t>(s.length);
            }
            chunks.push_back({kSeam, kRaw, std::move(seam.bytes), c});
        }
    }
    if (!a.weights.empty()) chunks.push_back({kWght, kRaw, a.weights});

    Writer out;
    out.bytes.insert(out.bytes.end(), kMagic, kMagic + 8);
    out.put<uint32_t>(a.coding.pyramid ? 4u : 3u);  // version 3 readers read what needs no pyramid coder
    out.put<uint32_t>(uint32_t(chunks.size()));
    out.put<uint32_t>(0);  // table CRC, patched below
    out.put<uint32_t>(0);
    size_t offset = kHeaderBytes + chunks.size() * kTableEntryBytes;
    Writer chunkTable;
    for (const Chunk& c : chunks) {
        offset = (offset + 7) & ~size_t(7);
        chunkTable.put<uint32_t>(c.code);
        chunkTable.put<uint32_t>(c.encoding);
        chunkTable.put<uint64_t>(offset);
        chunkTable.put<uint64_t>(c.bytes.size());
        chunkTable.put<uint32_t>(crc32Of(c.bytes));
        chunkTable.put<uint32_t>(c.chart);
        offset += c.bytes.size();
    }
    const uint32_t tableCrc = crc32Of(chunkTable.bytes);
    std::memcpy(out.bytes.data() + 16, &tableCrc, 4);
    out.bytes.insert(out.bytes.end(), chunkTable.bytes.begin(), chunkTable.bytes.end());
    for (const Chunk& c : chunks) {
        out.bytes.resize((out.bytes.size() + 7) & ~size_t(7), 0);
        out.bytes.insert(out.bytes.end(), c.bytes.begin(), c.bytes.end());
    }
    return out.bytes;
}

Asset parseAsset(std::span<const uint8_t> bytes, const std::string& name)
{
    Reader file{bytes, 0, name, "header"};
    if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
        file.fail("not an ngi asset (bad magic bytes)");
    file.at = 8;
    const uint32_t version = file.get<uint32_t>();
    if (version < 1 || version > kAssetFormatVersion)
        file.fail("unsupported asset format version " + std::to_string(version) + " (this build reads versions 1 to " +
                  std::to_string(kAssetFormatVersion) + ")");
    const uint32_t chunkCount = file.get<uint32_t>();
    const uint32_t tableCrc = file.get<uint32_t>();
    if (file.get<uint32_t>() != 0) file.fail("reserved header field is not zero");
    if (chunkCount == 0 || chunkCount > kMaxChunks) file.fail("implausible chunk count " + std::to_string(chunkCount));
    if (bytes.size() - kHeaderBytes < size_t(chunkCount) * kTableEntryBytes) file.fail("file is truncated (chunk table)");
    const auto tableBytes = bytes.subspan(kHeaderBytes, size_t(chunkCount) * kTableEntryBytes);
    if (crc32Of(tableBytes) != tableCrc) file.fail("chunk table fails its CRC32 check");

    struct Entry { uint32_t code; uint32_t chart; uint32_t encoding; std::span<const uint8_t> bytes; };
    std::vector<Entry> entries;
    Reader table{tableBytes, 0, name, "chunk table"};
    for (uint32_t i = 0; i < chunkCount; ++i) {
        const uint32_t code = table.get<uint32_t>();
        const uint32_t encoding = table.get<uint32_t>();
        const uint64_t offset = table.get<uint64_t>();
        const uint64_t size = table.get<uint64_t>();
        const uint32_t crc = table.get<uint32_t>();
        const uint32_t chart = table.get<uint32_t>();
        const bool perChart = code == kPosi || code == kNorm || (code == kSeam && version >= 3);
        if (chart != 0 && (version == 1 || !perChart)) file.fail("reserved chunk-table field is not zero");
        const std::string chunk = "chunk " + fourccName(code) + (perChart && chart ? " of chart " + std::to_string(chart) : "");
        if (offset > bytes.size() || size > bytes.size() - offset) file.fail("file is truncated (" + chunk + ")");
        if (encoding > kPredictedNormals || (encoding > kPredictedDeflate && version < 4))
            file.fail(chunk + " has unknown encoding " + std::to_string(encoding));
        const auto payload = bytes.subspan(size_t(offset), size_t(size));
        if (crc32Of(payload) != crc) file.fail(chunk + " fails its CRC32 check");
        for (const Entry& e : entries)
            if (e.code == code && e.chart == chart) file.fail("duplicate " + chunk);
        entries.push_back({code, chart, encoding, payload});
    }
    auto find = [&](uint32_t code, uint32_t chart, bool required) -> const Entry* {
        for (const Entry& e : entries)
            if (e.code == code && e.chart == chart) return &e;
        if (required)
            file.fail("required chunk " + fourccName(code) + (chart ? " of chart " + std::to_string(chart) : "") + " is missing");
        return nullptr;
    };

    Asset a;
    const Entry* headEntry = find(kHead, 0, true);
    if (headEntry->encoding != kRaw) file.fail("chunk HEAD must be stored raw");
    Reader head{headEntry->bytes, 0, name, "chunk HEAD"};
    // The chart table: in HEAD for version 1 (one chart), in CHRT for version 2.
    struct ChartEntry { uint32_t fullResolution, storedLevel, storedSize; };
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
            file.fail("chart count " + std::to_string(chartCount) + " is not in [1, " + std::to_string(kMaxCharts) + "]");
        const Entry* chrt = find(kChrt, 0, true);
        if (chrt->encoding != kRaw) file.fail("chunk CHRT must be stored raw");
        if (chrt->bytes.size() != size_t(chartCount) * kChartEntryBytes)
            file.fail("chunk CHRT holds " + std::to_string(chrt->bytes.size()) + " bytes, not the " +
                      std::to_string(chartCount) + " charts HEAD declares");
        Reader r{chrt->bytes, 0, name, "chunk CHRT"};
        for (uint32_t c = 0; c < chartCount; ++c) {
            ChartEntry e;
            e.fullResolution = r.get<uint32_t>();
            e.storedLevel = r.get<uint32_t>();
            e.storedSize = r.get<uint32_t>();
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
        if (!problem.empty()) file.fail(where + problem);
        if (e.storedSize != (e.fullResolution >> e.storedLevel) + 1)
            file.fail(where + "stored size " + std::to_string(e.storedSize) + " does not match resolution " +
                      std::to_string(e.fullResolution) + " at level " + std::to_string(e.storedLevel));
        totalSamples += uint64_t(e.fullResolution + 1) * (e.fullResolution + 1);
    }
    if (totalSamples > kMaxTotalFullSamples)
        file.fail("the charts' full images would hold " + std::to_string(totalSamples) + " samples, more than the limit of " +
                  std::to_string(kMaxTotalFullSamples));
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(a.offset[i]) || !std::isfinite(a.scale[i]) || !(a.scale[i] > 0.0f))
            file.fail("de-normalization offset/scale is not finite and positive");

    if (const Entry* meta = find(kMeta, 0, false)) {
        if (meta->encoding != kRaw) file.fail("chunk META must be stored raw");
        a.metadataJson.assign(reinterpret_cast<const char*>(meta->bytes.data()), meta->bytes.size());
    }
    for (const Entry& e : entries)
        if ((e.code == kPosi || e.code == kNorm || e.code == kSeam) && e.chart >= chartTable.size())
            file.fail("chunk " + fourccName(e.code) + " belongs to chart " + std::to_string(e.chart) + " of " +
                      std::to_string(chartTable.size()));
    a.charts.resize(chartTable.size());
    for (uint32_t c = 0; c < chartTable.size(); ++c) {
        AssetChart& chart = a.charts[c];
        chart.fullResolution = chartTable[c].fullResolution;
        chart.storedLevel = chartTable[c].storedLevel;
        const uint32_t storedSize = chartTable[c].storedSize;
        const size_t count = size_t(storedSize) * storedSize * 3;
        auto samples = [&](uint32_t code) {
            const Entry* e = find(code, c, true);
            const std::string what = std::string(code == kPosi ? "chunk POSI" : "chunk NORM") +
                                     (version == 1 ? "" : " of chart " + std::to_string(c));
            Reader r{e->bytes, 0, name, what.c_str()};
            if (e->encoding == kPredictedDeflate) return decodeSamples(e->bytes, count, storedSize * 3, r);
            if (e->encoding == kPyramid || e->encoding == kPredictedNormals) {
                if ((e->encoding == kPyramid) != (code == kPosi))
                    r.fail(what + " has encoding " + std::to_string(e->encoding) + ", which is for " +
                           (code == kPosi ? "NORM" : "POSI"));
                // The seams are read first: mates decode bitwise identical.
                const std::vector<uint32_t> mates = storedMates(chart);
                const std::string where = name + ": " + what;
                if (code == kPosi) {
                    if (c == 0) {
                        a.coding.pyramid = true;
                        const PyramidPayloadInfo info = pyramidPayloadInfo(e->bytes);
                        a.coding.positionStep = info.finestStep;
                        a.coding.positionTangentScale = info.tangentScale;
                    }
                    return decodePyramidPositions(e->bytes, storedSize, where, mates);
                }
                if (c == 0 && e->bytes.size() >= 3) a.coding.normalBits = e->bytes[2];
                return decodePredictedNormals(e->bytes, chart.positions, storedSize, where, mates);
            }
            if (e->bytes.size() != count * 2) r.fail(what + " size does not match the stored level");
            std::vector<uint16_t> out(count);
            std::memcpy(out.data(), e->bytes.data(), count * 2);
            return out;
        };
        if (const Entry* e = find(kSeam, c, false)) {
            const std::string what = "chunk SEAM of chart " + std::to_string(c);
            Reader r{e->bytes, 0, name, what.c_str()};
            if (e->encoding != kRaw) r.fail(what + " must be stored raw");
            chart.seams.matched = true;
            chart.seams.coarsestWatertightLevel = r.get<uint32_t>();
            const uint32_t count = r.get<uint32_t>();
            if (e->bytes.size() != 8 + size_t(count) * 12)
                r.fail(what + " holds " + std::to_string(e->bytes.size()) + " bytes, not the " + std::to_string(count) +
                       " segments it declares");
            chart.seams.segments.resize(count);
            for (SeamSegment& s : chart.seams.segments) {
                s.a = r.get<uint32_t>();
                s.b = r.get<uint32_t>();
                s.length = r.get<uint32_t>();
            }
            validateSeams(chart.seams, chart.fullResolution, chart.levelCount(), name + ": chart " + std::to_string(c));
        }
        chart.positions = samples(kPosi);
        chart.normals = samples(kNorm);
    }
    if (const Entry* w = find(kWght, 0, false)) {
        if (w->encoding != kRaw) file.fail("chunk WGHT must be stored raw");
        a.weights.assign(w->bytes.begin(), w->bytes.end());
    }
    return a;
}

std::vector<uint8_t> readFileBytes(const std::filesystem::path& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path.string() + ": cannot open file (" + std::strerror(errno) + ")");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) throw Error(path.string() + ": cannot read file (not a regular file?)");
    in.seekg(0);
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
        throw Error(path.string() + ": read failed");
    return bytes;
}

Asset readAsset(const std::filesystem::path& path)
{
    const std::vector<uint8_t> bytes = readFileBytes(path);
    return parseAsset(bytes, path.string());
}

void writeAsset(const Asset& asset, const std::filesystem::path& path)
{
    const std::vector<uint8_t> bytes = serializeAsset(asset);
    writeFileAtomic(path, bytes);
}

uint64_t fnv1a64(std::span<const uint8_t> bytes)
{
    uint64_t h = 1469598103934665603ull;
    for (uint8_t b : bytes) h = (h ^ b) * 1099511628211ull;
    return h;
}

} // namespace ngi
