// ngi-bench-codec: the nested-pyramid coder (ngi/pyramid_codec.h) on the stored levels of
// real assets. For each asset, each stored size (the asset's level and the nested levels
// below it) and each step, one table row: position bytes (one stream, as format 4), bits per
// sample (all and per the three finest levels), the cost of streaming (the level-by-level
// streams of format 5 minus the one stream: the flushes, about 4 B per level and chart; and
// the whole asset written as format 5 minus format 4 at that step with prediction-only
// normals: the flushes, the level table, less the NORM chunk format 5 leaves out), max / RMS
// error in units of 2^-16 of the bounding box, encode ms and decode MB/s (decoded u16
// samples), and the normal chunk's bytes and mean angle error against the stored normals at
// each --normal-bits. A first table times the whole read of each asset as a reader does it
// (ngi::readAsset: ms per asset, file and decoded MB/s); a second writes each asset as the
// oldest of formats 3-8 that holds it and as format 9, and gives the chunk table's, SEAM's and
// XSEM's bytes in each and what format 9's packed descriptions free.
//   ngi-bench-codec ASSET.ngi... [--sizes 257,129,65,33] [--steps 16,32,64,128,256] [--normal-bits 0,6,8]
//                   [--tangent-scale T] [--write DIR [--write-normal-bits B]]
// Steps are in 1/65536 of the bounding box; --tangent-scale T codes residuals in the normal /
// tangent frame with T times the step along the tangents (pyramid_codec.h).
// --write DIR writes DIR/NAME_sSIZE_kSTEP.ngi: the asset at that level holding the DECODED
// samples (positions and normals), to measure the restore's distance with ngi-eval;
// --write-normal-bits above 16 keeps the stored normals uncoded (the reference).
#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/pyramid_codec.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Option `flag`'s value "A,B,...": counts (ngi::parseUintOption).
std::vector<uint32_t> parseList(const std::string& flag, const std::string& text)
{
    std::vector<uint32_t> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(ngi::parseUintOption(flag, item));
    return out;
}

// Every 2^d-th sample of a size^2 RGB level.
std::vector<uint16_t> subsample(const std::vector<uint16_t>& s, uint32_t size, uint32_t d)
{
    const uint32_t n = ((size - 1) >> d) + 1;
    std::vector<uint16_t> out;
    out.reserve(size_t(n) * n * 3);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) out.push_back(s[(size_t(y << d) * size + (x << d)) * 3 + c]);
    return out;
}

glm::dvec3 unit(const std::vector<uint16_t>& n, size_t i)
{
    glm::dvec3 v(n[i] / 65535.0 * 2 - 1, n[i + 1] / 65535.0 * 2 - 1, n[i + 2] / 65535.0 * 2 - 1);
    const double l = glm::length(v);
    return l > 0 ? v / l : glm::dvec3(0, 0, 1);
}

double meanAngleDegrees(const std::vector<uint16_t>& a, const std::vector<uint16_t>& b)
{
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); i += 3) sum += std::acos(std::clamp(glm::dot(unit(a, i), unit(b, i)), -1.0, 1.0));
    return sum / double(a.size() / 3) * 180.0 / M_PI;
}

const char* kUsage =
    "usage: ngi-bench-codec ASSET.ngi... [--sizes 257,129,65,33] [--steps 16,32,64,128,256]\n"
    "                       [--normal-bits 0,6,8] [--tangent-scale S] [--write DIR [--write-normal-bits "
    "B]]\n";

}  // namespace

