// ngi offline: a component split into several matched charts (docs/splitting.md, "Splitting a surface
// into several charts"): its remesh cut into geodesic Voronoi pieces, each cut to a disk and
// mapped to its own square (paper section 3.1), the pieces' shared borders matched together
// (watertight across charts) and welded. Done for every component (BakeOptions::splitPieces),
// or for those whose one-chart bake hands them over for thin parts or high genus
// (BakeOptions::splitThinParts).
#include "bake_stages.h"

#include "ngi/mesh/chart_split.h"
#include "ngi/mip_pyramid.h"
#include "ngi/param/distortion.h"
#include "ngi/param/extremity_cut.h"
#include "ngi/param/matched_group.h"

namespace ngi {
namespace detail {
namespace {

// The charts of one split component, in piece order.
struct SplitCharts {
    std::vector<ChartReport> reports;
    std::vector<ChartBake> bakes;
    std::vector<RasterizedGeometryImage> images;
    std::vector<CrossSeamSegment> crossSeams;  // piece indices
    bool matched = false;                      // false: the split is abandoned (problem says why)
    std::string problem;
};

// One split component: remeshed once (or `premade`: its remesh at the density this function
// would ask for, already made by the one-chart bake that handed it over), its remesh cut into
// `pieces` geodesic Voronoi pieces that share its vertices, each cut to a disk and mapped to its
// own square, the borders matched together, each rasterized with its samples moved onto the
// component (one surface point projects the same way from both sides of a curve). `share` is
// the component's share of the surface; `group` numbers the split in the reports. Unmatched
// borders return matched = false (a cracked split is never shipped); throws where a piece's map
// flips.
SplitCharts bakeSplitComponent(const TriangleMesh& component, double share, uint32_t pieces, uint32_t storedLevel,
                               const BakeOptions& options, BakeReport& report, int group,
                               std::optional<RemeshResult> premade)
{
    const std::string& name = options.sourceName;
    SplitCharts out;
    RemeshOptions remeshOptions;
    remeshOptions.targetVertexCount = remeshVertexCountFor(chartResolutionFor(options.resolution, storedLevel, share));
    remeshOptions.featureAngleDegrees = options.featureAngleDegrees;
    const RemeshResult remeshed = premade
        ? std::move(*premade)
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
        bake.map =
            runStage("parameterize", options, report, [&] { return parameterizeToSquare(bake.disk, mapOptions); });
        if (bake.map.report.flippedTriangles != 0)
            throw Error(name + ": " + pieceName + "parameterize: the map flips " +
                        std::to_string(bake.map.report.flippedTriangles) + " triangles (not bijective)");
        chart.parameterization = bake.map.report;
        chart.undersampledAreaFraction = undersampledAreaFraction(bake.disk.mesh, bake.map.uv, kUndersampling);
        announce(
            options, "parameterize",
            pieceName +
                format(
                    "genus %ld, %zu boundary loops, ot %d it, area distortion mean %.3f max %.3f, %.2f%% undersampled",
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
    MatchedGroup matched = runStage("match seams", options, report,
                                    [&] { return matchBorders(group_, levelLimit, 0.05, 2, storedLevel); });
    if (matched.matched && matched.level < storedLevel)
        report.warnings.push_back(
            format("%s: split component %d: its shared borders match down to level %u only, finer than "
                   "the stored level %u: its charts draw no coarser level",
                   name.c_str(), group, matched.level, storedLevel));
    if (!matched.matched) {  // a cracked split is never shipped: the caller bakes the component as one chart
        out.problem = "their shared borders could not be matched: " + matched.problem;
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
    for (RasterizedGeometryImage& image : out.images)
        positions.push_back(&image.positions), normals.push_back(&image.normals);
    const double gap = weldGroupSeams(positions, seams, resolutions, out.crossSeams, 0);
    weldGroupSeams(normals, seams, resolutions, out.crossSeams, 0);
    for (ChartReport& chart : out.reports) chart.crossSeamGapBeforeWeld = gap;
    announce(options, "rasterize",
             format("split component %d: %zu images of %u to %u samples per side, shared borders' gap %.2g welded",
                    group, meshes.size(), smallest + 1, *std::max_element(resolutions.begin(), resolutions.end()) + 1,
                    gap));
    return out;
}

// Appends a matched split's charts as the next group (its cross-chart seams renumbered to the
// bake's chart indices); `thinParts` is why it was split (ChartReport::splitForThinParts).
void addGroup(SplitCharts& split, const std::string& thinParts, BakeResult& result, BakedCharts& baked)
{
    ++baked.splitGroups;
    const uint32_t base = uint32_t(result.report.charts.size());
    for (CrossSeamSegment g : split.crossSeams) {
        g.chartA += base, g.chartB += base;
        baked.crossSeams.push_back(g);
    }
    for (size_t i = 0; i < split.reports.size(); ++i) {
        split.reports[i].splitForThinParts = thinParts;
        result.report.charts.push_back(std::move(split.reports[i]));
        result.charts.push_back(std::move(split.bakes[i]));
        baked.images.push_back(std::move(split.images[i]));
    }
}

// The warning of a split whose borders could not be matched (the component becomes one chart).
void warnAbandoned(const SplitCharts& split, int group, const BakeOptions& options, BakeReport& report)
{
    report.warnings.push_back(format("%s: the split of component %d was abandoned, it is baked as one chart: %s",
                                     options.sourceName.c_str(), group, split.problem.c_str()));
}

}  // namespace

void splitEveryComponent(Components& components, uint32_t storedLevel, const BakeOptions& options, BakeResult& result,
                         BakedCharts& baked)
{
    BakeReport& report = result.report;
    std::vector<TriangleMesh> rest;
    std::vector<double> restAreas;
    for (size_t c = 0; c < components.parts.size(); ++c) {
        const uint32_t k = components.piecesFor(c, options.splitPieces);
        SplitCharts split;
        if (k >= 2) {
            split = bakeSplitComponent(components.parts[c], components.shareOf(c), k, storedLevel, options, report,
                                       baked.splitGroups, std::nullopt);
            if (!split.matched) warnAbandoned(split, baked.splitGroups, options, report);
        }
        if (k < 2 || !split.matched) {
            rest.push_back(std::move(components.parts[c]));
            restAreas.push_back(components.areas[c]);
            continue;
        }
        addGroup(split, "", result, baked);
    }
    components.parts = std::move(rest);
    components.areas = std::move(restAreas);
    const int group = baked.splitGroups;
    if (group > 0)
        report.warnings.push_back(format("%s: split of %d component%s into %zu matched Voronoi pieces "
                                         "(--split-pieces; format 7: readers before it refuse the asset); on compact "
                                         "shapes one chart per component is closer to the input at the same bytes",
                                         options.sourceName.c_str(), group, group == 1 ? "" : "s",
                                         report.charts.size()));
}

void splitHandedOver(std::vector<HandOver>& handedOver, const Components& components, uint32_t storedLevel,
                     const BakeOptions& options, BakeResult& result, BakedCharts& baked)
{
    for (HandOver& h : handedOver) {
        // A part of genus g gets at least g/2 pieces, so each piece keeps a genus near 2: a piece
        // with many handles maps as badly as the whole. Capped so that the asset holds at most
        // kMaxCharts charts.
        const size_t after = handedOver.size() - size_t(&h - handedOver.data()) - 1;  // one chart each at least
        const size_t used = result.report.charts.size() + after;
        const size_t room = used < kMaxCharts ? kMaxCharts - used : 0;
        const uint32_t k = uint32_t(std::clamp<size_t>(
            std::max<size_t>(components.piecesFor(h.part, options.splitThinParts), size_t(h.genus + 1) / 2), 2,
            std::max<size_t>(2, room)));
        announce(options, "cut search",
                 format("component %zu of %zu has thin parts (%s): split into %u matched charts", h.part + 1,
                        components.parts.size(), h.reason.c_str(), k));
        // A split whose pieces fail (a piece's remesh, flow or map) is abandoned as an unmatched one
        // is: the part goes back to one chart, whose last resort cannot fail on a disk.
        const size_t warnings = result.report.warnings.size();
        SplitCharts split;
        try {
            split = bakeSplitComponent(components.parts[h.part], components.shareOf(h.part), k, storedLevel, options,
                                       result.report, baked.splitGroups, std::move(h.remesh));
        } catch (const Error& e) {
            result.report.warnings.resize(warnings);
            split = SplitCharts{};
            split.matched = false;
            split.problem = std::string("a piece failed: ") + e.what();
        }
        if (split.matched) {
            addGroup(split, h.reason, result, baked);
        } else {
            warnAbandoned(split, baked.splitGroups, options, result.report);
            // A part whose one chart fails (its checks, or too many handles) would fail again: it
            // takes the last resort at once.
            if (h.oneChartFails) {
                bakeComponentWithLastResort(components, h.part, storedLevel, options, result, baked,
                                            h.reason + "; its split into " + std::to_string(k) +
                                                " pieces was abandoned: " + split.problem);
                continue;
            }
            // Where the one chart is refused too, the error says why the split did not save it.
            try {
                bakeComponentAsOneChart(components, h.part, storedLevel, options, result, baked, nullptr);
            } catch (const Error& e) {
                throw Error(std::string(e.what()) + "; its split into " + std::to_string(k) +
                            " pieces was abandoned too: " + split.problem);
            }
        }
    }
}

}  // namespace detail

bool anyComponentSplitForThinParts(const BakeReport& report)
{
    for (const ChartReport& c : report.charts)
        if (!c.splitForThinParts.empty()) return true;
    return false;
}

}  // namespace ngi
