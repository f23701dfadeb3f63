// ngi offline eval, the report's measurements (see report.h), in the order they run: bake or
// reuse one full-resolution asset per parameterization (stored level 0: the full image, 16-bit;
// Table 1), derive the stored levels from the OT one exactly as the baker's stage 8 does (nested
// subsampling; Table 4 and its peers), the rate-distortion rows (report_budgets.cpp), then the
// LoD rows and the contact sheets; every candidate mesh measured with docs/DESIGN.md's CD/HD.
#include "ngi/eval/report.h"

#include "report_job.h"

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/error.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/eval/draco_codec.h"
#include "ngi/eval/equal_bytes.h"
#include "ngi/eval/distance_heat_map.h"
#include "ngi/eval/report_picture.h"
#include "ngi/eval/simplify.h"
#include "ngi/eval/subdivision.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_catalog.h"
#include "ngi/stored_level.h"
#include "ngi/stopwatch.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

namespace ngi {

using namespace report_detail;
namespace fs = std::filesystem;

std::vector<fs::path> resolveMeshList(const std::string& dirOrList)
{
    static const std::set<std::string> kExtensions = {".off", ".obj", ".ply", ".stl", ".gltf", ".glb"};
    std::vector<fs::path> meshes;
    if (dirOrList.empty())
        throw Error("--meshes: empty (expected a directory or a comma-separated list of mesh files)");
    std::error_code ec;
    if (dirOrList.find(',') == std::string::npos && fs::is_directory(dirOrList, ec)) {
        for (const fs::directory_entry& e : fs::directory_iterator(dirOrList, ec)) {
            std::string ext = e.path().extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            if (e.is_regular_file() && kExtensions.count(ext)) meshes.push_back(e.path());
        }
        if (ec) throw Error(dirOrList + ": cannot list the directory (" + ec.message() + ")");
        std::sort(meshes.begin(), meshes.end());
        if (meshes.empty())
            throw Error(dirOrList + ": no mesh files (.off .obj .ply .stl .gltf .glb) in this directory");
        return meshes;
    }
    size_t start = 0;
    while (start <= dirOrList.size()) {
        const size_t end = std::min(dirOrList.find(',', start), dirOrList.size());
        const std::string item = dirOrList.substr(start, end - start);
        start = end + 1;
        if (item.empty()) continue;
        if (!fs::exists(item, ec)) throw Error(item + ": no such mesh file or directory");
        if (!fs::is_regular_file(item, ec)) throw Error(item + ": not a mesh file");
        meshes.push_back(item);
    }
    if (meshes.empty()) throw Error("--meshes '" + dirOrList + "': no mesh files listed");
    return meshes;
}

namespace {

using Clock = std::chrono::steady_clock;

// The asset file's bytes by what they hold (the chunk table, ngi/asset.h). Throws ngi::Error
// naming `name` when the file is no asset.
AssetBytes assetBytesOf(const std::vector<uint8_t>& file, const std::string& name)
{
    AssetBytes bytes;
    bytes.file = file.size();
    for (const AssetChunkSize& chunk : assetChunkSizes(file, name)) {
        if (chunk.name == "POSI")  // once per chart
            bytes.positions += chunk.bytes;
        else if (chunk.name == "NORM")
            bytes.normals += chunk.bytes;
        else if (chunk.name == "META" || chunk.name == "CHRT")
            bytes.metadata += chunk.bytes;
        else if (chunk.name == "WGHT")
            bytes.weights = chunk.bytes;
    }
    return bytes;
}

// The bake time and distortions recorded in a reused asset's metadata (the baker's report).
void readBakeReport(const Asset& asset, BakeRow& row)
{
    const nlohmann::json meta = nlohmann::json::parse(asset.metadataJson, nullptr, false);
    if (meta.is_discarded() || !meta.contains("bake")) return;
    const nlohmann::json& bake = meta["bake"];
    auto number = [](const nlohmann::json& j, const char* key) {
        return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : kNaN;
    };
    row.seconds = number(bake, "totalSeconds");
    if (bake.contains("parameterization")) {
        row.areaDistortionMean = number(bake["parameterization"], "areaDistortionMean");
        row.angleDistortionMean = number(bake["parameterization"], "angleDistortionMean");
    }
}

// The meshes of the picture stored resolution that the contact sheet shows.
struct PictureMeshes {
    std::optional<Asset> asset;
    std::vector<std::pair<std::string, TriangleMesh>> peerTiles;  // label, mesh
};

// One mesh of the report: run() calls its stages in the order the report reads.
struct MeshJob : MeshContext {
    bool lodCurve = false;
    std::span<const ShippedNetwork> shipped;  // the networks a budget asset may name

