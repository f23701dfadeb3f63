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

void normalizationFor(const GeometryImage& image, glm::vec3& offset, glm::vec3& scale) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::vec3& p : image.texels) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    const glm::dvec3 extent = hi - lo;
    const double side = std::max({extent.x, extent.y, extent.z});
    if (!(side > 0.0) || !std::isfinite(side)) throw Error("the geometry image has a zero-size or non-finite bounding box");
    offset = glm::vec3((lo + hi) * 0.5 - glm::dvec3(side * 0.5));
    scale = glm::vec3(float(side));
}

namespace detail {

void orderChartsByResolution(BakeResult& result, BakedCharts& baked) {
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

void storeAsset(uint32_t storedLevel, const BakeOptions& options, StopwatchClock::time_point bakeStart, BakeResult& result,
                BakedCharts& baked) {
    BakeReport& report = result.report;
    std::vector<RasterizedGeometryImage>& images = baked.images;
    runStage("store", options, report, [&] {
        Asset& asset = result.asset;
        asset.sourceName = options.sourceName;
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
             format("level %u kept: %ux%u samples (CR %.0f)%s", largest.storedLevel, largest.storedSize(), largest.storedSize(),
                    double(options.resolution) * options.resolution /
                        (double(options.storeResolution) * options.storeResolution),
                    result.asset.charts.size() > 1 ? format(" in the largest of %zu charts", result.asset.charts.size()).c_str() : ""));
}

} // namespace detail
} // namespace ngi
