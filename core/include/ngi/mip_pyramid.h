// ngi core: the boundary-exact mip pyramid of a geometry image.
//
// Scheme (after Gu, Gortler, Hoppe 2002, "Geometry Images", section 7): every level has
// (2^k + 1)^2 samples placed at uv = (x, y) / 2^k, so level L+1's samples are exactly the
// even samples of level L. A coarser level is the nested subsample of the finer one:
//     level[L+1](x, y) = level[L](2x, 2y).
// Why not a box filter: on an even-sized image a 2x2 average moves texel centres by half
// a texel per level and pulls the border (the cut seam) inwards, so coarse surfaces shrink
// and open at the seam. With nested subsampling every level's first/last row and column
// are samples of the full-resolution border: the surface keeps its boundary at every
// level, and every coarse vertex lies exactly on the full-resolution surface (the coarse
// mesh interpolates the fine one, as a vertex-subset simplification does). Normals are
// subsampled the same way and stay unit length.
//
// The chain ends at 2x2 (one quad, the four corners): a 1x1 level would have no boundary.
// The engine builds the same chain on the GPU (shaders/mip_downsample.comp); this file is
// its CPU reference and the baker's implementation.
#pragma once

#include "ngi/geometry_image.h"

#include <cstdint>
#include <vector>

namespace ngi {

// True when size = 2^k + 1 for some k >= 0 with size >= 2 (2, 3, 5, 9, ..., 1025, ...).
bool isNestedGridSize(uint32_t size);

// Number of levels from `fullSize` samples down to 2 samples, inclusive.
// fullSize must satisfy isNestedGridSize; 1025 -> 11 levels (1025, 513, ..., 3, 2).
uint32_t mipLevelCount(uint32_t fullSize);

// Samples per side of `level` (0 = full): ((fullSize - 1) >> level) + 1.
uint32_t mipLevelSize(uint32_t fullSize, uint32_t level);

// The level `levels` steps coarser than `fine` by nested subsampling.
// Throws ngi::Error if fine.size is not a nested grid size or has fewer than `levels` steps.
GeometryImage downsampleNested(const GeometryImage& fine, uint32_t levels = 1);

// The next finer nested level by bilinear interpolation (the restore path without the
// super-resolution network; CPU reference of shaders/mip_upsample.comp): even samples copy
// `coarse`, edge midpoints average two samples, cell centres average four as
// ((a + b) + (c + d)) / 4. With `normalize` the averages are renormalized (normal images).
GeometryImage upsampleNested(const GeometryImage& coarse, bool normalize);

// All levels, [0] = `full` itself, down to the 2x2 level.
std::vector<GeometryImage> buildMipPyramid(const GeometryImage& full);

}  // namespace ngi
