// ngi core: the surface area each sample of a geometry image stands for (the rate
// control and the residual gain weigh a sample's error by it). The evaluation's Chamfer
// distance samples the SURFACE uniformly (DESIGN.md "Metrics"); a map that squeezes a thin
// part (a tail, a neck) into few image samples gives each of them a large share of the
// surface, so an error averaged with one equal weight per image sample underweights exactly
// the parts the coarse levels lose (docs/rate-control.md measures it on diplodocus).
#pragma once

#include "ngi/geometry_image.h"

#include <span>
#include <vector>

namespace ngi {

// Per sample of `positions` (row-major like its texels): the 3D area of the quads around it,
// each quad (cell) giving a quarter of its area |d1 x d2| / 2 (d1, d2 its diagonals) to each of
// its four corners; so the areas sum to the image's quad-mesh area. An image with fewer than
// 2 samples per side has no cells: all 0.
std::vector<double> sampleSurfaceAreas(const GeometryImage& positions);

// sampleSurfaceAreas divided by their mean, so the mean weight is 1 and a weighted mean square
// error stays in the units (and, for a uniform map, the value) of the unweighted one. All 1
// when the image has no area (degenerate or empty cells only).
std::vector<double> surfaceAreaWeights(const GeometryImage& positions);
// The same from areas already computed by sampleSurfaceAreas.
std::vector<double> surfaceAreaWeights(std::span<const double> areas);

}  // namespace ngi
