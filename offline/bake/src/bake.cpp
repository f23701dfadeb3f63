// ngi offline: the ngi-bake pipeline, stages 2-8 (see bake.h). Paper section 3.1 ("Optimal
// Transport for Geometry Images") and section 3.2 "Input Precondition": remesh, cut, conformal
// start, OT refinement, rasterize into a 16-bit geometry image, keep one mip level.
#include "ngi/bake/bake.h"

#include "ngi/bake/bake_report.h"
#include "ngi/error.h"
#include "ngi/mesh/chart_split.h"
#include "ngi/param/matched_group.h"
#include "ngi/mip_pyramid.h"
#include "ngi/param/distortion.h"
#include "ngi/param/extremity_cut.h"
#include "ngi/param/rasterize.h"
#include "ngi/param/sampling_check.h"
#include "ngi/stopwatch.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>

namespace ngi {
namespace {

using Clock = StopwatchClock;

std::string format(const char* fmt, auto... args) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, fmt, args...);
    return buffer;
}

thread_local double lastStageSeconds = 0.0;

// Runs one stage: times it, adds its time to the report (summed over charts), and prefixes
// errors with the source and stage.
template <typename Function>
auto runStage(const char* stage, const BakeOptions& options, BakeReport& report, Function&& function) {
    const Clock::time_point start = Clock::now();
    try {
        auto result = function();
        const double seconds = secondsSince(start);
        auto same = std::find_if(report.stages.begin(), report.stages.end(), [&](const StageTime& s) { return s.stage == stage; });
        if (same == report.stages.end()) report.stages.push_back({stage, seconds});
        else same->seconds += seconds;
        lastStageSeconds = seconds;
        return result;
    } catch (const Error& e) {
        const std::string message = e.what();
        if (message.rfind(options.sourceName + ":", 0) == 0) throw;  // already names the file
        throw Error(options.sourceName + ": " + stage + ": " + message);
    }
}

void announce(const BakeOptions& options, const char* stage, const std::string& summary) {
    if (options.stageDone) options.stageDone(stage, lastStageSeconds, summary);
}

double surfaceArea(const TriangleMesh& mesh) {
    double area = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        area += 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    return area;
}

} // namespace

double undersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv, double factor) {
    return mapUndersampledAreaFraction(mesh, uv, factor);  // one definition (sampling_check.h)
}

size_t remeshVertexCountFor(uint32_t resolution) {
    return std::clamp<size_t>(size_t(resolution) * resolution / 64, 1000, 150000);
}

size_t remeshVertexCountForThinParts(uint32_t resolution) {
    return std::clamp<size_t>(size_t(resolution) * resolution / 16, 1000, 150000);
}

void normalizationFor(const GeometryImage& image, glm::vec3& offset, glm::vec3& scale) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::vec3& p : image.texels) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    const glm::dvec3 extent = hi - lo;
    const double side = std::max({extent.x, extent.y, extent.z});
    if (!(side > 0.0) || !std::isfinite(side)) throw Error("the geometry image has a zero-size or non-finite bounding box");
    offset = glm::vec3((lo + hi) * 0.5 - glm::dvec3(side * 0.5));
    scale = glm::vec3(float(side));
}

TriangleMesh geometryImageMesh(const GeometryImage& image) {
    TriangleMesh mesh;
    const uint32_t n = image.size;
    mesh.positions.reserve(image.texels.size());
    for (const glm::vec3& p : image.texels) mesh.positions.push_back(glm::dvec3(p));
    if (n < 2) return mesh;
    mesh.triangles.reserve(size_t(n - 1) * (n - 1) * 2);
    for (uint32_t y = 0; y + 1 < n; ++y)
        for (uint32_t x = 0; x + 1 < n; ++x) {
            const uint32_t a = y * n + x, b = a + 1, c = a + n + 1, d = a + n;
            mesh.triangles.push_back({a, b, c});
            mesh.triangles.push_back({a, c, d});
        }
    return mesh;
}

size_t peakResidentBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return size_t(std::stoull(line.substr(6))) * 1024;  // "VmHWM:  1234 kB"
    return 0;
}

