// ngi offline: the last stage of the bake (stage 8): the charts ordered largest first, one
// normalization for all of them (one frame, so one network restores every chart), each chart's
// nested mip level at the stored resolution, and the asset with its bake report. The byte
// budget (--target-bytes) is fitted to this asset afterwards (rate_control.h).
#include "bake_stages.h"

#include "ngi/bake/bake_report.h"
#include "ngi/mip_pyramid.h"

#include <glm/common.hpp>

#include <limits>
#include <numeric>

namespace ngi {

void normalizationFor(const GeometryImage& image, const glm::dvec3& centre, glm::vec3& offset, glm::vec3& scale)
{
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::vec3& p : image.texels) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    const glm::dvec3 extent = hi - lo;
    const double side = std::max({extent.x, extent.y, extent.z});
    if (!(side > 0.0) || !std::isfinite(side))
        throw Error("the geometry image has a zero-size or non-finite bounding box");
    // The corner rounded down to a float and the side then rounded up to one that still reaches
    // the far corner: offset + scale * [0,1]^3 covers the image exactly in the input's
    // coordinates, however far from the origin (the rounding only widens the box).
    double reach = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double corner = centre[i] + (0.5 * (lo[i] + hi[i]) - 0.5 * side);
        float rounded = float(corner);
        if (double(rounded) > corner) rounded = std::nextafter(rounded, -std::numeric_limits<float>::infinity());
        offset[i] = rounded;
        reach = std::max(reach, (centre[i] - double(rounded)) + hi[i]);
    }
    float reachRounded = float(reach);
    if (double(reachRounded) < reach)
        reachRounded = std::nextafter(reachRounded, std::numeric_limits<float>::infinity());
    scale = glm::vec3(reachRounded);
}

namespace detail {
namespace {

// The stored positions resolve 1/65535 of the asset's scale (16 bits per coordinate); a consumer
// that computes offset + scale * normalized in 32-bit floats (a shader, a float vertex buffer)
// resolves half a float step at the surface's distance from the origin. Warns where that is the
// coarser of the two (the asset itself holds the placement exactly: normalizationFor).
void warnWhereFloatsRoundTheSurface(const Asset& asset, const std::string& name, BakeReport& report)
{
    double farthest = 0.0;
    for (int i = 0; i < 3; ++i)
        farthest = std::max(
            {farthest, std::abs(double(asset.offset[i])), std::abs(double(asset.offset[i]) + double(asset.scale[i]))});
    const double floatStep = 0.5 *
        (double(std::nextafter(float(farthest), std::numeric_limits<float>::infinity())) - double(float(farthest)));
    const double storedStep = double(asset.scale.x) / 65535.0;
    if (floatStep > storedStep)
        report.warnings.push_back(
            format("%s: the surface lies %.6g from the origin, %.3g times its size: world positions "
                   "computed in 32-bit floats round to %.3g (%.2g%% of its size), coarser than the "
                   "asset's %.3g steps; the asset stores the shape relative to its offset, exactly",
                   name.c_str(), farthest, farthest / double(asset.scale.x), floatStep,
                   100.0 * floatStep / double(asset.scale.x), storedStep));
}

}  // namespace

void orderChartsByResolution(BakeResult& result, BakedCharts& baked)
{
    BakeReport& report = result.report;
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
        sorted.push_back(std::move(baked.images[order[i]]));
    }
    report.charts = std::move(reports);
    result.charts = std::move(bakes);
    baked.images = std::move(sorted);
    for (CrossSeamSegment& g : baked.crossSeams) {
        g.chartA = at[g.chartA], g.chartB = at[g.chartB];
        if (g.chartA > g.chartB) std::swap(g.chartA, g.chartB), std::swap(g.a, g.b);
    }
    result.crossSeams = std::move(baked.crossSeams);
}

void storeAsset(uint32_t storedLevel, const BakeOptions& options, StopwatchClock::time_point bakeStart,
                BakeResult& result, BakedCharts& baked)
{
    BakeReport& report = result.report;
    std::vector<RasterizedGeometryImage>& images = baked.images;
    runStage("store", options, report, [&] {
        Asset& asset = result.asset;
        asset.sourceName = options.sourceName;
        asset.sourceHash = options.sourceHash;
        GeometryImage all;  // the bounding box of every chart
        for (const RasterizedGeometryImage& image : images)
            all.texels.insert(all.texels.end(), image.positions.texels.begin(), image.positions.texels.end());
        normalizationFor(all, baked.centre, asset.offset, asset.scale);
        warnWhereFloatsRoundTheSurface(asset, options.sourceName, report);
        asset.parameterization = report.method;
        // The images are in the centred frame: the asset's corner there, in double.
        const glm::dvec3 corner = glm::dvec3(asset.offset) - baked.centre, side = glm::dvec3(asset.scale);
        for (size_t c = 0; c < images.size(); ++c) {
            ChartBake& bake = result.charts[c];
            bake.fullPositions = std::move(images[c].positions);
            for (glm::vec3& t : bake.fullPositions.texels)
                t = glm::clamp(glm::vec3((glm::dvec3(t) - corner) / side), glm::vec3(0.0f), glm::vec3(1.0f));
            bake.fullNormals = std::move(images[c].normals);
            AssetChart& chart = asset.charts.emplace_back();
            chart.fullResolution = report.charts[c].resolution;
            chart.storedLevel = storedLevel;
            storeGeometryImage(chart, downsampleNested(bake.fullPositions, storedLevel),
                               downsampleNested(bake.fullNormals, storedLevel));
            chart.seams = bake.seams;
            if (c < baked.baseColors.size() && !baked.baseColors[c].rgba.empty()) {
                chart.baseColorLevel = baked.baseColors[c].level;
                chart.baseColor = std::move(baked.baseColors[c].rgba);
            }
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
             format("level %u kept: %ux%u samples (CR %.0f)%s", largest.storedLevel, largest.storedSize(),
                    largest.storedSize(),
                    double(options.resolution) * options.resolution /
                        (double(options.storeResolution) * options.storeResolution),
                    result.asset.charts.size() > 1
                        ? format(" in the largest of %zu charts", result.asset.charts.size()).c_str()
                        : ""));
}

}  // namespace detail
}  // namespace ngi
