// ngi core: coarse levels that approximate the surface instead of interpolating it. A nested
// level's samples all lie on the full surface, so its triangles cut every convex bump and
// miss every concave one by the whole sagitta. fitCoarseLevels moves each interior sample of
// each coarser level to the linear least-squares fit of the level's triangles (alternating
// diagonals) to the full surface, with the parameterization fixed (the vertex-position step of
// Hoppe et al. 1993, "Mesh Optimization", SIGGRAPH, section 4.2, on the level's grid),
// reweighted towards the fit of the smallest largest distance (Lawson 1961, "Contributions to
// the Theory of Linear Least Maximum Approximation", PhD thesis, UCLA). The
// samples on the square's border keep their nested values, so seam mates stay bitwise equal
// and every guarantee of the seams holds; the geomorph then runs to the coarser level's
// surface at the vertex's uv (coarserSurfaceAt), which for nested levels is the usual target.
#pragma once

#include "ngi/lod_grid.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <utility>

namespace ngi {

// Replaces levels 1 .. of `pyramid` (nested subsamples of level 0, as buildSurfacePyramid
// makes them) by their fits to level 0. Each level's interior samples first minimize the sum
// of squared distances between its triangles, at the uv of each data sample, and the data
// sample (level 0 for levels 1 and 2, every sample of level k - 2 of the nested pyramid for
// level k: at least 16 data per quad); then `rounds` rounds of Lawson's reweighting move the
// fit towards the smallest largest distance, which is what the tile bounds measure.
// Conjugate gradients, `iterations` per solve (a third of them after the first), started
// from the nested values; border samples and normals are kept. The levels are fitted on
// parallel threads; the result does not depend on their number. A level of fewer than 3 x 3
// samples has no interior and is kept.
void fitCoarseLevels(SurfacePyramid& pyramid, uint32_t iterations = 16, uint32_t rounds = 4);

// The surface of level image `coarser` (alternating diagonals) at the uv of sample (x, y) of
// the next finer level, and its normal there (interpolated like the position, normalized; +z
// where the interpolation vanishes): the geomorph target of that sample.
std::pair<glm::vec3, glm::vec3> coarserSurfaceAt(const GeometryImage& coarserPositions,
                                                 const GeometryImage& coarserNormals, uint32_t x, uint32_t y);

}  // namespace ngi
