// ngi offline: the bake's refusal of a map that would make a garbage geometry image. A map to
// the square gives each triangle a share of the samples proportional to its uv area; where that
// share is far below the triangle's share of the surface, the image has holes and streaks
// there. A bake whose chart is squeezed like that over a large part of its surface (cheese,
// genus 133 in one chart: 46% of the area at < 1/100, CD 110 x1e-4) must fail, not ship.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec2.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace ngi {

// A triangle is undersampled when its share of the uv area times this factor is still below
// its share of the 3D area (it gets < 1/100 of its fair share of samples).
inline constexpr double kUndersamplingFactor = 100.0;
// The bake fails when more than this fraction of a chart's 3D area is undersampled. Chosen
// between what real meshes reach after the extremity cut (camel 2.8%, elephant-with-holes 5.8%,
// dino 0.4%) and what is unusable (cheese 46%).
inline constexpr double kMaxUndersampledAreaFraction = 0.20;

// The same measure as ngi-bake's undersampledAreaFraction (bake.h; the bake may call this one
// instead and drop its own). Fraction of the 3D area of `mesh` whose triangles get less than 1/factor of their fair share
// of the uv area `uv` (one uv per vertex). 0 for a mesh or map of zero area.
double mapUndersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv,
                                   double factor = kUndersamplingFactor);

struct ChartSamplingContext {
    std::string file;   // the input, for the message
    size_t chart = 0;   // 0-based chart index
    size_t charts = 1;  // charts of the asset
    long genus = 0;     // of the chart's component
    double maxUndersampledAreaFraction = kMaxUndersampledAreaFraction;
};

// Throws ngi::Error when more than context.maxUndersampledAreaFraction of the chart's area is
// undersampled (see above), naming the file, the chart, its genus and the fraction, with a
// hint. `undersampledFraction` is mapUndersampledAreaFraction of the chart's mesh and map.
void checkChartSampling(double undersampledFraction, const ChartSamplingContext& context);

// The image check, on what the map made rather than on the map: the part of the input surface
// farther than kFarFromImageDistance x the chart's longest bounding-box side from the geometry
// image's surface. A map can pass the sampling check and still be garbage (cheese, genus 133,
// after the both-graphs cut search: 8.8% undersampled, below the limit, but LoD-0 CD 36 x1e-4,
// HD 24% of its size). Real meshes stay far below the limit (see kMaxFarFromImageArea).
inline constexpr double kFarFromImageDistance = 0.05;
inline constexpr double kMaxFarFromImageArea = 0.02;

// Throws ngi::Error when more than kMaxFarFromImageArea of the chart's input area lies farther
// than kFarFromImageDistance of its size from the geometry image (`farArea`, a fraction of the
// chart's area), naming the file, chart, genus and fraction.
void checkChartImage(double farArea, const ChartSamplingContext& context);

}  // namespace ngi
