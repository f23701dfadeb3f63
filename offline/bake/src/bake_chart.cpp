// ngi offline: one component baked as one chart, stages 3-7 of the bake. Paper section 3.2
// "Input Precondition" (isotropic remesh, cut to a disk) and section 3.1 "Optimal Transport for
// Geometry Images" (conformal start by discrete Ricci flow, Eq. 1-2; optimal transport by power
// diagrams and Newton, Alg. 1, Eq. 4-6), then the matched border (Gu et al. 2002, section 4)
// and the geometry image sampled on the input.
#include "bake_stages.h"

#include "ngi/mip_pyramid.h"
#include "ngi/param/distortion.h"
#include "ngi/param/extremity_cut.h"
#include "ngi/param/sampling_check.h"

#include <glm/common.hpp>

namespace ngi::detail {
namespace {

// The cut search on a coarse remesh of `part` with `vertices` vertices (BakeOptions::
// cutSearchVertices; cutByPlan says why); nullopt where that remesh fails or changes the
// topology (the search then runs on the bake's remesh). `searchVertices` gets the remesh's size.
std::optional<ExtremityCutResult> coarseCutSearch(const TriangleMesh& part, const MeshTopology& topology,
                                                  RemeshOptions coarse, size_t vertices,
                                                  const ExtremityCutOptions& cutOptions, const BakeOptions& options,
                                                  size_t& searchVertices)
{
    try {
        coarse.targetVertexCount = vertices;
        const RemeshResult proxy = remeshIsotropic(part, coarse);
        const MeshTopology t = analyzeTopology(proxy.mesh);
        if (t.genus != topology.genus || t.boundaryLoops != topology.boundaryLoops ||
            t.components != topology.components)
            throw Error(format("its remesh at %zu vertices has genus %ld and %zu boundary loops, the part %ld and %zu",
                               proxy.mesh.positions.size(), t.genus, t.boundaryLoops, topology.genus,
                               topology.boundaryLoops));
        searchVertices = proxy.mesh.positions.size();
        return cutThroughExtremities(proxy.mesh, cutOptions);
    } catch (const Error& e) {
        if (options.progress) options.progress(std::string("cut search on a coarse remesh skipped: ") + e.what());
        searchVertices = 0;
        return std::nullopt;
    }
}

// One chart in the making: the component it maps and where its results go.
struct ChartWork {
    const BakeOptions& options;
    BakeReport& report;
    const TriangleMesh& part;  // the component; the samples are moved onto it
    size_t index = 0;          // the component's index among `count` (messages and checks)
    size_t count = 0;
    std::string name;  // "chart i/n: " where the bake has several charts, else empty
    ChartReport& chart;
    ChartBake& bake;
    // The last resort (bakeChartLastResort): the image checks warn instead of refusing.
    bool lastResort = false;
};

// runStage for one chart: in a bake of several charts, its errors name the chart after the
// source ("SOURCE: chart i/n: stage: problem").
template <typename Function> auto chartStage(const ChartWork& work, const char* stage, Function&& function)
{
    try {
        return runStage(stage, work.options, work.report, function);
    } catch (const Error& e) {
        if (work.name.empty()) throw;
        const std::string message = e.what();
        const std::string prefix = work.options.sourceName + ": ";
        throw Error(prefix + work.name + (message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message));
    }
}

// The cut search on a coarse remesh of the part (coarseCutSearch at BakeOptions::
// cutSearchVertices), timed as the "cut search" stage; records the rounds and the remesh's size
// in the chart's report and announces them. nullopt where the search falls back to the remesh.
std::optional<ExtremityCutResult> searchCutOnCoarseRemesh(ChartWork& work, const RemeshOptions& remeshOptions,
                                                          const ExtremityCutOptions& cutOptions)
{
    const BakeOptions& options = work.options;
    ChartReport& chart = work.chart;
    std::optional<ExtremityCutResult> search = chartStage(work, "cut search", [&] {
        return coarseCutSearch(work.part, chart.topology, remeshOptions, options.cutSearchVertices, cutOptions, options,
                               chart.cutSearchVertices);
    });
    if (search) {
        chart.cutRounds = search->rounds.size();
        announce(options, "cut search",
                 work.name +
                     format("%zu cuts measured on a %zu-vertex remesh: %s + %zu extremity paths, conformal "
                            "shrink e^%.3g",
                            search->rounds.size(), chart.cutSearchVertices, search->cut.report.method.c_str(),
                            search->cut.report.extremityPaths, search->conformalShrink));
    }
    return search;
}

// Stage 3: the isotropic remesh of the part at remeshOptions' density. The remesh carries the
// map only if it follows the input: where `adaptive` and it cuts through or off a thin part
// (antlers, claws) by more than the detail transfer may move a sample (kMaxRemeshFarArea at
// half an edge), it is redone at twice the density, up to `dense` (remeshOptions and
// ChartReport::remeshDensified follow). With `stopAtCoarse`, a remesh at `coarseCount` that
// does so is returned as it is with `farFromInput` set (the part is handed over instead).
RemeshResult remeshChart(ChartWork& work, RemeshOptions& remeshOptions, bool adaptive, size_t dense, bool stopAtCoarse,
                         size_t coarseCount, bool& farFromInput)
{
    ChartReport& chart = work.chart;
    return chartStage(work, "remesh", [&] {
        RemeshResult result = remeshIsotropic(work.part, remeshOptions);
        while (adaptive) {
            const double limit = 0.5 * result.report.targetEdgeLength;                       // as the transfer's
            chart.remeshFarArea = std::max(areaFartherThan(result.mesh, work.part, limit),   // cut through
                                           areaFartherThan(work.part, result.mesh, limit));  // cut off
            if (chart.remeshFarArea <= kMaxRemeshFarArea || remeshOptions.targetVertexCount * 2 > dense) break;
            if (stopAtCoarse && remeshOptions.targetVertexCount == coarseCount) {
                farFromInput = true;
                break;
            }
            remeshOptions.targetVertexCount *= 2;
            result = remeshIsotropic(work.part, remeshOptions);
            ++chart.remeshDensified;
        }
        return result;
    });
}

// Records the chart's remesh in its report and announces it.
void announceRemesh(ChartWork& work, const RemeshResult& remeshed)
{
    ChartReport& chart = work.chart;
    chart.remesh = remeshed.report;
    announce(
        work.options, "remesh",
        work.name +
            format("%zu -> %zu vertices, %zu triangles, edge %.4g, min angle %.1f deg, %zu feature edges, "
                   "%.3g%% of it off the input by > edge/2%s%s",
                   chart.remesh.inputVertices, chart.remesh.outputVertices, chart.remesh.outputTriangles,
                   chart.remesh.targetEdgeLength, chart.remesh.minAngleDegrees, chart.remesh.featureEdges,
                   100.0 * chart.remeshFarArea,
                   chart.remeshDensified ? format(" (densified %zux)", size_t(1) << chart.remeshDensified).c_str() : "",
                   chart.remesh.droppedFeatureEdges
                       ? format(" (%zu creases dropped: they made %.1f deg slivers)", chart.remesh.droppedFeatureEdges,
                                chart.remesh.minAngleWithFeaturesDegrees)
                             .c_str()
                       : ""));
}

// Stage 4: cuts the remesh to a disk through its extremities (Gu et al. 2002), so the conformal
// start of OT does not shrink an uncut protrusion beyond what the power diagram separates: the
// cut `search` chose (cutByPlan) where there is one, else a search on the remesh itself.
// Records the cut in the chart's report (cutRounds adds up) and announces it.
ExtremityCutResult cutChart(ChartWork& work, const RemeshResult& remeshed,
                            const std::optional<ExtremityCutResult>& search, const ExtremityCutOptions& cutOptions)
{
    ChartReport& chart = work.chart;
    ExtremityCutResult cut = chartStage(work, "cut", [&] {
        return search ? cutByPlan(remeshed.mesh, search->plan, cutOptions)
                      : cutThroughExtremities(remeshed.mesh, cutOptions);
    });
    chart.cut = cut.cut.report;
    chart.cutConformalShrink = cut.conformalShrink;
    chart.cutRounds += cut.rounds.size();
    announce(work.options, "cut",
             work.name +
                 format("%s + %zu extremity paths: genus %ld, %zu boundary loops, cut length %.4g (%zu edges), "
                        "%zu boundary vertices, conformal shrink e^%.3g%s",
                        chart.cut.method.c_str(), chart.cut.extremityPaths, chart.cut.genus, chart.cut.boundaryLoops,
                        chart.cut.cutLength, chart.cut.cutEdges, chart.cut.diskBoundaryVertices, cut.conformalShrink,
                        search ? format(" (searched over %zu cuts of a %zu-vertex remesh)", search->rounds.size(),
                                        chart.cutSearchVertices)
                                     .c_str()
                               : ""));
    return cut;
}

// Stages 5-6: maps the chart's disk (already in bake.disk) to the square with
// BakeOptions::method: the conformal start (discrete Ricci flow, paper Eq. 1-2; the cut stage
// measured it, `cut` hands it on) refined by optimal transport (paper Alg. 1). Throws where the
// map flips a triangle (not bijective).
void mapChartToSquare(ChartWork& work, const ExtremityCutResult& cut)
{
    const BakeOptions& options = work.options;
    ChartBake& bake = work.bake;
    ParameterizeOptions mapOptions;
    mapOptions.method = options.method;
    mapOptions.progress = options.progress;
    mapOptions.detailDensity = options.detailDensity;
    if (cut.conformalStart) mapOptions.conformalStart = &*cut.conformalStart;  // measured by the cut stage
    mapOptions.conformalStartFailed = cut.conformalStartFailed;
    bake.map = chartStage(work, "parameterize", [&] { return parameterizeToSquare(bake.disk, mapOptions); });
    if (bake.map.report.flippedTriangles != 0)
        throw Error(options.sourceName + ": " + work.name + "parameterize: the " + work.report.method + " map flips " +
                    std::to_string(bake.map.report.flippedTriangles) + " triangles (not bijective)");
}

// Stage 5b: records and announces the map; where it squeezes the surface, the geometry image
// has almost no samples. Throws where a map squeezes so much of the chart that it is garbage
// (checkChartSampling); warns above 0.1% of the area.
void checkMapSampling(ChartWork& work)
{
    const BakeOptions& options = work.options;
    ChartReport& chart = work.chart;
    const ChartBake& bake = work.bake;
    const ParameterizeReport& p = chart.parameterization = bake.map.report;
    announce(options, "parameterize",
             work.name +
                 format("%s: ricci %d it (residual %.2g), ot %d it (residual %.2g), area distortion mean %.3f "
                        "max %.3f, angle distortion mean %.3f, %zu flipped",
                        work.report.method.c_str(), p.ricciIterations, p.ricciResidual, p.otIterations, p.otResidual,
                        p.areaDistortionMean, p.areaDistortionMax, p.angleDistortionMean, p.flippedTriangles));
    chart.undersampledAreaFraction = undersampledAreaFraction(bake.disk.mesh, bake.map.uv, kUndersampling);
    if (!work.lastResort)
        checkChartSampling(
            chart.undersampledAreaFraction,
            {.file = options.sourceName, .chart = work.index, .charts = work.count, .genus = chart.topology.genus});
    if (chart.undersampledAreaFraction > 1e-3)
        work.report.warnings.push_back(format("%s: %s%.2f%% of the surface gets less than 1/%.0f of its fair share of "
                                              "samples (max area distortion e^%.1f): expect holes or streaks there",
                                              options.sourceName.c_str(), work.name.c_str(),
                                              100.0 * chart.undersampledAreaFraction, kUndersampling,
                                              p.areaDistortionMax));
}

// Stage 6b: matches the border so that the two sides of every cut sample the same points at
// every level down to the coarsest watertight one (Gu et al. 2002, section 4). Unmatched
// (BakeOptions::matchSeams off, or no match found: a warning) the map keeps its own border.
void matchChartBorder(ChartWork& work)
{
    const BakeOptions& options = work.options;
    ChartReport& chart = work.chart;
    ChartBake& bake = work.bake;
    MatchedBorder matched = chartStage(work, "match seams", [&] {
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
                 work.name +
                     format("%zu cut paths matched%s, watertight to level %u (%ux%u), border lengths changed "
                            "%.1f%% (sides' mismatch %.1f%%), area distortion mean %.3f max %.3f",
                            matched.report.cutPaths, matched.report.movedCorners ? " (corners moved)" : "",
                            matched.report.level, (chart.resolution >> matched.report.level) + 1,
                            (chart.resolution >> matched.report.level) + 1, 100.0 * matched.report.lengthChange,
                            100.0 * matched.report.mismatch, d.areaMean, d.areaMax));
    } else if (options.matchSeams) {
        work.report.warnings.push_back(format("%s: %sthe seam could not be matched (%s): it may crack",
                                              options.sourceName.c_str(), work.name.c_str(),
                                              matched.report.problem.c_str()));
    }
    if (!matched.report.matched) announce(options, "match seams", work.name + "not matched: " + matched.report.problem);
}

// The image check (sampling_check.h): how much of the part the geometry image `full` misses,
// or adds (spikes), measured on a level of at most 257^2 samples (a 5% distance needs no finer
// mesh). The full image, not the stored level: a stored level too coarse for the shape is the
// resolution's doing, not the map's. Records ChartReport::farFromImageArea; throws above
// checkChartImage's limit.
void checkImageCoversPart(ChartWork& work, const GeometryImage& full)
{
    ChartReport& chart = work.chart;
    const uint32_t step = std::max<uint32_t>(1, (full.size - 1) / 256);
    GeometryImage coarse;
    coarse.size = (full.size - 1) / step + 1;
    coarse.texels.reserve(size_t(coarse.size) * coarse.size);
    for (uint32_t y = 0; y < coarse.size; ++y)
        for (uint32_t x = 0; x < coarse.size; ++x) coarse.texels.push_back(full.at(x * step, y * step));
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& p : work.part.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const TriangleMesh stored = geometryImageMesh(coarse);
    chart.farFromImageArea = std::max(areaFartherThan(work.part, stored, kFarFromImageDistance * side),
                                      areaFartherThan(stored, work.part, kFarFromImageDistance * side));
    if (work.lastResort) {
        if (chart.farFromImageArea > 1e-3)
            work.report.warnings.push_back(format("%s: %s%.2f%% of the surface is farther than %.0f%% of its size from "
                                                  "the geometry image: expect holes or spikes there",
                                                  work.options.sourceName.c_str(), work.name.c_str(),
                                                  100.0 * chart.farFromImageArea, 100.0 * kFarFromImageDistance));
        return;
    }
    checkChartImage(
        chart.farFromImageArea,
        {.file = work.options.sourceName, .chart = work.index, .charts = work.count, .genus = chart.topology.genus});
}

// Stage 7: rasterizes the chart's positions and normals at its resolution (samples moved onto
// the part where BakeOptions::transferDetail), appends them to `images`, checks the image
// (checkImageCoversPart), then welds the mates of a matched seam (equal up to rounding) bitwise.
void rasterizeChart(ChartWork& work, std::vector<RasterizedGeometryImage>& images)
{
    const BakeOptions& options = work.options;
    ChartReport& chart = work.chart;
    const ChartBake& bake = work.bake;
    images.push_back(chartStage(work, "rasterize", [&] {
        RasterizedGeometryImage image = rasterizeGeometryImage(bake.disk, bake.map.uv, chart.resolution);
        if (options.transferDetail)
            chart.detail = transferDetail(work.part, image.positions, image.normals,
                                          {.maxDistance = 0.5 * chart.remesh.targetEdgeLength});
        return image;
    }));
    checkImageCoversPart(work, images.back().positions);
    if (bake.seams.matched) {
        const std::vector<uint32_t> table = seamWeldTable(bake.seams, chart.resolution);
        chart.seamGapBeforeWeld = measureSeamGap(images.back().positions, table).maxDistance;
        weldSeams(images.back().positions, table);
        weldSeams(images.back().normals, table);
    }
    announce(options, "rasterize",
             work.name +
                 format("%ux%u samples%s", images.back().positions.size, images.back().positions.size,
                        bake.seams.matched ? format(", seam gap %.2g welded", chart.seamGapBeforeWeld).c_str() : "") +
                 (options.transferDetail
                      ? format(", detail from the input: %zu samples moved (mean %.2g, max %.2g), %zu kept",
                               chart.detail.projected, chart.detail.meanDistance, chart.detail.maxDistance,
                               chart.detail.kept)
                      : std::string()));
}

// Stages 5b-7 on the chart's map: the sampling check, the matched border, the image and its
// check. Throws where the chart is refused.
void finishChart(ChartWork& work, std::vector<RasterizedGeometryImage>& images)
{
    // Set only where the seams match: a retried chart must not keep the failed attempt's.
    work.chart.seamAreaDistortionMax = work.chart.seamAreaDistortionMean = work.chart.seamGapBeforeWeld = 0.0;
    checkMapSampling(work);
    matchChartBorder(work);
    rasterizeChart(work, images);
}

// The last resort for a part every regular attempt refused (a remesh that changes the
// topology, a flow or transport that fails, a map that flips or squeezes, an image far from the
// part): a map that cannot fail on a disk. The part is remeshed coarsely, or taken as it is
// where that remesh fails, cut to a disk by a tree-cotree cut, or face peeling where that
// fails (no extremity search, no flow),
// and mapped by Tutte's uniform fixed-border map (Tutte 1963: convex border, no flips), with no
// optimal transport. The sampling and image checks warn with their figures instead of refusing;
// one warning says why the part came here and what the map costs. Throws where even this fails.
void bakeChartLastResort(ChartWork& work, size_t coarseCount, const std::string& why,
                         std::vector<RasterizedGeometryImage>& images)
{
    const BakeOptions& options = work.options;
    ChartReport& chart = work.chart;
    ChartBake& bake = work.bake;
    work.lastResort = true;
    RemeshResult remeshed;
    bool asItIs = false;
    try {
        RemeshOptions coarse;
        coarse.targetVertexCount = coarseCount;
        coarse.featureAngleDegrees = options.featureAngleDegrees;
        remeshed = remeshIsotropic(work.part, coarse);
    } catch (const Error&) {
        asItIs = true;
    }
    if (asItIs) {
        remeshed = RemeshResult{};
        remeshed.mesh = work.part;
        double length = 0.0;
        size_t edges = 0;
        for (const auto& t : work.part.triangles)
            for (int k = 0; k < 3; ++k, ++edges)
                length += glm::length(work.part.positions[t[k]] - work.part.positions[t[(k + 1) % 3]]);
        remeshed.report.inputVertices = remeshed.report.outputVertices = work.part.positions.size();
        remeshed.report.inputTriangles = remeshed.report.outputTriangles = work.part.triangles.size();
        remeshed.report.targetEdgeLength = remeshed.report.meanEdgeLength = edges ? length / double(edges) : 0.0;
    }
    chart.remeshForThinParts = false;
    announceRemesh(work, remeshed);
    CutResult cut = chartStage(work, "cut", [&] {
        try {
            return cutToDisk(remeshed.mesh, {.cornersAtBoundaryTurns = true});
        } catch (const Error&) {  // face peeling reaches a disk where the tree-cotree cut does not
            return cutToDisk(remeshed.mesh, {.graph = CutGraph::FacePeeling, .cornersAtBoundaryTurns = true});
        }
    });
    chart.cut = cut.report;
    chart.cutConformalShrink = 0.0;
    bake.disk = std::move(cut.disk);
    ParameterizeOptions mapOptions;
    mapOptions.method = ParameterizationMethod::Tutte;
    bake.map = chartStage(work, "parameterize", [&] { return parameterizeToSquare(bake.disk, mapOptions); });
    finishChart(work, images);
    const ParameterizeReport& p = chart.parameterization;
    work.report.warnings.push_back(
        format("%s: %sbaked with the last-resort map (%s; cut: %s; Tutte's fixed-border map without "
               "optimal transport: area distortion mean %.3f max %.3f, %zu flipped, %.2f%% undersampled, %.2f%% far "
               "from the image) because: %s",
               options.sourceName.c_str(), work.name.c_str(),
               asItIs ? "the part as it is: its remesh failed" : "a coarse remesh", chart.cut.method.c_str(),
               p.areaDistortionMean, p.areaDistortionMax, p.flippedTriangles, 100.0 * chart.undersampledAreaFraction,
               100.0 * chart.farFromImageArea, why.c_str()));
}

// Appends the report and bake entries of components.parts[c] as one chart (its topology, area
// share and resolution) and returns the work that fills them.
ChartWork beginChart(const Components& components, size_t c, uint32_t storedLevel, const BakeOptions& options,
                     BakeResult& result)
{
    const size_t count = components.parts.size();
    ChartReport& chart = result.report.charts.emplace_back();
    chart.topology = analyzeTopology(components.parts[c]);
    chart.areaFraction = components.shareOf(c);
    chart.resolution = chartResolutionFor(options.resolution, storedLevel, chart.areaFraction);
    ChartBake& bake = result.charts.emplace_back();
    return ChartWork{.options = options,
                     .report = result.report,
                     .part = components.parts[c],
                     .index = c,
                     .count = count,
                     .name = count == 1 ? "" : format("chart %zu/%zu: ", c + 1, count),
                     .chart = chart,
                     .bake = bake};
}

// The remesh density of a chart: its share of the samples (BakeOptions::remeshVertexCount, else
// the resolution's).
size_t coarseRemeshCount(const BakeOptions& options, const ChartReport& chart)
{
    return options.remeshVertexCount
        ? std::max<size_t>(size_t(double(options.remeshVertexCount) * chart.areaFraction), 200)
        : remeshVertexCountFor(chart.resolution);
}

// bakeComponentAsOneChart's regular attempts (see there); throws where they all fail.
bool bakeComponentRegularly(const Components& components, size_t c, uint32_t storedLevel, const BakeOptions& options,
                            BakeResult& result, BakedCharts& baked, std::vector<HandOver>* handOvers)
{
    BakeReport& report = result.report;
    ChartWork work = beginChart(components, c, storedLevel, options, result);
    ChartReport& chart = work.chart;
    ChartBake& bake = work.bake;

    // The remesh density: the chart's share of the samples; the dense one for thin parts.
    RemeshOptions remeshOptions;
    remeshOptions.targetVertexCount = coarseRemeshCount(options, chart);
    remeshOptions.featureAngleDegrees = options.featureAngleDegrees;
    const bool adaptive = options.transferDetail && !options.remeshVertexCount;
    const size_t dense = std::max(remeshOptions.targetVertexCount, remeshVertexCountForThinParts(chart.resolution));
    const size_t coarseCount = remeshOptions.targetVertexCount;
    const bool splitThin = options.splitPieces <= 1 && options.splitThinParts > 1;
    const bool handOver = handOvers && adaptive && splitThin && components.piecesFor(c, options.splitThinParts) >= 2;
    // Where the part would need the dense remesh for thin parts, it is split instead: its
    // entries are removed again and it goes to *handOvers.
    auto handOverToSplit = [&](std::string reason, std::optional<RemeshResult> coarse, bool oneChartFails = false) {
        if (options.progress)
            options.progress(reason + ": the part has thin parts, it is split instead of remeshed densely");
        handOvers->push_back({c, std::move(reason), chart.topology.genus, std::move(coarse), oneChartFails});
        report.charts.pop_back();
        result.charts.pop_back();
        return false;
    };
    // So many handles that one chart maps them badly whatever the cut: split at once, however
    // small the part (the split gives it at least genus / 2 pieces), before a cut search that
    // costs minutes on such a part and whose map fails its checks anyway.
    if (handOvers && adaptive && splitThin && chart.topology.genus > kMaxOneChartGenus)
        return handOverToSplit(
            format("genus %ld, above the %ld one chart is tried for", chart.topology.genus, kMaxOneChartGenus),
            std::nullopt, true);

    // The cut search, once per chart on a coarse remesh of the part when the bake's remesh is
    // much denser (cutByPlan says why); the chosen cut is then made on each remesh. If the
    // coarse remesh fails or changes the topology, the search runs on the remesh itself.
    ExtremityCutOptions cutOptions;
    cutOptions.progress = options.progress;
    cutOptions.cut.cornersAtBoundaryTurns = true;  // the part's boundary is the input's own
    std::optional<ExtremityCutResult> search;
    if (options.cutSearchVertices > 0 && remeshOptions.targetVertexCount > 2 * options.cutSearchVertices) {
        search = searchCutOnCoarseRemesh(work, remeshOptions, cutOptions);
        // A cut's shrink grows with the remesh density, so a search past the coarse limit means
        // the coarse remesh would be redone dense below: remesh dense at once. A flow that failed
        // only on the coarse remesh decides nothing (the remesh decides).
        if (adaptive && search && !std::isnan(search->conformalShrink) &&
            search->conformalShrink > kMaxCoarseRemeshShrink && remeshOptions.targetVertexCount < dense) {
            if (handOver)
                return handOverToSplit(format("conformal shrink e^%.3g > e^%.3g on the cut search's %zu-vertex remesh",
                                              search->conformalShrink, kMaxCoarseRemeshShrink, chart.cutSearchVertices),
                                       std::nullopt);
            if (options.progress)
                options.progress(format("conformal shrink e^%.3g > e^%.3g on the cut search's remesh: remeshing at %zu "
                                        "vertices",
                                        search->conformalShrink, kMaxCoarseRemeshShrink, dense));
            remeshOptions.targetVertexCount = dense;
            chart.remeshForThinParts = true;
        }
    }

    // The dense remesh is tried where it should pay; if its map fails, the coarse one once.
    RemeshResult remeshed;
    ExtremityCutResult cut;
    for (bool denseAllowed = true;; denseAllowed = false) {
        // Stages 3-4: remesh and cut, again at the dense count where the cut shrinks strongly.
        for (;;) {
            bool farFromInput = false;  // the remesh cuts through thin parts: handed over
            remeshed = remeshChart(work, remeshOptions, adaptive, dense, handOver, coarseCount, farFromInput);
            if (farFromInput) {
                std::string reason = format("%.3g%% of the %zu-vertex remesh off the input by more than half an edge",
                                            100.0 * chart.remeshFarArea, remeshed.mesh.positions.size());
                return handOverToSplit(std::move(reason), std::move(remeshed));
            }
            announceRemesh(work, remeshed);
            cut = cutChart(work, remeshed, search, cutOptions);
            // Protrusions the conformal start shrinks strongly (legs, limbs) get few samples per
            // remesh triangle from OT, so the coarse remesh's map undersamples them: such charts
            // are remeshed at the dense count.
            if (!adaptive || !denseAllowed || cut.conformalShrink <= kMaxCoarseRemeshShrink ||
                remeshOptions.targetVertexCount >= dense)
                break;
            if (handOver) {  // a flow that failed here (NaN) sent the chart to the dense remesh too
                std::string reason = std::isnan(cut.conformalShrink)
                    ? format("no conformal start on the %zu-vertex remesh (the flow failed)",
                             remeshed.mesh.positions.size())
                    : format("conformal shrink e^%.3g > e^%.3g on the %zu-vertex remesh", cut.conformalShrink,
                             kMaxCoarseRemeshShrink, remeshed.mesh.positions.size());
                return handOverToSplit(std::move(reason), std::move(remeshed));
            }
            if (options.progress)
                options.progress(format("conformal shrink e^%.3g > e^%.3g: remeshing at %zu vertices",
                                        cut.conformalShrink, kMaxCoarseRemeshShrink, dense));
            remeshOptions.targetVertexCount = dense;
            chart.remeshForThinParts = true;
        }
        bake.disk = std::move(cut.cut.disk);

        // Stages 5-7: map to the square, check, match the border, sample.
        const size_t warningsBefore = report.warnings.size(), imagesBefore = baked.images.size();
        try {
            mapChartToSquare(work, cut);
            finishChart(work, baked.images);
            break;
        } catch (const Error& e) {
            // The dense remesh is for thin limbs; on a part whose shrink comes from many handles
            // it can make the map worse, or its image can leave out what the coarse one keeps.
            // Then the coarse remesh is baked instead, once, and what the failed attempt added to
            // the report and images is dropped.
            const bool retryCoarse = chart.remeshForThinParts && denseAllowed;
            // A one-chart map that fails its checks (flips, squeeze, far surface) is split into
            // pieces instead of refusing the mesh: each piece has fewer handles and less to
            // squeeze. Where the split fails too, the part comes back here without hand-over and
            // is refused with this error.
            if (!retryCoarse && handOvers && adaptive && splitThin) {
                report.warnings.resize(warningsBefore);
                baked.images.erase(baked.images.begin() + long(imagesBefore), baked.images.end());
                report.warnings.push_back(format("%s: %sone chart failed its checks, split into pieces instead: %s",
                                                 options.sourceName.c_str(), work.name.c_str(), e.what()));
                return handOverToSplit(std::string("one chart failed its checks: ") + e.what(), std::nullopt, true);
            }
            if (!retryCoarse) throw;
            report.warnings.resize(warningsBefore);
            baked.images.erase(baked.images.begin() + long(imagesBefore), baked.images.end());
            if (options.progress)
                options.progress(std::string("the dense remesh's chart failed (") + e.what() +
                                 "): baking the coarse remesh");
            remeshOptions.targetVertexCount = coarseCount;
            chart.remeshForThinParts = false;
            chart.remeshDensified = 0;
            chart.denseRemeshFailed = true;
            chart.denseRemeshProblem = e.what();
        }
    }
    return true;
}

}  // namespace

bool bakeComponentAsOneChart(const Components& components, size_t c, uint32_t storedLevel, const BakeOptions& options,
                             BakeResult& result, BakedCharts& baked, std::vector<HandOver>* handOvers)
{
    const size_t warnings = result.report.warnings.size(), charts = result.report.charts.size(),
                 bakes = result.charts.size(), images = baked.images.size();
    try {
        return bakeComponentRegularly(components, c, storedLevel, options, result, baked, handOvers);
    } catch (const Error& e) {
        // What the failed attempts added goes; their stage times stay (the time was spent).
        const std::string why = e.what();
        result.report.warnings.resize(warnings);
        while (result.report.charts.size() > charts) result.report.charts.pop_back();
        while (result.charts.size() > bakes) result.charts.pop_back();
        baked.images.erase(baked.images.begin() + long(images), baked.images.end());
        bakeComponentWithLastResort(components, c, storedLevel, options, result, baked, why);
        return true;
    }
}

void bakeComponentWithLastResort(const Components& components, size_t c, uint32_t storedLevel,
                                 const BakeOptions& options, BakeResult& result, BakedCharts& baked,
                                 const std::string& why)
{
    if (options.progress) options.progress("every regular map failed (" + why + "): the last-resort map");
    try {
        ChartWork work = beginChart(components, c, storedLevel, options, result);
        bakeChartLastResort(work, coarseRemeshCount(options, work.chart), why, baked.images);
    } catch (const Error& last) {
        throw Error(why + "; the last-resort map failed too: " + last.what());
    }
}

}  // namespace ngi::detail