    // The full image of one parameterization as an asset storing level 0, baked or reused.
    std::optional<Asset> fullAsset(ParameterizationMethod method, BakeRow& row)
    {
        const std::string name = parameterizationName(method);
        const fs::path path = assetPath(name, "full.ngi");
        const fs::path failedPath = assetPath(name, "failed.txt");
        std::error_code ec;
        if (options.reuse && fs::exists(path, ec)) {
            try {
                Asset asset = readAsset(path);
                const bool fullLevels = std::all_of(asset.charts.begin(), asset.charts.end(),
                                                    [](const AssetChart& c) { return c.storedLevel == 0; });
                if (fullLevels && asset.fullResolution() == options.resolution && asset.sourceHash == sourceHash &&
                    asset.parameterization == name) {
                    row.ok = row.reused = true;
                    readBakeReport(asset, row);
                    progress.advance(kBakeUnits, report.name + ": reuse " + name);
                    return asset;
                }
            } catch (const Error&) {
                // Not reusable: bake again below.
            }
        }
        if (options.reuse && fs::exists(failedPath, ec)) {
            const std::vector<uint8_t> text = readFileBytes(failedPath);
            row.failure = std::string(text.begin(), text.end());
            row.reused = true;
            progress.advance(kBakeUnits, report.name + ": reuse failed " + name);
            return std::nullopt;
        }
        const Clock::time_point start = Clock::now();
        try {
            BakeOptions bake;
            bake.resolution = options.resolution;
            bake.storeResolution = options.resolution;  // level 0 kept below anyway
            bake.method = method;
            bake.sourceName = report.path;
            bake.sourceHash = sourceHash;
            BakeResult result = bakeMesh(input, bake);
            row.seconds = secondsSince(start);
            row.areaDistortionMean = row.angleDistortionMean = 0.0;
            for (const ChartReport& c : result.report.charts) {  // area-weighted over the charts
                row.areaDistortionMean += c.areaFraction * c.parameterization.areaDistortionMean;
                row.angleDistortionMean += c.areaFraction * c.parameterization.angleDistortionMean;
            }
            Asset asset = std::move(result.asset);
            for (size_t c = 0; c < asset.charts.size(); ++c) {
                asset.charts[c].storedLevel = 0;
                storeGeometryImage(asset.charts[c], result.charts[c].fullPositions, result.charts[c].fullNormals);
            }
            writeAsset(asset, path);
            fs::remove(failedPath, ec);
            row.ok = true;
            progress.advance(kBakeUnits, report.name + ": bake " + name);
            return asset;
        } catch (const std::exception& e) {
            row.seconds = secondsSince(start);
            row.failure = oneLine(e.what());
            const std::string text = row.failure;
            writeFileAtomic(failedPath, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
            progress.advance(kBakeUnits, report.name + ": bake " + name + " failed");
            return std::nullopt;
        }
    }

    // The asset the baker would write for `stored`, derived from the full (level-0) asset.
    Asset storedAsset(const Asset& full, uint32_t stored) const
    {
        Asset asset = full;
        const uint32_t level = storedLevelOf(full.fullResolution(), stored);
        for (AssetChart& chart : asset.charts) {
            // A chart smaller than the largest keeps the same level (same CR), down to 2x2.
            const uint32_t chartLevel = std::min(level, uint32_t(std::countr_zero(chart.fullResolution)));
            const GeometryImage positions = downsampleNested(storedPositions(chart), chartLevel);  // from level 0
            const GeometryImage normals = downsampleNested(storedNormals(chart), chartLevel);
            chart.storedLevel = chartLevel;
            storeGeometryImage(chart, positions, normals);
        }
        return asset;
    }

    // The input's size, and its Draco bytes (the peer's ceiling).
    void measureInput()
    {
        report.inputVertices = input.positions.size();
        report.inputTriangles = input.triangles.size();
        try {
            report.inputDracoBytes = encodeDraco(input).size();
        } catch (const std::exception&) {
            report.inputDracoBytes = 0;
        }
    }

    // Table 1: each parameterization's full image, baked (or reused) and measured. Returns the OT
    // asset (the stored rows derive from it), if OT is among them and baked.
    std::optional<Asset> parameterizationRows()
    {
        std::optional<Asset> ot;
        for (ParameterizationMethod method : options.parameterizations) {
            BakeRow row;
            row.method = parameterizationName(method);
            std::optional<Asset> full = fullAsset(method, row);
            if (full) {
                try {
                    row.full = measure(assetMesh(*full, {.lod = 0.0f}).mesh, "Table 1 " + row.method);
                } catch (const std::exception& e) {
                    row.full.failure = "failed: " + oneLine(e.what());
                    progress.advance(1.0, report.name + ": Table 1 " + row.method);
                }
            } else {
                row.full.failure = "failed: " + row.failure;
                progress.advance(1.0, report.name + ": Table 1 " + row.method);
            }
            report.bakes.push_back(row);
            if (method == ParameterizationMethod::OptimalTransport) {
                ot = std::move(full);
                report.otOk = ot.has_value();
                report.otFailure = row.failure;
            }
        }
        if (!ot && report.otFailure.empty()) report.otFailure = "ot not among --params";
        return ot;
    }

    // Table 4 and the peers at equal bytes and at equal triangles: the OT asset at each stored
    // resolution. Returns the meshes of the picture stored resolution.
    PictureMeshes storedRows(const std::optional<Asset>& ot)
    {
        PictureMeshes kept;
        for (uint32_t stored : options.storedResolutions) {
            StoredRow row;
            row.stored = stored;
            row.level = storedLevelOf(options.resolution, stored);
            row.compressionRatio = compressionRatioAtLevel(row.level);
            const std::string step = "stored " + std::to_string(stored);
            if (!ot) {
                for (Measured* m : {&row.ngi, &row.equalBytes, &row.loop, &row.butterfly, &row.ngiGrid,
                                    &row.simplifiedEqualTriangles})
                    m->failure = "failed: OT bake " + report.otFailure;
                progress.advance(6.0, report.name + ": " + step + " (no OT asset)");
                report.stored.push_back(row);
                continue;
            }
            const bool forPicture = stored == report.lodStored;
            try {
                const Asset asset = storedAsset(*ot, stored);
                const fs::path path = assetPath("ot", "s" + std::to_string(stored) + ".ngi");
                writeAsset(asset, path);
                row.assetFile = fs::relative(path, options.outDir).string();
                row.bytes = assetBytesOf(readFileBytes(path), path.string());
                if (forPicture) kept.asset = asset;
                row.ngi = measure(assetMesh(asset, {.lod = 0.0f}).mesh, step + " ngi");
                const TriangleMesh grid = assetMesh(asset, {.lod = float(row.level)}).mesh;
                row.ngiGrid = measure(grid, step + " ngi grid");

                const EqualBytesResult peer = simplifyToByteBudget(input, row.bytes.file);
                row.dracoBytes = peer.dracoBytes;
                row.budgetMet = peer.budgetMet;
                row.wholeInputFits = peer.simplified.triangles.size() == input.triangles.size();
                row.equalBytes = measure(peer.decoded, step + " meshopt+draco");
                uint32_t iterations = 1;
                while (iterations < 3 &&
                       peer.decoded.triangles.size() * (size_t(1) << (2 * iterations)) < input.triangles.size())
                    ++iterations;
                row.subdivisionIterations = iterations;
                SubdivisionResult loop, butterfly;
                try {
                    loop = subdivideMesh(peer.decoded, {SubdivisionScheme::loop, iterations});
                    row.loop = measure(loop.mesh, step + " loop");
                } catch (const std::exception& e) {
                    row.loop.failure = "failed: " + oneLine(e.what());
                    progress.advance(1.0, report.name + ": " + step + " loop");
                }
                try {
                    butterfly = subdivideMesh(peer.decoded, {SubdivisionScheme::modifiedButterfly, iterations});
                    row.butterfly = measure(butterfly.mesh, step + " butterfly");
                } catch (const std::exception& e) {
                    row.butterfly.failure = "failed: " + oneLine(e.what());
                    progress.advance(1.0, report.name + ": " + step + " butterfly");
                }
                const size_t gridTriangles = grid.triangles.size();
                row.inputHasFewerTriangles = gridTriangles >= input.triangles.size();
                TriangleMesh simplified = row.inputHasFewerTriangles
                    ? input
                    : simplifyMesh(input, {.targetTriangleCount = uint32_t(gridTriangles)}).mesh;
                row.simplifiedEqualTriangles = measure(simplified, step + " meshopt equal triangles");
                if (forPicture) {
                    kept.peerTiles.emplace_back("meshopt+Draco at equal bytes", peer.decoded);
                    kept.peerTiles.emplace_back("Loop x" + std::to_string(iterations), std::move(loop.mesh));
                    kept.peerTiles.emplace_back("Butterfly x" + std::to_string(iterations), std::move(butterfly.mesh));
                    kept.peerTiles.emplace_back("meshopt at " + std::to_string(gridTriangles) + " triangles",
                                                std::move(simplified));
                }
            } catch (const std::exception& e) {
                for (Measured* m : {&row.ngi, &row.equalBytes, &row.loop, &row.butterfly, &row.ngiGrid,
                                    &row.simplifiedEqualTriangles})
                    if (!m->ok && m->failure.empty()) m->failure = "failed: " + oneLine(e.what());
                progress.advance(0.0, report.name + ": " + step + " failed");
            }
            report.stored.push_back(row);
        }
        return kept;
    }

    // The LoD rows (first mesh only) and the contact sheet.
    void lodRowsAndPictures(const PictureMeshes& kept)
    {
        std::optional<TriangleMesh> finest;  // LoD 0 as drawn above, for the heat map
        try {
            PictureView view = pictureViewFor(input);
            std::vector<RgbImage> tiles;
            tiles.push_back(renderMeshPicture(input, view, options.pictureSize, {0.85f, 0.8f, 0.7f}));
            report.pictureTiles.push_back("input (" + std::to_string(input.triangles.size()) + " triangles)");
            if (kept.asset) {
                const uint32_t levels = mipLevelCount(kept.asset->fullResolution() + 1);
                // Levels coarser than the asset draws (its seams' limit, ngi/asset.h) are skipped.
                const uint32_t drawnLevels = kept.asset->charts.front().coarsestDrawnLevel() + 1;
                for (uint32_t lod = 0; lod < levels; ++lod) {
                    const bool wanted = lodCurve || lod + 3 < levels;
                    if (!wanted) continue;
                    if (lod >= drawnLevels) {
                        if (lodCurve)
                            progress.advance(1.0, report.name + ": LoD " + std::to_string(lod) + " not drawn");
                        continue;
                    }
                    AssetMesh drawn = assetMesh(*kept.asset, {.lod = float(lod)});
                    if (lodCurve) {
                        LodRow row;
                        row.lod = lod;
                        row.gridSize = drawn.selection.gridSize;
                        row.m = measure(drawn.mesh, "LoD " + std::to_string(lod));
                        report.lods.push_back(row);
                    }
                    if (lod + 3 < levels) {  // the 2x2 .. 5x5 levels say nothing in a picture
                        tiles.push_back(renderMeshPicture(drawn.mesh, view, options.pictureSize));
                        report.pictureTiles.push_back("ngi LoD " + std::to_string(lod) + " (grid " +
                                                      std::to_string(drawn.selection.gridSize) + ", " +
                                                      std::to_string(drawn.mesh.triangles.size()) + " triangles)");
                    }
                    if (lod == 0) finest = std::move(drawn.mesh);
                }
            }
            for (const auto& [label, mesh] : kept.peerTiles) {
                tiles.push_back(renderMeshPicture(mesh, view, options.pictureSize, {0.7f, 0.85f, 0.75f}));
                report.pictureTiles.push_back(label + " (" + std::to_string(mesh.triangles.size()) + " triangles)");
            }
            report.pictureColumns = 5;
            const fs::path picture = options.outDir / "pictures" / (report.name + ".png");
            fs::create_directories(picture.parent_path());
            writeRgbPng(picture, contactSheet(tiles, report.pictureColumns));
            report.pictureFile = fs::relative(picture, options.outDir).string();
        } catch (const std::exception& e) {
            report.pictureFailure = oneLine(e.what());
        }
        // Where the drawn surface is far from the input: the input coloured by its distance.
        if (kept.asset) try {
                if (!finest) finest = assetMesh(*kept.asset, {.lod = 0.0f}).mesh;
                const DistanceHeatMap map =
                    distanceHeatMap(input, *finest, referenceFrame(input), 0.0, distanceThreads);
                const fs::path picture = options.outDir / "pictures" / (report.name + ".heat.png");
                fs::create_directories(picture.parent_path());
                writeRgbPng(picture, map.image);
                report.heatMapFile = fs::relative(picture, options.outDir).string();
                report.heatMapFarthest = map.farthest * kHausdorffReportScale;
            } catch (const std::exception& e) {
                report.heatMapFailure = oneLine(e.what());
            }
        progress.advance(1.0, report.name + ": pictures");
    }

    void run()
    {
        measureInput();
        const std::optional<Asset> ot = parameterizationRows();
        const PictureMeshes kept = storedRows(ot);
        measureBudgetRows(*this, shipped);
        lodRowsAndPictures(kept);
    }
};

double unitsPerMesh(const ReportOptions& o, bool lodCurve)
{
    double units = double(o.parameterizations.size()) * (kBakeUnits + 1.0);
    units += 6.0 * double(o.storedResolutions.size());
    if (!o.budgets.empty()) units += kBakeUnits + 5.0 * double(o.budgets.size());  // ngi x2, peer x3 per budget
    if (lodCurve) units += double(mipLevelCount(o.resolution + 1));
    return units + 1.0;
}

void checkOptions(const ReportOptions& o)
{
    if (o.meshes.empty()) throw Error("report: no meshes");
    if (!std::has_single_bit(o.resolution) || o.resolution < 32 || o.resolution > 4096)
        throw Error("report: --resolution " + std::to_string(o.resolution) + " is not a power of two in [32, 4096]");
    if (o.storedResolutions.empty()) throw Error("report: no stored resolutions");
    for (uint32_t s : o.storedResolutions)
        if (!std::has_single_bit(s) || s < 2 || s > o.resolution)
            throw Error("report: stored resolution " + std::to_string(s) + " is not a power of two in [2, " +
                        std::to_string(o.resolution) + "]");
    if (o.parameterizations.empty()) throw Error("report: no parameterizations");
    if (o.jobs == 0) throw Error("report: --jobs must be at least 1");
    if (o.sampleCount == 0) throw Error("report: the sample count must be at least 1");
    if (o.pictureSize < 16) throw Error("report: the picture size must be at least 16 pixels");
    for (size_t b : o.budgets)
        if (b == 0) throw Error("report: a byte budget must be at least 1");
    std::error_code ec;
    if (!o.networks.empty() && !fs::is_directory(o.networks, ec))
        throw Error("report: --networks " + o.networks.string() + ": not a directory");
}

}  // namespace

ReportResult runReport(const ReportOptions& options)
{
    checkOptions(options);
    const Clock::time_point start = Clock::now();

    // Read every mesh first: bad input fails before any work.
    std::vector<TriangleMesh> inputs;
    std::vector<uint64_t> hashes;
    for (const fs::path& path : options.meshes) {
        inputs.push_back(readMesh(path));
        hashes.push_back(fnv1a64(readFileBytes(path)));
    }
    std::error_code ec;
    fs::create_directories(options.outDir / "assets", ec);
    if (ec) throw Error(options.outDir.string() + ": cannot create the output directory (" + ec.message() + ")");

    double total = 0.0;
    for (size_t i = 0; i < inputs.size(); ++i) total += unitsPerMesh(options, i == 0);
    ProgressSink progress(options, total);
    // The same networks ngi-bake finds (a file that does not read is skipped and reported).
    std::vector<std::string> skippedNetworkFiles;
    const std::vector<ShippedNetwork> shipped = options.budgets.empty()
        ? std::vector<ShippedNetwork>{}
        : findShippedNetworks(networkSearchPath(options.networks), skippedNetworkFiles);

    uint32_t lodStored = options.storedResolutions.front();
    for (uint32_t s : options.storedResolutions)
        if (std::abs(int(s) - int(options.pictureStoredResolution)) <
            std::abs(int(lodStored) - int(options.pictureStoredResolution)))
            lodStored = s;

    const unsigned workers = std::min<unsigned>(options.jobs, unsigned(inputs.size()));
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    std::vector<MeshReport> reports(inputs.size());
    std::atomic<size_t> next{0};
    std::mutex errorMutex;
    std::string firstError;
    auto work = [&] {
        for (size_t i = next++; i < inputs.size(); i = next++) {
            try {
                MeshJob job{
                    {options, progress, inputs[i], hashes[i], std::max(1u, hardware / workers), {}}, i == 0, shipped};
                job.report.name = options.meshes[i].stem().string();
                job.report.path = options.meshes[i].string();
                job.report.lodStored = lodStored;
                job.run();
                reports[i] = std::move(job.report);
            } catch (const std::exception& e) {
                std::lock_guard lock(errorMutex);
                if (firstError.empty()) firstError = options.meshes[i].string() + ": " + e.what();
            }
        }
    };
    std::vector<std::thread> threads;
    for (unsigned t = 1; t < workers; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (!firstError.empty()) throw Error(firstError);

    std::string networkNote = "no trained network";
    if (!options.networkWeights.empty()) {
        if (!fs::exists(options.networkWeights, ec))
            throw Error(options.networkWeights.string() + ": no such network file");
        networkNote = "network " + options.networkWeights.filename().string() + " (" +
            std::to_string(fs::file_size(options.networkWeights, ec)) +
            " bytes) given, but the SR restore is not wired into ngi-eval yet";
    }

    ReportResult result;
    result.skippedNetworkFiles = std::move(skippedNetworkFiles);
    result.meshCount = reports.size();
    for (const MeshReport& r : reports) {
        for (const BakeRow& b : r.bakes) result.failedBakes += b.ok ? 0 : 1;
        for (const StoredRow& s : r.stored)
            for (const Measured* m :
                 {&s.ngi, &s.equalBytes, &s.loop, &s.butterfly, &s.ngiGrid, &s.simplifiedEqualTriangles})
                result.failedMeasurements += m->ok ? 0 : 1;
        result.failedBakes += r.budgetBakeFailure.empty() ? 0 : 1;
    }
    result.seconds = secondsSince(start);
    result.reportPath = writeReportFiles(options, reports, result.seconds, networkNote);
    return result;
}

}  // namespace ngi
