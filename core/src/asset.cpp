// The .ngi asset file: writer and validating reader.
// Layout and version history are documented in ngi/asset.h.
#include "ngi/asset.h"

#include "asset_format.h"
#include "ngi/color_codec.h"
#include "byte_stream.h"
#include "crc32.h"
#include "file_kind.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/pyramid_codec.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

static_assert(std::endian::native == std::endian::little, "ngi assets are little-endian");

namespace ngi {
namespace {

using namespace detail;

using Writer = detail::ByteWriter;
using Reader = detail::AssetReader;

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

std::vector<uint16_t> decodeSamples(std::span<const uint8_t> stored, size_t count, uint32_t rowSamples, const Reader& r)
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

// One chart's stored level through the pyramid coder: the payloads and what a reader decodes.
// Format 5 codes it level by level (codec 2), format 4 in one stream (codec 1): the same
// residuals and decoded samples.
struct CodedChart {
    std::vector<uint8_t> positionBytes, normalBytes;  // format 4's POSI; NORM
    PyramidLevels levels;                             // format 5's share of the POSI
    std::vector<uint16_t> positions, normals;
    bool normalsFlipped = false;
};

CodedChart codeChart(const AssetChart& chart, const AssetCoding& coding)
{
    CodedChart out;
    const uint32_t n = chart.storedSize();
    const std::vector<uint32_t> mates = storedMates(chart);
    PyramidCodecOptions options{.step = coding.positionStep, .tangentScale = coding.positionTangentScale};
    options.mates = mates;
    if (coding.positionStepGrade > 1.0)  // 0 (steps of another writer) and 1: uniform
        options.levelSteps = gradedLevelSteps(coding.positionStep, pyramidLevelCount(n), coding.positionStepGrade);
    if (coding.progressive) {
        out.levels = encodePyramidLevels(chart.positions, n, options);
        out.positions = decodePyramidLevels(out.levels, n, "asset writer", mates);
    } else {
        out.positionBytes = encodePyramidPositions(chart.positions, n, options);
        out.positions = decodePyramidPositions(out.positionBytes, n, "asset writer", mates);
    }
    out.normalBytes = encodePredictedNormals(out.positions, chart.normals, n, coding.normalBits, mates);
    out.normals = decodePredictedNormals(out.normalBytes, out.positions, n, "asset writer", mates);
    out.normalsFlipped = out.normalBytes.at(1) & 1;
    return out;
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
        if (chart.positions.size() != expect)
            fail("chart " + std::to_string(c) + ": position level has the wrong number of samples");
        if (chart.normals.size() != expect)
            fail("chart " + std::to_string(c) + ": normal level has the wrong number of samples");
        if (!(chart.residualGain >= 0.0f && chart.residualGain <= 1.0f))
            fail("chart " + std::to_string(c) + ": residual gain " + std::to_string(chart.residualGain) +
                 " is not in [0, 1]");
        if (chart.seams.matched)
            validateSeams(chart.seams, chart.fullResolution, chart.levelCount(),
                          where + ": chart " + std::to_string(c));
        if (!chart.baseColor.empty() &&
            (chart.baseColorLevel >= chart.levelCount() ||
             chart.baseColor.size() != size_t(chart.baseColorSize()) * chart.baseColorSize() * 4))
            fail("chart " + std::to_string(c) + ": base colour of " + std::to_string(chart.baseColor.size()) +
                 " bytes at level " + std::to_string(chart.baseColorLevel) + " does not fit the chart");
    }
    if (a.coding.colorQuality > 101)
        fail("coding: colour quality " + std::to_string(a.coding.colorQuality) + " is above 101");
    if (totalSamples > kMaxTotalFullSamples)
        fail("the charts' full images exceed " + std::to_string(kMaxTotalFullSamples) + " samples");
    if (!a.crossSeams.empty()) {
        std::vector<ChartSeams> seams;
        std::vector<uint32_t> resolutions;
        for (const AssetChart& chart : a.charts)
            seams.push_back(chart.seams), resolutions.push_back(chart.fullResolution);
        validateCrossSeams(a.crossSeams, seams, resolutions, where);
    }
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(a.offset[i]) || !std::isfinite(a.scale[i]) || !(a.scale[i] > 0.0f))
            fail("de-normalization offset/scale is not finite and positive");
    for (const std::string* s : {&a.sourceName, &a.parameterization, &a.networkId, &a.metadataJson})
        if (s->size() > kMaxAssetString * 64) fail("a metadata string is too long");
    for (const std::string* s : {&a.sourceName, &a.parameterization, &a.networkId})
        if (s->size() > kMaxAssetString) fail("a header string is longer than 64 KiB");
    if (a.coding.pyramid &&
        (a.coding.positionStep < 1 || a.coding.positionStep > kMaxPyramidStep || a.coding.normalBits > 16))
        fail("coding: position step " + std::to_string(a.coding.positionStep) + " or " +
             std::to_string(a.coding.normalBits) + " normal bits outside [1, " + std::to_string(kMaxPyramidStep) +
             "] / [0, 16]");
    const double grade = a.coding.positionStepGrade;
    if (a.coding.pyramid && !(grade == 0.0 || (grade >= 1.0 && grade <= 4.0)))
        fail("coding: position step grade " + std::to_string(grade) + " is outside [1, 4]");
}

}  // namespace

