// ngi offline: the appearance stage of the bake (after stage 7, before the store): each
// chart's base colour over its own square. A geometry image's square is its own texture atlas
// (Gu, Gortler and Hoppe 2002, "Geometry images", section 6; Sander et al. 2003 for several
// charts): texel (x, y) of a chart's colour image is the colour of the input surface where
// the chart's sample ((x, y) << level) lies, found by the detail transfer's closest-point
// search, so no texture coordinates are stored and the colour does not move as the geometry
// coarsens (appearance-preserving simplification, Cohen, Olano and Manocha 1998).
#include "bake_stages.h"

#include "ngi/mesh/surface_color.h"
#include "ngi/mip_pyramid.h"
#include "ngi/param/detail_transfer.h"

#include <glm/common.hpp>

#include <bit>
#include <cmath>

namespace ngi::detail {

constexpr double kMinColorSide = 256.0;

uint32_t colorLevelFor(uint32_t resolution, double areaShare, double samplesPerArea, double totalArea)
{
    const uint32_t levels = uint32_t(std::countr_zero(resolution)) + 1;  // down to 2 x 2
    if (!(samplesPerArea > 0.0)) return levels - 1;
    // Samples per side it needs; at least kMinColorSide where the colour varies at all: a colour
    // edge crosses the texel grid at any angle, so a coarse image draws it as a staircase.
    const double side = std::max(std::sqrt(samplesPerArea * areaShare * totalArea), kMinColorSide);
    uint32_t level = 0;
    while (level + 1 < levels && double(resolution >> (level + 1)) >= side) ++level;
    return level;
}

void bakeAppearance(const TriangleMesh& input, const BakeOptions& options, BakeResult& result, BakedCharts& baked)
{
    if (!options.appearance || options.appearance->empty()) return;
    BakeReport& report = result.report;
    runStage("appearance", options, report, [&] {
        // The input where the charts are: the bake works relative to the input's centre.
        TriangleMesh located = input;
        for (glm::dvec3& p : located.positions) p -= baked.centre;
        const SurfaceColor colour(located, *options.appearance);
        report.colorSamplesPerArea = colour.samplesPerArea();
        const double totalArea = surfaceArea(input);
        baked.baseColors.assign(baked.images.size(), {});
        for (size_t c = 0; c < baked.images.size(); ++c) {
            ChartReport& chart = report.charts[c];
            const uint32_t level =
                colorLevelFor(chart.resolution, chart.areaFraction, colour.samplesPerArea(), totalArea);
            const GeometryImage positions = downsampleNested(baked.images[c].positions, level);
            const GeometryImage normals = downsampleNested(baked.images[c].normals, level);
            const uint32_t n = positions.size;
            const std::vector<SurfaceLocation> at = locateOnSurface(located, positions, normals);
            // The area-preserving map gives every sample the same share of the chart's area.
            const double footprint = std::sqrt(chart.areaFraction * totalArea) / double(n - 1);
            GeometryImage rgb(n), alpha(n);
            for (size_t i = 0; i < at.size(); ++i) {
                const glm::dvec4 linear = colour.baseColor(at[i].triangle, at[i].bary, footprint);
                rgb.texels[i] = glm::vec3(linearToSrgb(linear.r), linearToSrgb(linear.g), linearToSrgb(linear.b));
                alpha.texels[i] = glm::vec3(float(linear.a));
            }
            // Mates of a matched seam take one colour (as their positions are one point).
            const ChartSeams& seams = result.charts[c].seams;
            if (seams.matched && level <= seams.coarsestWatertightLevel) {
                const std::vector<uint32_t> table = seamWeldTable(seams, chart.resolution, level);
                weldSeams(rgb, table);
                weldSeams(alpha, table);
            }
            BakedColor& out = baked.baseColors[c];
            out.level = level;
            out.rgba.resize(size_t(n) * n * 4);
            for (size_t i = 0; i < rgb.texels.size(); ++i) {
                for (int k = 0; k < 3; ++k)
                    out.rgba[i * 4 + size_t(k)] =
                        uint8_t(std::lround(255.0 * glm::clamp(rgb.texels[i][k], 0.0f, 1.0f)));
                out.rgba[i * 4 + 3] = uint8_t(std::lround(255.0 * glm::clamp(alpha.texels[i].x, 0.0f, 1.0f)));
            }
            chart.colorLevel = int(level);
        }
        return 0;
    });
    const ChartReport& largest = report.charts[0];
    announce(
        options, "appearance",
        format("base colour from %s: %ux%u texels in the largest chart (level %d), %.3g samples per unit area needed",
               options.appearance->cornerUVs.empty()
                   ? (options.appearance->cornerColors.empty() ? "materials" : "vertex colours")
                   : "textures",
               (largest.resolution >> largest.colorLevel) + 1, (largest.resolution >> largest.colorLevel) + 1,
               largest.colorLevel, report.colorSamplesPerArea));
}

}  // namespace ngi::detail
