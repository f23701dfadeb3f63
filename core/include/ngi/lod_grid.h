// ngi core: the triangle mesh the renderer draws at any level of detail, on the CPU.
// This is the one definition of the drawn surface: shaders/surface.vert mirrors it, and
// ngi-eval exports it, so a test can check that both agree.
//
// Continuous LoD F in [0, levelCount - 1], 0 = full resolution. Level l = floor(F) is drawn
// as its full nested grid (N_l = size of level l vertices per side, 2 (N_l - 1)^2 triangles),
// every vertex geomorphed towards the next coarser level's surface by t = F - l (see
// morphTarget). Each quad is split along its shorter 3D diagonal (ties: diagonal a-c).
// At t = 1 the fine grid lies on the coarse grid's triangles, so F never pops.
// A fixed grid size N that is not a level size samples the coarsest level with at least N
// samples per side bilinearly at uv = (i, j) / (N - 1), without morphing.
#pragma once

#include "ngi/geometry_image.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <utility>
#include <vector>

namespace ngi {

// Positions and normals of every mip level, [0] = full resolution.
struct SurfacePyramid {
    std::vector<GeometryImage> positions;
    std::vector<GeometryImage> normals;
    uint32_t fullSize() const { return positions.empty() ? 0 : positions.front().size; }
    uint32_t levelCount() const { return uint32_t(positions.size()); }
};

// Builds the nested mip pyramid of both images (same size, 2^k + 1). ngi::Error otherwise.
SurfacePyramid buildSurfacePyramid(const GeometryImage& positions, const GeometryImage& normals);

struct LodSelection {
    uint32_t level = 0;     // mip level whose grid is drawn
    float morph = 0.0f;     // geomorph factor towards level + 1, in [0, 1)
    uint32_t gridSize = 0;  // vertices per side drawn
};

// Continuous LoD -> level and morph. `lod` is clamped to [0, levelCount - 1].
LodSelection selectLod(uint32_t levelCount, uint32_t fullSize, float lod);

// The level to sample for an arbitrary grid of N vertices per side: the coarsest level with
// at least N samples. ngi::Error if N < 2 or N > fullSize.
uint32_t levelForGridSize(uint32_t fullSize, uint32_t gridSize);

// Triangles drawn by an N x N vertex grid: 2 (N - 1)^2.
uint64_t gridTriangleCount(uint32_t gridSize);

// Geomorph target of sample (x, y) of one level: the point of the next coarser level's
// surface at the same uv, and its normal (unit). Even samples map to themselves.
std::pair<glm::vec3, glm::vec3> morphTarget(const GeometryImage& positions, const GeometryImage& normals, uint32_t x,
                                            uint32_t y);

// The split of one quad along the geomorph: with corners a, b, c, d (counter-clockwise in
// uv) at positions p(t) = mix(level[i], target[i], t), returns (C, B, A) of
//     f(t) = |c(t) - a(t)|^2 - |d(t) - b(t)|^2 = C + B t + A t^2;
// the quad is split along a-c where f(t) <= 0 (the shorter diagonal), else along b-d.
glm::vec3 quadDiagonal(const glm::vec3 level[4], const glm::vec3 target[4]);
inline bool splitsAlongAC(glm::vec3 f, float t) { return (f.z * t + f.y) * t + f.x <= 0.0f; }

struct LodMesh {
    std::vector<glm::vec3> positions;  // normalized asset space, one per grid vertex
    std::vector<glm::vec3> normals;
    std::vector<glm::uvec3> triangles;  // counter-clockwise in uv
    std::vector<glm::vec2> uvs;         // grid uv in [0, 1]^2 per vertex (adaptive meshes; empty otherwise)
};

// The mesh drawn at continuous LoD `lod` (clamped as in selectLod).
LodMesh buildLodMesh(const SurfacePyramid& pyramid, float lod);

// The mesh drawn for a fixed grid of N vertices per side (2 <= N <= full size).
LodMesh buildGridMesh(const SurfacePyramid& pyramid, uint32_t gridSize);

}  // namespace ngi