uint32_t AssetChart::levelCount() const { return isNestedGridSize(fullSize()) ? mipLevelCount(fullSize()) : 1; }

uint32_t AssetChart::coarsestDrawnLevel() const { return ngi::coarsestDrawnLevel(seams, levelCount()); }

uint32_t Asset::fullResolution() const
{
    uint32_t r = 0;
    for (const AssetChart& c : charts) r = std::max(r, c.fullResolution);
    return r;
}

bool Asset::hasBaseColors() const
{
    return std::any_of(charts.begin(), charts.end(), [](const AssetChart& c) { return !c.baseColor.empty(); });
}

int chartLevelForAssetLevel(const Asset&, const AssetChart&, int assetLevel)
{
    // The bake sizes a chart by sqrt of its area share (chartResolutionFor), so level l of every
    // chart has the same density: the same index, not one shifted by the resolution ratio (that
    // drew a chart of half the resolution at the largest one's cell count, twice as dense).
    return assetLevel;
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
    const std::string where = asset.sourceName.empty() ? "asset" : asset.sourceName;
    checkFields(asset, where);
    for (AssetChart& chart : asset.charts)
        if (!chart.baseColor.empty())
            chart.baseColor = decodeColorImage(
                encodeColorImage(chart.baseColor, chart.baseColorSize(), asset.coding.colorQuality, where),
                chart.baseColorSize(), where);
    if (!asset.coding.pyramid) return;
    for (AssetChart& chart : asset.charts) {
        CodedChart coded = codeChart(chart, asset.coding);
        chart.positions = std::move(coded.positions);
        chart.normals = std::move(coded.normals);
    }
}

std::vector<uint8_t> serializeAsset(const Asset& a) { return writeAsset(a, false); }

std::vector<uint8_t> detail::writeAsset(const Asset& a, bool legacy)
{
    const std::string name = a.sourceName.empty() ? "asset" : a.sourceName;  // in errors
    checkFields(a, name);
    const bool progressive = a.coding.pyramid && a.coding.progressive;
    const bool packed = !legacy;  // format 9

    struct Chunk {
        uint32_t code;
        uint32_t encoding;
        std::vector<uint8_t> bytes;
        uint32_t chart = 0;
    };
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
    // 16-byte CHRT entries (with the residual gain) from format 6 on.
    const bool gains = packed || legacyVersion(a) >= 6;
    Writer table;
    for (const AssetChart& c : a.charts) {
        table.put<uint32_t>(c.fullResolution);
        table.put<uint32_t>(c.storedLevel);
        table.put<uint32_t>(c.storedSize());
        if (gains) table.put<float>(c.residualGain);
    }
    chunks.push_back({kChrt, kRaw, std::move(table.bytes)});
    chunks.push_back({kMeta, kRaw, std::vector<uint8_t>(a.metadataJson.begin(), a.metadataJson.end())});
    bool anySeams = false;
    for (const AssetChart& c : a.charts) anySeams |= c.seams.matched;
    if (packed) {  // description chunks, before POSI: every chart's seams in one, then XSEM
        if (anySeams) chunks.push_back({kSeam, kPacked, packSeams(a.charts)});
        if (!a.crossSeams.empty()) chunks.push_back({kXsem, kPacked, packCrossSeams(a.crossSeams)});
    } else if (!a.crossSeams.empty()) {  // a description chunk: before POSI (format 7)
        chunks.push_back({kXsem, kRaw, writeLegacyCrossSeams(a.crossSeams)});
    }
    auto seamChunk = [&](uint32_t c) {  // formats 3-8: one per chart
        const AssetChart& chart = a.charts[c];
        if (!packed && chart.seams.matched) chunks.push_back({kSeam, kRaw, writeLegacySeams(chart.seams), c});
    };
    if (progressive) {
        // Streaming order (format 5): the description, every chart's positions coarse to
        // fine in one chunk, then what a prefix may lack.
        for (uint32_t c = 0; c < a.charts.size(); ++c) seamChunk(c);
        std::vector<CodedChart> coded;
        std::vector<PyramidLevels> levels;
        std::vector<bool> flipped;
        for (const AssetChart& chart : a.charts) {
            coded.push_back(codeChart(chart, a.coding));
            levels.push_back(std::move(coded.back().levels));
            flipped.push_back(coded.back().normalsFlipped);
        }
        chunks.push_back({kPosi, kProgressivePositions, encodeProgressivePositions(levels, flipped)});
        if (a.coding.normalBits > 0)
            for (uint32_t c = 0; c < a.charts.size(); ++c)
                chunks.push_back({kNorm, kPredictedNormals, std::move(coded[c].normalBytes), c});
    } else {
        // Chart by chart, largest first (formats 3 and 4 do not stream).
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
            seamChunk(c);
        }
    }
    // The colours after the geometry: a prefix of a progressive file has the shape first.
    bool colors = false;
    for (const AssetChart& chart : a.charts) colors |= !chart.baseColor.empty();
    if (packed && colors) chunks.push_back({kBcol, kPackedWebp, packColors(a.charts, a.coding.colorQuality, name)});
    for (uint32_t c = 0; c < a.charts.size() && !packed; ++c)  // format 8: one per coloured chart
        if (!a.charts[c].baseColor.empty())
            chunks.push_back(
                {kBcol, kWebp,
                 writeLegacyColor(a.charts[c], a.coding.colorQuality, name + ": chart " + std::to_string(c)), c});
    if (!a.weights.empty()) chunks.push_back({kWght, kRaw, a.weights});

    Writer out;
    out.bytes.insert(out.bytes.end(), kAssetMagic, kAssetMagic + 8);
    out.put<uint32_t>(packed ? kAssetFormatVersion : legacyVersion(a));
    out.put<uint32_t>(uint32_t(chunks.size()));
    out.put<uint32_t>(0);  // table CRC, patched below
    out.put<uint32_t>(0);
    size_t offset = kAssetHeaderBytes + chunks.size() * kChunkEntryBytes;
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