int main(int argc, char** argv)
{
    try {
        std::vector<fs::path> assets;
        std::vector<uint32_t> sizes = {257, 129, 65, 33}, steps = {16, 32, 64, 128, 256}, normalBits = {0, 6, 8};
        fs::path writeDir;
        uint32_t writeNormalBits = 0, tangentScale = 0;
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            const std::string& a = args.flag();
            if (args.is("--sizes"))
                sizes = parseList(a, args.value());
            else if (args.is("--steps"))
                steps = parseList(a, args.value());
            else if (args.is("--normal-bits"))
                normalBits = parseList(a, args.value());
            else if (args.is("--write"))
                writeDir = args.value();
            else if (args.is("--tangent-scale"))
                tangentScale = ngi::parseUintOption(a, args.value());
            else if (args.is("--write-normal-bits"))
                writeNormalBits = ngi::parseUintOption(a, args.value());
            else if (args.is("-h", "--help")) {
                std::fputs(kUsage, stdout);
                return 0;
            } else if (args.positional())
                assets.emplace_back(a);
            else
                throw args.unknown();
        }
        if (assets.empty()) throw ngi::UsageError("no asset");
        // What a reader pays: ngi::readAsset on the file as it is (every chunk checked, the
        // positions decoded, the normals predicted or decoded), best of 5 after one warm-up.
        std::printf("| asset | file B | charts | stored | decoded samples (positions + normals) | read + decode ms | "
                    "file MB/s | decoded MB/s |\n"
                    "|---|---|---|---|---|---|---|---|\n");
        for (const fs::path& path : assets) {
            const size_t fileBytes = fs::file_size(path);
            ngi::Asset asset = ngi::readAsset(path);
            double best = 1e30;
            for (int run = 0; run < 5; ++run) {
                const auto t0 = std::chrono::steady_clock::now();
                asset = ngi::readAsset(path);
                best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            }
            size_t samples = 0;
            for (const ngi::AssetChart& c : asset.charts) samples += c.positions.size() + c.normals.size();
            std::printf("| %s | %zu | %zu | %ux%u | %zu | %.2f | %.1f | %.1f |\n", path.filename().string().c_str(),
                        fileBytes, asset.charts.size(), asset.charts[0].storedSize(), asset.charts[0].storedSize(),
                        samples / 3, best * 1e3, double(fileBytes) / best / 1e6, double(samples * 2) / best / 1e6);
        }
        std::printf("\n");
        // What format 9's packed descriptions free: each asset as read, written as the oldest
        // format of 3-8 that holds it and as format 9 (the same coded samples in both).
        std::printf("| asset | charts | format | file B | chunk table B | SEAM B | XSEM B | format 9 frees B |\n"
                    "|---|---|---|---|---|---|---|---|\n");
        for (const fs::path& path : assets) {
            const ngi::Asset asset = ngi::readAsset(path);
            const std::vector<uint8_t> old = ngi::serializeLegacyAsset(asset), nine = ngi::serializeAsset(asset);
            for (const std::vector<uint8_t>* file : {&old, &nine}) {
                const std::vector<ngi::AssetChunkSize> chunks = ngi::assetChunkSizes(*file, path.string());
                uint64_t seam = 0, xsem = 0;
                for (const ngi::AssetChunkSize& c : chunks) {
                    if (c.name == "SEAM") seam += c.bytes;
                    if (c.name == "XSEM") xsem += c.bytes;
                }
                std::printf("| %s | %zu | %u | %zu | %zu | %llu | %llu | %s |\n", path.filename().string().c_str(),
                            asset.charts.size(), unsigned((*file)[8]), file->size(), 24 + 32 * chunks.size(),
                            (unsigned long long)seam, (unsigned long long)xsem,
                            file == &nine ? std::to_string(long(old.size()) - long(nine.size())).c_str() : "");
            }
        }
        std::printf("\n");
        std::printf("| asset | size | step | POSI B | bits/sample | finest 3 levels bits/sample | flushes B (levels) | "
                    "format 5 - 4 B | max err | RMS err | enc ms | dec MB/s |");
        for (uint32_t b : normalBits) std::printf(" NORM %ub B (deg) |", b);
        std::printf("\n|---|---|---|---|---|---|---|---|---|---|---|---|");
        for (size_t b = 0; b < normalBits.size(); ++b) std::printf("---|");
        std::printf("\n");
        for (const fs::path& path : assets) {
            const ngi::Asset asset = ngi::readAsset(path);
            const uint32_t stored = asset.charts[0].storedSize();
            for (uint32_t size : sizes) {
                if (size > stored || !ngi::pyramidLevelCount(size)) continue;
                const uint32_t d = uint32_t(std::countr_zero(stored - 1) - std::countr_zero(size - 1));
                for (uint32_t k : steps) {
                    size_t bytes = 0, samples = 0, streamedBytes = 0, levelCount = 0;
                    std::vector<double> finest(3, 0.0), finestSamples(3, 0.0);
                    double maxErr = 0, sq = 0, encSeconds = 0, decSeconds = 0;
                    std::vector<size_t> normalBytes(normalBits.size(), 0);
                    std::vector<double> normalAngle(normalBits.size(), 0.0);
                    ngi::Asset written = asset;
                    for (size_t c = 0; c < asset.charts.size(); ++c) {
                        const ngi::AssetChart& chart = asset.charts[c];
                        const uint32_t cd = std::min<uint32_t>(d, uint32_t(std::countr_zero(chart.storedSize() - 1)));
                        const uint32_t n = ((chart.storedSize() - 1) >> cd) + 1;
                        const auto positions = subsample(chart.positions, chart.storedSize(), cd);
                        const auto normals = subsample(chart.normals, chart.storedSize(), cd);
                        std::vector<size_t> levelBytes;
                        const auto t0 = std::chrono::steady_clock::now();
                        const auto payload = ngi::encodePyramidPositions(
                            positions, n, {.step = k, .tangentScale = tangentScale, .levelBytes = &levelBytes});
                        const auto t1 = std::chrono::steady_clock::now();
                        const auto decoded = ngi::decodePyramidPositions(payload, n, path.string());
                        const auto t2 = std::chrono::steady_clock::now();
                        encSeconds += std::chrono::duration<double>(t1 - t0).count();
                        decSeconds += std::chrono::duration<double>(t2 - t1).count();
                        bytes += payload.size();
                        samples += size_t(n) * n;
                        // Format 5's level-by-level streams (the flushes are the difference).
                        const ngi::PyramidLevels streamed =
                            ngi::encodePyramidLevels(positions, n, {.step = k, .tangentScale = tangentScale});
                        streamedBytes += streamed.header.size();
                        for (const auto& level : streamed.levels) streamedBytes += level.size();
                        levelCount += streamed.levels.size();
                        for (size_t i = 0; i < decoded.size(); ++i) {
                            const double e = double(decoded[i]) - double(positions[i]);
                            maxErr = std::max(maxErr, std::abs(e));
                            sq += e * e;
                        }
                        const uint32_t levels = uint32_t(levelBytes.size());
                        for (uint32_t f = 0; f < 3 && f + 1 < levels; ++f) {
                            const uint32_t l = levels - 1 - f, m = ((n - 1) >> f) + 1,
                                           coarse = ((n - 1) >> (f + 1)) + 1;
                            finest[f] += double(levelBytes[l]) * 8.0;
                            finestSamples[f] += double(m) * m - double(coarse) * coarse;
                        }
                        std::vector<uint16_t> writtenNormals;
                        for (size_t b = 0; b < normalBits.size(); ++b) {
                            const auto np = ngi::encodePredictedNormals(decoded, normals, n, normalBits[b]);
                            const auto nd = ngi::decodePredictedNormals(np, decoded, n, path.string());
                            normalBytes[b] += np.size();
                            normalAngle[b] += meanAngleDegrees(nd, normals) * double(n) * n;
                            if (normalBits[b] == writeNormalBits) writtenNormals = nd;
                        }
                        if (writeNormalBits > 16) writtenNormals = normals;  // the stored normals, uncoded
                        if (writtenNormals.empty())
                            writtenNormals = ngi::decodePredictedNormals(
                                ngi::encodePredictedNormals(decoded, normals, n, writeNormalBits), decoded, n,
                                path.string());
                        ngi::AssetChart& w = written.charts[c];
                        w.storedLevel = chart.storedLevel + cd;
                        w.positions = decoded;
                        w.normals = writtenNormals;
                    }
                    // The whole asset at this level and step, as format 4 and as format 5.
                    ngi::Asset coded = written;
                    coded.coding = {
                        .pyramid = true, .progressive = false, .positionStep = k, .positionTangentScale = tangentScale};
                    const size_t formatFour = ngi::serializeAsset(coded).size();
                    coded.coding.progressive = true;
                    const size_t formatFive = ngi::serializeAsset(coded).size();
                    std::printf("| %s | %u | %u | %zu | %.3f | ", path.stem().c_str(), size, k, bytes,
                                bytes * 8.0 / double(samples));
                    for (int f = 2; f >= 0; --f)
                        std::printf(f ? "%.2f / " : "%.2f", finestSamples[f] > 0 ? finest[f] / finestSamples[f] : 0.0);
                    std::printf(" | %ld (%zu) | %ld", long(streamedBytes) - long(bytes), levelCount,
                                long(formatFive) - long(formatFour));
                    std::printf(" | %.0f | %.1f | %.2f | %.1f |", maxErr, std::sqrt(sq / double(samples * 3)),
                                encSeconds * 1e3, double(samples) * 6.0 / 1e6 / decSeconds);
                    for (size_t b = 0; b < normalBits.size(); ++b)
                        std::printf(" %zu (%.2f) |", normalBytes[b], normalAngle[b] / double(samples));
                    std::printf("\n");
                    std::fflush(stdout);
                    if (!writeDir.empty())
                        ngi::writeAsset(written,
                                        writeDir /
                                            (path.stem().string() + "_s" + std::to_string(size) + "_k" +
                                             std::to_string(k) + ".ngi"));
                }
            }
        }
        return 0;
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-bench-codec: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-codec: error: %s\n", e.what());
        return 1;
    }
}