namespace {

// BakeOptions::splitNecks: limbs cut off every component at their necks (unmatched: an
// experiment), all pieces largest first.
std::vector<TriangleMesh> splitAtNecksForExperiment(std::vector<TriangleMesh> components, const BakeOptions& options,
                                                    const std::string& name, BakeReport& report) {
    std::vector<std::pair<double, TriangleMesh>> split;
    for (TriangleMesh& component : components) {
        const ChartPartition partition = splitAtNecks(component, {.maxLimbs = options.splitNecks});
        for (TriangleMesh& piece : splitIntoPieces(component, partition.pieceOfFace)) {
            const double area = surfaceArea(piece);
            split.emplace_back(area, std::move(piece));
        }
    }
    std::stable_sort(split.begin(), split.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    report.warnings.push_back(format("%s: EXPERIMENTAL split into %zu pieces at necks (from %zu components): the pieces' "
                                     "shared borders are not matched across charts, so the asset cracks along them",
                                     name.c_str(), split.size(), components.size()));
    std::vector<TriangleMesh> parts;
    for (auto& [area, piece] : split) parts.push_back(std::move(piece));
    return parts;
}

// The cut search on a coarse remesh of `part` with `vertices` vertices (BakeOptions::
// cutSearchVertices; cutByPlan says why); nullopt where that remesh fails or changes the
// topology (the search then runs on the bake's remesh). `searchVertices` gets the remesh's size.
std::optional<ExtremityCutResult> coarseCutSearch(const TriangleMesh& part, const MeshTopology& topology, RemeshOptions coarse,
                                                  size_t vertices, const ExtremityCutOptions& cutOptions,
                                                  const BakeOptions& options, size_t& searchVertices) {
    try {
        coarse.targetVertexCount = vertices;
        const RemeshResult proxy = remeshIsotropic(part, coarse);
        const MeshTopology t = analyzeTopology(proxy.mesh);
        if (t.genus != topology.genus || t.boundaryLoops != topology.boundaryLoops || t.components != topology.components)
            throw Error(format("its remesh at %zu vertices has genus %ld and %zu boundary loops, the part %ld and %zu",
                               proxy.mesh.positions.size(), t.genus, t.boundaryLoops, topology.genus, topology.boundaryLoops));
        searchVertices = proxy.mesh.positions.size();
        return cutThroughExtremities(proxy.mesh, cutOptions);
    } catch (const Error& e) {
        if (options.progress) options.progress(std::string("cut search on a coarse remesh skipped: ") + e.what());
        searchVertices = 0;
        return std::nullopt;
    }
}

// The charts of one split component (BakeOptions::splitPieces), in piece order.
struct SplitCharts {
    std::vector<ChartReport> reports;
    std::vector<ChartBake> bakes;
    std::vector<RasterizedGeometryImage> images;
    std::vector<CrossSeamSegment> crossSeams;  // piece indices
    bool matched = false;                      // false: the split is abandoned (problem says why)
    std::string problem;
};

// BakeOptions::splitPieces for one component: remeshed once (or `premade`: its remesh at the
// density this function would ask for, already made by the one-chart bake that handed it over), its remesh cut into `pieces`
// geodesic Voronoi pieces that share its vertices, each cut to a disk and mapped to its own
// square, the borders matched together, each rasterized with its samples moved onto the
// component (one surface point projects the same way from both sides of a curve).
SplitCharts bakeSplitComponent(const TriangleMesh& component, double share, uint32_t pieces, uint32_t storedLevel,
                               const BakeOptions& options, BakeReport& report, int group, std::optional<RemeshResult> premade) {
    const std::string& name = options.sourceName;
    SplitCharts out;
    RemeshOptions remeshOptions;
    remeshOptions.targetVertexCount = remeshVertexCountFor(chartResolutionFor(options.resolution, storedLevel, share));
    remeshOptions.featureAngleDegrees = options.featureAngleDegrees;
    const RemeshResult remeshed = premade ? std::move(*premade)
                                          : runStage("remesh", options, report, [&] { return remeshIsotropic(component, remeshOptions); });
    std::vector<std::vector<uint32_t>> source;
    const std::vector<TriangleMesh> meshes = runStage("cut", options, report, [&] {
        ChartPartition partition = partitionByGeodesicVoronoi(remeshed.mesh, {.pieces = pieces});
        // Shared curves get four times the vertices: the matched border needs one near each
        // square corner that falls on them (a one-edge stretch has none).
        TriangleMesh refined = remeshed.mesh;
        refinePieceBorders(refined, partition.pieceOfFace, 2);
        return splitIntoPieces(refined, partition.pieceOfFace, &source);
    });
    announce(options, "remesh",
             format("split component %d: %zu vertices remeshed, cut into %zu Voronoi pieces", group,
                    remeshed.mesh.positions.size(), meshes.size()));
    const double area = surfaceArea(remeshed.mesh);
    std::vector<uint32_t> resolutions;  // each piece's share of the samples, as a component's
    for (const TriangleMesh& piece : meshes)
        resolutions.push_back(chartResolutionFor(options.resolution, storedLevel, share * surfaceArea(piece) / area));
    const uint32_t smallest = *std::min_element(resolutions.begin(), resolutions.end());
    std::vector<GroupChart> group_;
    out.reports.resize(meshes.size());
    out.bakes.resize(meshes.size());
    std::vector<ExtremityCutResult> cuts(meshes.size());
    for (size_t i = 0; i < meshes.size(); ++i) {
        ChartReport& chart = out.reports[i];
        ChartBake& bake = out.bakes[i];
        const std::string pieceName = format("piece %zu/%zu of split component %d: ", i + 1, meshes.size(), group);
        chart.splitGroup = group;
        chart.topology = analyzeTopology(meshes[i]);
        chart.areaFraction = share * surfaceArea(meshes[i]) / area;
        chart.resolution = resolutions[i];
        chart.remesh = remeshed.report;
        ExtremityCutOptions cutOptions;
        cutOptions.progress = options.progress;
        cuts[i] = runStage("cut", options, report, [&] {
            ExtremityCutResult cut = cutThroughExtremities(meshes[i], cutOptions);
            // A piece with no cut path has only shared curves and open segments on its border:
            // nothing in it can absorb a length the group's system asks of it. A slit from its
            // deepest vertex to the border gives it a cut path whose length is free.
            if (findSeamEdges(cut.cut.disk).mates.empty()) {
                const uint32_t deepest = deepestVertex(meshes[i]);
                if (deepest != kNoFace) {
                    cut.cut = cutToDisk(meshes[i], {.extremities = {deepest}});
                    cut.conformalStart.reset();
                    cut.conformalStartFailed = false;
                }
            }
            return cut;
        });
        chart.cut = cuts[i].cut.report;
        chart.cutConformalShrink = cuts[i].conformalShrink;
        chart.cutRounds = cuts[i].rounds.size();
        bake.disk = cuts[i].cut.disk;
        ParameterizeOptions mapOptions;
        mapOptions.method = options.method;
        mapOptions.progress = options.progress;
        mapOptions.detailDensity = options.detailDensity;
        if (cuts[i].conformalStart) mapOptions.conformalStart = &*cuts[i].conformalStart;
        mapOptions.conformalStartFailed = cuts[i].conformalStartFailed;
        bake.map = runStage("parameterize", options, report, [&] { return parameterizeToSquare(bake.disk, mapOptions); });
        if (bake.map.report.flippedTriangles != 0)
            throw Error(name + ": " + pieceName + "parameterize: the map flips " + std::to_string(bake.map.report.flippedTriangles) +
                        " triangles (not bijective)");
        chart.parameterization = bake.map.report;
        chart.undersampledAreaFraction = undersampledAreaFraction(bake.disk.mesh, bake.map.uv, kUndersampling);
        announce(options, "parameterize",
                 pieceName + format("genus %ld, %zu boundary loops, ot %d it, area distortion mean %.3f max %.3f, %.2f%% undersampled",
                                    chart.topology.genus, chart.topology.boundaryLoops, bake.map.report.otIterations,
                                    bake.map.report.areaDistortionMean, bake.map.report.areaDistortionMax,
                                    100.0 * chart.undersampledAreaFraction));
        GroupChart& g = group_.emplace_back();
        g.disk = &bake.disk;
        g.map = &bake.map;
        g.resolution = resolutions[i];
        g.groupVertex.assign(bake.disk.mesh.positions.size(), kNoGroupVertex);
        for (size_t v = 0; v < g.groupVertex.size(); ++v) {
            const uint32_t original = bake.disk.originalVertex[v];
            if (original < source[i].size()) g.groupVertex[v] = source[i][original];
        }
    }
    const uint32_t levelLimit = seamLevelLimit(mipLevelCount(smallest + 1));
    MatchedGroup matched =
        runStage("match seams", options, report, [&] { return matchBorders(group_, levelLimit, 0.05, 2, storedLevel); });
    if (matched.matched && matched.level < storedLevel)
        report.warnings.push_back(format("%s: split component %d: its shared borders match down to level %u only, finer than "
                                         "the stored level %u: its charts draw no coarser level",
                                         name.c_str(), group, matched.level, storedLevel));
    if (!matched.matched) {  // a cracked split is never shipped: the caller bakes the component as one chart
        out.problem = matched.problem;
        return out;
    }
    out.matched = true;
    announce(options, "match seams",
             format("split component %d: %zu shared curves matched (%zu repair walks), watertight to level %u", group,
                    matched.sharedCurves, matched.repairWalks, matched.level));
    out.crossSeams = matched.crossSeams;
    std::vector<ChartSeams> seams;
    for (size_t i = 0; i < meshes.size(); ++i) {
        ChartReport& chart = out.reports[i];
        ChartBake& bake = out.bakes[i];
        chart.seam = matched.charts[i].report;  // matched: every chart of the group is
        bake.map.uv = std::move(matched.charts[i].uv);
        bake.map.corners = matched.charts[i].corners;
        bake.seams = matched.charts[i].seams;
        const MapDistortion d = measureDistortion(bake.disk.mesh, bake.map.uv);
        chart.seamAreaDistortionMax = d.areaMax;
        chart.seamAreaDistortionMean = d.areaMean;
        seams.push_back(bake.seams);
        out.images.push_back(runStage("rasterize", options, report, [&] {
            RasterizedGeometryImage image = rasterizeGeometryImage(bake.disk, bake.map.uv, resolutions[i]);
            if (options.transferDetail)
                chart.detail = transferDetail(component, image.positions, image.normals,
                                              {.maxDistance = 0.5 * remeshed.report.targetEdgeLength});
            return image;
        }));
    }
    std::vector<GeometryImage*> positions, normals;
    for (RasterizedGeometryImage& image : out.images) positions.push_back(&image.positions), normals.push_back(&image.normals);
    const double gap = weldGroupSeams(positions, seams, resolutions, out.crossSeams, 0);
    weldGroupSeams(normals, seams, resolutions, out.crossSeams, 0);
    for (ChartReport& chart : out.reports) chart.crossSeamGapBeforeWeld = gap;
    announce(options, "rasterize",
             format("split component %d: %zu images of %u to %u samples per side, shared borders' gap %.2g welded", group,
                    meshes.size(), smallest + 1, *std::max_element(resolutions.begin(), resolutions.end()) + 1, gap));
    return out;
}

} // namespace

bool anyComponentSplitForThinParts(const BakeReport& report)
{
    for (const ChartReport& c : report.charts)
        if (!c.splitForThinParts.empty()) return true;
    return false;
}

BakeResult bakeMesh(const TriangleMesh& input, const BakeOptions& options) {
    const std::string& name = options.sourceName;
    if (!std::has_single_bit(options.resolution) || options.resolution < 2 || options.resolution > kMaxFullResolution)
        throw Error(name + ": --resolution " + std::to_string(options.resolution) + " is not a power of two in [2, " +
                    std::to_string(kMaxFullResolution) + "] (the largest image every tool renders)");
    if (!std::has_single_bit(options.storeResolution) || options.storeResolution < 1 || options.storeResolution > options.resolution)
        throw Error(name + ": --store-res " + std::to_string(options.storeResolution) +
                    " is not a power of two in [1, resolution = " + std::to_string(options.resolution) + "]");
    const Clock::time_point bakeStart = Clock::now();
    BakeResult result;
    BakeReport& report = result.report;
    report.method = parameterizationName(options.method);
    report.detailDensity = options.method == ParameterizationMethod::OptimalTransport ? options.detailDensity : 0.0;

    // Stage 2: clean (repair; every component kept).
    CleanResult cleaned = runStage("clean", options, report, [&] { return cleanMesh(input, {.sourceName = name}); });
    report.clean = cleaned.report;
    report.cleaned = analyzeTopology(cleaned.mesh);
    report.warnings = cleaned.report.warnings;
    std::vector<TriangleMesh> parts = splitComponents(cleaned.mesh);
    if (options.splitNecks > 0) parts = splitAtNecksForExperiment(std::move(parts), options, name, report);
    if (parts.size() > kMaxCharts)
        throw Error(name + ": the mesh has " + std::to_string(parts.size()) + " connected components, more than the " +
                    std::to_string(kMaxCharts) + " charts an asset holds");
    announce(options, "clean",
             format("%zu vertices, %zu triangles, %zu component%s, genus %ld, %zu boundary loops", report.cleaned.vertices,
                    report.cleaned.faces, parts.size(), parts.size() == 1 ? "" : "s (one chart each)",
                    parts.size() == 1 ? report.cleaned.genus : long(0), report.cleaned.boundaryLoops));

    std::vector<double> areas;
    double totalArea = 0.0;
    for (const TriangleMesh& part : parts) totalArea += areas.emplace_back(surfaceArea(part));
    const uint32_t storedLevel = uint32_t(std::countr_zero(options.resolution / options.storeResolution));
    std::vector<RasterizedGeometryImage> images;
    // Components split into matched charts become groups of charts (bakeSplitComponent):
    // BakeOptions::splitPieces splits every component with a large enough share, first;
    // splitThinParts those whose one-chart bake below finds thin parts, which it hands over.
    std::vector<CrossSeamSegment> crossSeams;
    int group = 0;
    auto addGroup = [&](SplitCharts& split, const std::string& thinParts) {
        ++group;
        const uint32_t base = uint32_t(report.charts.size());
        for (CrossSeamSegment g : split.crossSeams) {
            g.chartA += base, g.chartB += base;
            crossSeams.push_back(g);
        }
        for (size_t i = 0; i < split.reports.size(); ++i) {
            split.reports[i].splitForThinParts = thinParts;
            report.charts.push_back(std::move(split.reports[i]));
            result.charts.push_back(std::move(split.bakes[i]));
            images.push_back(std::move(split.images[i]));
        }
    };
    auto abandoned = [&](const SplitCharts& split) {
        report.warnings.push_back(format("%s: the split of component %d was abandoned, it is baked as one chart: its "
                                         "pieces' shared borders could not be matched (%s)",
                                         name.c_str(), group, split.problem.c_str()));
    };
    auto shareOf = [&](size_t c) { return totalArea > 0.0 ? areas[c] / totalArea : 1.0; };
    auto piecesFor = [&](size_t c, uint32_t perWhole) { return uint32_t(std::lround(perWhole * shareOf(c))); };
    if (options.splitPieces > 1) {
        std::vector<TriangleMesh> rest;
        std::vector<double> restAreas;
        for (size_t c = 0; c < parts.size(); ++c) {
            const uint32_t k = piecesFor(c, options.splitPieces);
            SplitCharts split;
            if (k >= 2) {
                split = bakeSplitComponent(parts[c], shareOf(c), k, storedLevel, options, report, group, std::nullopt);
                if (!split.matched) abandoned(split);
            }
            if (k < 2 || !split.matched) {
                rest.push_back(std::move(parts[c]));
                restAreas.push_back(areas[c]);
                continue;
            }
            addGroup(split, "");
        }
        parts = std::move(rest);
        areas = std::move(restAreas);
        if (group > 0)
            report.warnings.push_back(format("%s: EXPERIMENTAL split of %d component%s into %zu matched Voronoi pieces "
                                             "(format 7: readers before it refuse the asset); on compact shapes one chart "
                                             "per component is closer to the input at the same bytes",
                                             name.c_str(), group, group == 1 ? "" : "s", report.charts.size()));
    }
    const bool splitThin = options.splitPieces <= 1 && options.splitThinParts > 1;
    // A component handed over by its one-chart bake: why (for the report), its genus and its
    // coarse remesh where one was made.
    struct HandOver {
        size_t part = 0;
        std::string reason;
        long genus = 0;
        std::optional<RemeshResult> remesh;
    };
    std::vector<HandOver> handedOver;
    // One chart for parts[c]. With `mayHandOver`, a part found to have thin parts (where the
    // dense remesh would be needed) is handed over to the split instead: its report and bake
    // entries are removed again, `handedOver` gets it, and false is returned.
    auto bakeWhole = [&](size_t c, bool mayHandOver) -> bool {
        // Errors and summaries of a multi-chart bake name the chart.
        const std::string chartName = parts.size() == 1 ? "" : format("chart %zu/%zu: ", c + 1, parts.size());
        BakeOptions chartOptions = options;
        chartOptions.sourceName = name;
        ChartReport& chart = report.charts.emplace_back();
        chart.topology = analyzeTopology(parts[c]);
        chart.areaFraction = shareOf(c);
        chart.resolution = chartResolutionFor(options.resolution, storedLevel, chart.areaFraction);
        ChartBake& bake = result.charts.emplace_back();
        auto stage = [&](const char* stageName, auto&& function) {
            try {
                return runStage(stageName, chartOptions, report, function);
            } catch (const Error& e) {
                if (chartName.empty()) throw;
                const std::string message = e.what();
                const std::string prefix = name + ": ";
                throw Error(prefix + chartName + (message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message));
            }
        };

        // Stage 3: isotropic remeshing to the target density (the chart's share of samples).
        RemeshOptions remeshOptions;
        remeshOptions.targetVertexCount =
            options.remeshVertexCount
                ? std::max<size_t>(size_t(double(options.remeshVertexCount) * chart.areaFraction), 200)
                : remeshVertexCountFor(chart.resolution);
        remeshOptions.featureAngleDegrees = options.featureAngleDegrees;
        const bool adaptive = options.transferDetail && !options.remeshVertexCount;
        const size_t dense = std::max(remeshOptions.targetVertexCount, remeshVertexCountForThinParts(chart.resolution));
        RemeshResult remeshed;
        ExtremityCutResult cut;
        const size_t coarseCount = remeshOptions.targetVertexCount;
        const bool handOver = mayHandOver && adaptive && splitThin && piecesFor(c, options.splitThinParts) >= 2;
        auto handOverToSplit = [&](std::string reason, std::optional<RemeshResult> coarse) {
            if (options.progress) options.progress(reason + ": the part has thin parts, it is split instead of remeshed densely");
            handedOver.push_back({c, std::move(reason), chart.topology.genus, std::move(coarse)});
            report.charts.pop_back();
            result.charts.pop_back();
            return false;
        };
        ExtremityCutOptions cutOptions;
        cutOptions.progress = options.progress;
        // The cut search, once per chart on a coarse remesh of the part when the bake's remesh
        // is much denser (cutByPlan says why); the chosen cut is then made on each remesh. If
        // the coarse remesh fails or changes the topology, the search runs on the remesh itself.
        // So many handles that one chart maps them badly whatever the cut (the highest genus one
        // chart bakes well in data/meshes is 11; cheese, 133, is refused by its image check
        // after a 17 s cut search): split at once.
        if (handOver && chart.topology.genus > kMaxOneChartGenus)
            return handOverToSplit(format("genus %ld, above the %ld one chart is tried for", chart.topology.genus, kMaxOneChartGenus),
                                   std::nullopt);
        std::optional<ExtremityCutResult> search;
        if (options.cutSearchVertices > 0 && remeshOptions.targetVertexCount > 2 * options.cutSearchVertices) {
            search = stage("cut search", [&] {
                return coarseCutSearch(parts[c], chart.topology, remeshOptions, options.cutSearchVertices, cutOptions, options,
                                       chart.cutSearchVertices);
            });
            if (search) {
                chart.cutRounds = search->rounds.size();
                announce(options, "cut search",
                         chartName + format("%zu cuts measured on a %zu-vertex remesh: %s + %zu extremity paths, conformal "
                                            "shrink e^%.3g",
                                            search->rounds.size(), chart.cutSearchVertices, search->cut.report.method.c_str(),
                                            search->cut.report.extremityPaths, search->conformalShrink));
            }
            // The shrink of a cut grew with the remesh density where we measured it (femur:
            // e^11.7 at 6k vertices, the flow fails at 32k and 64k), so a search past the coarse
            // limit means the coarse remesh would be re-done dense below: remesh dense at once.
            // A flow that failed only on the coarse remesh decides nothing (the remesh decides).
            if (adaptive && search && !std::isnan(search->conformalShrink) &&
                search->conformalShrink > kMaxCoarseRemeshShrink && remeshOptions.targetVertexCount < dense) {
                if (handOver)
                    return handOverToSplit(format("conformal shrink e^%.3g > e^%.3g on the cut search's %zu-vertex remesh",
                                                  search->conformalShrink, kMaxCoarseRemeshShrink, chart.cutSearchVertices),
                                           std::nullopt);
                if (options.progress)
                    options.progress(format("conformal shrink e^%.3g > e^%.3g on the cut search's remesh: remeshing at %zu "
                                            "vertices", search->conformalShrink, kMaxCoarseRemeshShrink, dense));
                remeshOptions.targetVertexCount = dense;
                chart.remeshForThinParts = true;
            }
        }
        // Stages 5b-7 on the map: the checks, seams and image; throws where the chart is refused.
        auto finishChart = [&] {
            // Set only where the seams match: a retried chart must not keep the failed attempt's.
            chart.seamAreaDistortionMax = chart.seamAreaDistortionMean = chart.seamGapBeforeWeld = 0.0;
            const ParameterizeReport& p = chart.parameterization = bake.map.report;
            announce(options, "parameterize",
                     chartName + format("%s: ricci %d it (residual %.2g), ot %d it (residual %.2g), area distortion mean %.3f "
                                        "max %.3f, angle distortion mean %.3f, %zu flipped",
                                        report.method.c_str(), p.ricciIterations, p.ricciResidual, p.otIterations,
                                        p.otResidual, p.areaDistortionMean, p.areaDistortionMax, p.angleDistortionMean,
                                        p.flippedTriangles));

            // Where the map squeezes the surface, the geometry image has almost no samples: say so.
            chart.undersampledAreaFraction = undersampledAreaFraction(bake.disk.mesh, bake.map.uv, kUndersampling);
            // A map that squeezes a fifth of the chart is garbage (cheese, genus 133): refuse it.
            checkChartSampling(chart.undersampledAreaFraction,
                               {.file = name, .chart = c, .charts = parts.size(), .genus = chart.topology.genus});
            if (chart.undersampledAreaFraction > 1e-3)
                report.warnings.push_back(format("%s: %s%.2f%% of the surface gets less than 1/%.0f of its fair share of "
                                                 "samples (max area distortion e^%.1f): expect holes or streaks there",
                                                 name.c_str(), chartName.c_str(), 100.0 * chart.undersampledAreaFraction,
                                                 kUndersampling, p.areaDistortionMax));

            // Stage 6b: match the border so that the two sides of every cut sample the same points
            // at every level down to the coarsest watertight one (Gu et al. 2002, section 4).
            MatchedBorder matched = stage("match seams", [&] {
                if (!options.matchSeams) {
                    MatchedBorder unmatched;
                    unmatched.report.problem = "matching turned off";
                    return unmatched;
                }
                return matchBorder(bake.disk, bake.map, chart.resolution, seamLevelLimit(mipLevelCount(chart.resolution + 1)));
            });
            chart.seam = matched.report;
            bake.seams = matched.seams;
            if (matched.report.matched) {
                bake.map.uv = std::move(matched.uv);
                bake.map.corners = matched.corners;
                const MapDistortion d = measureDistortion(bake.disk.mesh, bake.map.uv);
                chart.seamAreaDistortionMax = d.areaMax;
                chart.seamAreaDistortionMean = d.areaMean;
                announce(options, "match seams",
                         chartName + format("%zu cut paths matched%s, watertight to level %u (%ux%u), border lengths changed "
                                            "%.1f%% (sides' mismatch %.1f%%), area distortion mean %.3f max %.3f",
                                            matched.report.cutPaths, matched.report.movedCorners ? " (corners moved)" : "",
                                            matched.report.level,
                                            (chart.resolution >> matched.report.level) + 1,
                                            (chart.resolution >> matched.report.level) + 1, 100.0 * matched.report.lengthChange,
                                            100.0 * matched.report.mismatch, d.areaMean, d.areaMax));
            } else if (options.matchSeams) {
                report.warnings.push_back(format("%s: %sthe seam could not be matched (%s): it may crack", name.c_str(),
                                                 chartName.c_str(), matched.report.problem.c_str()));
            }
            if (!matched.report.matched) announce(options, "match seams", chartName + "not matched: " + matched.report.problem);

            // Stage 7: rasterize, then weld the mates (equal up to rounding) bitwise.
            images.push_back(stage("rasterize", [&] {
                RasterizedGeometryImage image = rasterizeGeometryImage(bake.disk, bake.map.uv, chart.resolution);
                if (options.transferDetail)
                    chart.detail = transferDetail(parts[c], image.positions, image.normals,
                                                  {.maxDistance = 0.5 * chart.remesh.targetEdgeLength});
                return image;
            }));
            // The image check (sampling_check.h): how much of the input the map's image misses, or
            // adds (spikes), on a level of at most 257^2 samples (the 1025^2 image's mesh would cost
            // seconds; a 5% distance does not need it). The full image, not the stored level: a
            // stored level too coarse for the shape is the resolution's doing, not the map's.
            {
                const GeometryImage& full = images.back().positions;
                const uint32_t step = std::max<uint32_t>(1, (full.size - 1) / 256);
                GeometryImage coarse;
                coarse.size = (full.size - 1) / step + 1;
                coarse.texels.reserve(size_t(coarse.size) * coarse.size);
                for (uint32_t y = 0; y < coarse.size; ++y)
                    for (uint32_t x = 0; x < coarse.size; ++x) coarse.texels.push_back(full.at(x * step, y * step));
                glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
                for (const glm::dvec3& p : parts[c].positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
                const double side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
                const TriangleMesh stored = geometryImageMesh(coarse);
                chart.farFromImageArea = std::max(areaFartherThan(parts[c], stored, kFarFromImageDistance * side),
                                                  areaFartherThan(stored, parts[c], kFarFromImageDistance * side));
                checkChartImage(chart.farFromImageArea,
                                {.file = name, .chart = c, .charts = parts.size(), .genus = chart.topology.genus});
            }
            if (bake.seams.matched) {
                const std::vector<uint32_t> table = seamWeldTable(bake.seams, chart.resolution);
                chart.seamGapBeforeWeld = measureSeamGap(images.back().positions, table).maxDistance;
                weldSeams(images.back().positions, table);
                weldSeams(images.back().normals, table);
            }
            announce(options, "rasterize",
                     chartName + format("%ux%u samples%s", images.back().positions.size, images.back().positions.size,
                                        bake.seams.matched ? format(", seam gap %.2g welded", chart.seamGapBeforeWeld).c_str() : "") +
                         (options.transferDetail
                              ? format(", detail from the input: %zu samples moved (mean %.2g, max %.2g), %zu kept",
                                       chart.detail.projected, chart.detail.meanDistance, chart.detail.maxDistance, chart.detail.kept)
                              : std::string()));
        };
        // The dense remesh is tried where it should pay; if its map fails, the coarse one once.
        for (bool denseAllowed = true;; denseAllowed = false) {
            for (;;) {
                bool farFromInput = false;  // the remesh cuts through thin parts: handed over
                remeshed = stage("remesh", [&] {
                    RemeshResult result = remeshIsotropic(parts[c], remeshOptions);
                    // The remesh carries the map only if it follows the input: where it cuts through
                    // a thin part (antlers, claws) by more than the transfer may move a sample, those
                    // samples stay off the input. Remesh denser then, up to the dense count.
                    while (adaptive) {
                        const double limit = 0.5 * result.report.targetEdgeLength;  // as the transfer's
                        chart.remeshFarArea = std::max(areaFartherThan(result.mesh, parts[c], limit),   // cut through
                                                       areaFartherThan(parts[c], result.mesh, limit));  // cut off
                        if (chart.remeshFarArea <= kMaxRemeshFarArea || remeshOptions.targetVertexCount * 2 > dense) break;
                        if (handOver && remeshOptions.targetVertexCount == coarseCount) {
                            farFromInput = true;
                            break;
                        }
                        remeshOptions.targetVertexCount *= 2;
                        result = remeshIsotropic(parts[c], remeshOptions);
                        ++chart.remeshDensified;
                    }
                    return result;
                });
                if (farFromInput) {
                    std::string reason = format("%.3g%% of the %zu-vertex remesh off the input by more than half an edge",
                                                100.0 * chart.remeshFarArea, remeshed.mesh.positions.size());
                    return handOverToSplit(std::move(reason), std::move(remeshed));
                }
                chart.remesh = remeshed.report;
                announce(options, "remesh",
                         chartName + format("%zu -> %zu vertices, %zu triangles, edge %.4g, min angle %.1f deg, %zu feature edges, "
                                            "%.3g%% of it off the input by > edge/2%s%s",
                                            chart.remesh.inputVertices, chart.remesh.outputVertices, chart.remesh.outputTriangles,
                                            chart.remesh.targetEdgeLength, chart.remesh.minAngleDegrees, chart.remesh.featureEdges,
                                            100.0 * chart.remeshFarArea,
                                            chart.remeshDensified ? format(" (densified %zux)", size_t(1) << chart.remeshDensified).c_str() : "",
                                            chart.remesh.droppedFeatureEdges
                                                ? format(" (%zu creases dropped: they made %.1f deg slivers)",
                                                         chart.remesh.droppedFeatureEdges, chart.remesh.minAngleWithFeaturesDegrees)
                                                      .c_str()
                                                : ""));

                // Stage 4: cut to a disk, through extremities (Gu et al. 2002) so the conformal start
                // of OT does not shrink an uncut protrusion beyond what the power diagram separates.
                cut = stage("cut", [&] {
                    return search ? cutByPlan(remeshed.mesh, search->plan, cutOptions)
                                  : cutThroughExtremities(remeshed.mesh, cutOptions);
                });
                chart.cut = cut.cut.report;
                chart.cutConformalShrink = cut.conformalShrink;
                chart.cutRounds += cut.rounds.size();
                announce(options, "cut",
                         chartName + format("%s + %zu extremity paths: genus %ld, %zu boundary loops, cut length %.4g (%zu edges), "
                                            "%zu boundary vertices, conformal shrink e^%.3g%s",
                                            chart.cut.method.c_str(), chart.cut.extremityPaths, chart.cut.genus,
                                            chart.cut.boundaryLoops, chart.cut.cutLength, chart.cut.cutEdges,
                                            chart.cut.diskBoundaryVertices, cut.conformalShrink,
                                            search ? format(" (searched over %zu cuts of a %zu-vertex remesh)",
                                                            search->rounds.size(), chart.cutSearchVertices).c_str()
                                                   : ""));
                // Protrusions the conformal start shrinks strongly (legs, limbs) get few samples per
                // remesh triangle from OT; there the coarse remesh's map undersamples them (camel at
                // 1024, LoD-0 CD x1e-4: R^2/64 0.44, R^2/32 0.32, R^2/16 0.042; shapes below e^8, such
                // as bunny00, fandisk, knot1, lose nothing). Such charts are remeshed at the dense count.
                if (!adaptive || !denseAllowed || cut.conformalShrink <= kMaxCoarseRemeshShrink ||
                    remeshOptions.targetVertexCount >= dense)
                    break;
                if (handOver) {  // a flow that failed here (NaN) sent the chart to the dense remesh too
                    std::string reason =
                        std::isnan(cut.conformalShrink)
                            ? format("no conformal start on the %zu-vertex remesh (the flow failed)", remeshed.mesh.positions.size())
                            : format("conformal shrink e^%.3g > e^%.3g on the %zu-vertex remesh", cut.conformalShrink,
                                     kMaxCoarseRemeshShrink, remeshed.mesh.positions.size());
                    return handOverToSplit(std::move(reason), std::move(remeshed));
                }
                if (options.progress)
                    options.progress(format("conformal shrink e^%.3g > e^%.3g: remeshing at %zu vertices", cut.conformalShrink,
                                            kMaxCoarseRemeshShrink, dense));
                remeshOptions.targetVertexCount = dense;
                chart.remeshForThinParts = true;
            }
            bake.disk = std::move(cut.cut.disk);

            // Stages 5-6: map to the square.
            ParameterizeOptions mapOptions;
            mapOptions.method = options.method;
            mapOptions.progress = options.progress;
            mapOptions.detailDensity = options.detailDensity;
            if (cut.conformalStart) mapOptions.conformalStart = &*cut.conformalStart;  // measured by the cut stage
            mapOptions.conformalStartFailed = cut.conformalStartFailed;
            const size_t warningsBefore = report.warnings.size(), imagesBefore = images.size();
            try {
                bake.map = stage("parameterize", [&] { return parameterizeToSquare(bake.disk, mapOptions); });
                if (bake.map.report.flippedTriangles != 0)
                    throw Error(name + ": " + chartName + "parameterize: the " + report.method + " map flips " +
                                std::to_string(bake.map.report.flippedTriangles) + " triangles (not bijective)");
                finishChart();
                break;
            } catch (const Error& e) {
                // The dense remesh is for thin limbs; on a part whose shrink comes from many handles
                // it can make the map worse (couplingdown, genus 9, at 1024: conformal e^102 at 65k
                // vertices against e^37 at 6k, 354 flips; baked at 16k in 32 s), or its image can
                // leave out what the coarse one keeps (boeing, genus 10: 5.9% far from the image
                // in one bake, 0% in others; the dense map of so many handles is on a knife's
                // edge). Then the coarse remesh is baked instead, once, and what the failed
                // attempt added to the report and images is dropped.
                if (!chart.remeshForThinParts || !denseAllowed) throw;
                report.warnings.resize(warningsBefore);
                images.erase(images.begin() + long(imagesBefore), images.end());
                if (options.progress)
                    options.progress(std::string("the dense remesh's chart failed (") + e.what() + "): baking the coarse remesh");
                remeshOptions.targetVertexCount = coarseCount;
                chart.remeshForThinParts = false;
                chart.remeshDensified = 0;
                chart.denseRemeshFailed = true;
                chart.denseRemeshProblem = e.what();
            }
        }
        return true;
    };
    for (size_t c = 0; c < parts.size(); ++c) bakeWhole(c, true);
    for (HandOver& h : handedOver) {
        // A part of genus g gets at least g/2 pieces, so each piece keeps a genus near 2: a piece
        // with many handles maps as badly as the whole (cheese, genus 133, LoD-0 CD x1e-4 / HD
        // x1e-2 against the input: 8 pieces 2.45 / 9.93, 32 0.64 / 6.18, 64 0.198 / 4.19, 128
        // 0.164 / 4.38). Capped so that the asset holds at most kMaxCharts charts.
        const size_t after = handedOver.size() - size_t(&h - handedOver.data()) - 1;  // one chart each at least
        const size_t used = report.charts.size() + after;
        const size_t room = used < kMaxCharts ? kMaxCharts - used : 0;
        const uint32_t k = uint32_t(std::clamp<size_t>(std::max<size_t>(piecesFor(h.part, options.splitThinParts), size_t(h.genus + 1) / 2),
                                                       2, std::max<size_t>(2, room)));
        announce(options, "cut search",
                 format("component %zu of %zu has thin parts (%s): split into %u matched charts", h.part + 1, parts.size(),
                        h.reason.c_str(), k));
        SplitCharts split =
            bakeSplitComponent(parts[h.part], shareOf(h.part), k, storedLevel, options, report, group, std::move(h.remesh));
        if (split.matched) {
            addGroup(split, h.reason);
        } else {
            abandoned(split);
            bakeWhole(h.part, false);
        }
    }

    // The largest resolution first (split pieces may be smaller than an unsplit component).
    {
        std::vector<size_t> order(report.charts.size());
        std::iota(order.begin(), order.end(), size_t(0));
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t a, size_t b) { return report.charts[a].resolution > report.charts[b].resolution; });
        std::vector<uint32_t> at(order.size());
        std::vector<ChartReport> reports;
        std::vector<ChartBake> bakes;
        std::vector<RasterizedGeometryImage> sorted;
        for (size_t i = 0; i < order.size(); ++i) {
            at[order[i]] = uint32_t(i);
            reports.push_back(std::move(report.charts[order[i]]));
            bakes.push_back(std::move(result.charts[order[i]]));
            sorted.push_back(std::move(images[order[i]]));
        }
        report.charts = std::move(reports);
        result.charts = std::move(bakes);
        images = std::move(sorted);
        for (CrossSeamSegment& g : crossSeams) {
            g.chartA = at[g.chartA], g.chartB = at[g.chartB];
            if (g.chartA > g.chartB) std::swap(g.chartA, g.chartB), std::swap(g.a, g.b);
        }
        result.crossSeams = std::move(crossSeams);
    }