namespace {

// One chart's samples of formats 1 to 4 (a POSI and a NORM chunk per chart).
void readChartSamples(const AssetLayout& layout, Asset& a, uint32_t c, const std::string& name)
{
    const uint32_t version = layout.version;
    AssetChart& chart = a.charts[c];
    const uint32_t storedSize = chart.storedSize();
    const size_t count = size_t(storedSize) * storedSize * 3;
    auto samples = [&](uint32_t code) {
        const AssetChunk* e = layout.find(code, c, true, name);
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
                    a.coding.progressive = false;
                    const PyramidPayloadInfo info = pyramidPayloadInfo(e->bytes);
                    a.coding.positionStep = info.finestStep;
                    a.coding.positionTangentScale = info.tangentScale;
                    a.coding.positionStepGrade = stepGradeOf(info.steps);
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
    chart.positions = samples(kPosi);
    chart.normals = samples(kNorm);
}

}  // namespace

Asset parseAsset(std::span<const uint8_t> bytes, const std::string& name)
{
    const AssetLayout layout = *readAssetLayout(bytes, name, false);
    Asset a = readAssetDescription(layout, name);
    if (layout.coding >= 5) {
        const AssetChunk* posi = layout.find(kPosi, 0, true, name);
        ProgressivePositions positions(a, name + ": chunk POSI", posi->size);
        positions.advance(posi->bytes);
        if (!positions.tableRead() || positions.roundsDecoded() != positions.roundCount())
            throw Error(name + ": chunk POSI holds " + std::to_string(positions.roundsDecoded()) + " of its " +
                        std::to_string(positions.roundCount()) + " levels");
        finishProgressiveAsset(layout, positions, a, name);
    } else {
        for (uint32_t c = 0; c < a.charts.size(); ++c) readChartSamples(layout, a, c, name);
    }
    readChartColors(layout, a, name);
    if (const AssetChunk* w = layout.find(kWght, 0, false, name)) {
        if (w->encoding != kRaw) throw Error(name + ": chunk WGHT must be stored raw");
        a.weights.assign(w->bytes.begin(), w->bytes.end());
    }
    return a;
}

std::vector<AssetChunkSize> assetChunkSizes(std::span<const uint8_t> file, const std::string& name)
{
    const AssetLayout layout = *readAssetLayout(file, name, false);
    std::vector<AssetChunkSize> sizes;
    sizes.reserve(layout.chunks.size());
    for (const AssetChunk& e : layout.chunks)
        sizes.push_back({fourccName(e.code), e.chart, e.offset, e.size, e.encoding});
    return sizes;
}

std::vector<uint8_t> readFileBytes(const std::filesystem::path& path)
{
    // Refused before it is opened (opening a device can have effects) and again after (it
    // may have been replaced in between). O_NONBLOCK: opening a FIFO never waits for a writer.
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
        throw Error(path.string() + ": is " + detail::fileKindName(status.type()) + ", not a regular file");
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error(path.string() + ": cannot open file (" + std::strerror(errno) + ")");
    struct FileDescriptor {
        int fd;
        ~FileDescriptor() { ::close(fd); }
    } owner{fd};
    struct stat opened {};
    if (::fstat(fd, &opened) != 0) throw Error(path.string() + ": cannot read file (" + std::strerror(errno) + ")");
    if (!S_ISREG(opened.st_mode)) throw Error(path.string() + ": is not a regular file");
    std::vector<uint8_t> bytes;
    try {
        bytes.resize(size_t(opened.st_size));
    } catch (const std::bad_alloc&) {
        throw Error(path.string() + ": out of memory reading the file (" + std::to_string(opened.st_size) + " bytes)");
    }
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw Error(path.string() + ": read failed (" + std::strerror(errno) + ")");
        if (n == 0) throw Error(path.string() + ": read failed (the file shrank while it was read)");
        done += size_t(n);
    }
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

}  // namespace ngi
