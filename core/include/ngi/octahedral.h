// ngi core: octahedral unit-vector encoding in 2 x 16 bits (Cigolle et al. 2014, "A Survey
// of Efficient Representations for Independent Unit Vectors", JCGT 3(2)). The GPU keeps a
// geometry-image normal in one 32-bit word this way; shaders/texel.glsl is the GLSL mirror.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>

namespace ngi {

// Packs a (not necessarily unit) vector's direction; a zero vector packs as +z.
uint32_t packNormalOctahedral(glm::vec3 n);

// Unit vector from packed bits.
glm::vec3 unpackNormalOctahedral(uint32_t bits);

}  // namespace ngi