    // Stage 8: one normalization for all charts, nested mip level, asset.
    runStage("store", options, report, [&] {
        Asset& asset = result.asset;
        asset.sourceName = name;
        asset.sourceHash = options.sourceHash;
        GeometryImage all;  // the bounding box of every chart
        for (const RasterizedGeometryImage& image : images)
            all.texels.insert(all.texels.end(), image.positions.texels.begin(), image.positions.texels.end());
        normalizationFor(all, asset.offset, asset.scale);
        asset.parameterization = report.method;
        for (size_t c = 0; c < images.size(); ++c) {
            ChartBake& bake = result.charts[c];
            bake.fullPositions = std::move(images[c].positions);
            for (glm::vec3& t : bake.fullPositions.texels)
                t = glm::clamp((t - asset.offset) / asset.scale, glm::vec3(0.0f), glm::vec3(1.0f));
            bake.fullNormals = std::move(images[c].normals);
            AssetChart& chart = asset.charts.emplace_back();
            chart.fullResolution = report.charts[c].resolution;
            chart.storedLevel = storedLevel;
            storeGeometryImage(chart, downsampleNested(bake.fullPositions, storedLevel),
                               downsampleNested(bake.fullNormals, storedLevel));
            chart.seams = bake.seams;
        }
        asset.crossSeams = result.crossSeams;
        report.totalSeconds = secondsSince(bakeStart);
        nlohmann::json metadata;
        metadata["bake"] = bakeReportJson(report);
        asset.metadataJson = metadata.dump();
        return 0;
    });
    report.totalSeconds = secondsSince(bakeStart);
    const AssetChart& largest = result.asset.charts[0];
    announce(options, "store",
             format("level %u kept: %ux%u samples (CR %.0f)%s", largest.storedLevel, largest.storedSize(), largest.storedSize(),
                    double(options.resolution) * options.resolution /
                        (double(options.storeResolution) * options.storeResolution),
                    result.asset.charts.size() > 1 ? format(" in the largest of %zu charts", result.asset.charts.size()).c_str() : ""));
    return result;
}

uint32_t chartResolutionFor(uint32_t resolution, uint32_t storedLevel, double areaFraction) {
    const double ideal = double(resolution) * std::sqrt(std::clamp(areaFraction, 0.0, 1.0));
    uint32_t r = ideal >= 1.0 ? 1u << uint32_t(std::lround(std::log2(ideal))) : 1u;
    r = std::max({r, kMinChartResolution, 1u << storedLevel});
    return std::min(r, resolution);
}

} // namespace ngi
