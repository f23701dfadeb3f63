// ngi core: the compact texel the adaptive draw keeps on the GPU, 8 bytes per sample
// (RGBA16UI) where the restore works in 16 (RGBA32UI: float position bits and a 2 x 16-bit
// octahedral normal, ngi_shared.h). x, y, z: the position as 16-bit unorm over one lattice
// shared by every chart of an asset (normalized space, [kCompactOrigin, kCompactOrigin +
// kCompactExtent] per axis), so seam mates, being the same point, get the same bits and stay
// watertight; w: the normal, octahedral in 2 x 8 bits (Cigolle et al. 2014, "A Survey of
// Efficient Representations for Independent Unit Vectors", JCGT 3(2), snorm codes so that
// the axes are exact, the "precise" variant: the best of the four roundings). shaders/texel.glsl decodes it identically
// (compactTexelPosition, compactTexelNormal).
#pragma once

#include "ngi/geometry_image.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace ngi {

// The lattice: normalized space is [0, 1]^3 for the input; the margin keeps a restore that
// overshoots the box by up to 12.5% of the size exact, farther points are clamped onto it.
inline constexpr float kCompactOrigin = -0.125f;
inline constexpr float kCompactExtent = 1.25f;
// The largest distance between a position and its compact one, inside the lattice
// (half a step per axis, times sqrt(3)), in normalized units: 1.66e-5 of the size.
inline constexpr float kCompactPositionError = 0.5f * kCompactExtent / 65535.0f * 1.7320508f;

// The compact texel of a position (normalized space) and a normal (any length; zero or not
// finite packs as +z). A NaN coordinate packs as the lattice's origin.
glm::u16vec4 packCompactTexel(glm::vec3 position, glm::vec3 normal);

// The position and the unit normal a compact texel stands for.
glm::vec3 compactTexelPosition(glm::u16vec4 texel);
glm::vec3 compactTexelNormal(glm::u16vec4 texel);

// A level made compact: returns its compact texels (the GPU's copy) and replaces `positions`
// and `normals` (same size) by what they stand for, the CPU mirror of exactly what is drawn.
std::vector<glm::u16vec4> makeLevelCompact(GeometryImage& positions, GeometryImage& normals);

}  // namespace ngi
