// ngi core: the geometry image (Gu et al. 2002) as a square grid of 3-vectors.
//
// Sampling convention, used everywhere in ngi (baker, mip pyramid, engine, evaluation):
// a geometry image of "resolution R" has R cells per side and size = R + 1 samples per
// side; sample (x, y) sits exactly at uv = (x / R, y / R) in the unit square, so the first
// and last rows and columns lie ON the square's border (the cut seam). R is a power of two
// (1024 by default), which makes every mip level a nested subset of the finer one; see
// mip_pyramid.h.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace ngi {

struct GeometryImage {
    uint32_t size = 0;              // samples per side (resolution + 1)
    std::vector<glm::vec3> texels;  // row-major, texel (x, y) at index y * size + x

    GeometryImage() = default;
    explicit GeometryImage(uint32_t samplesPerSide)
        : size(samplesPerSide), texels(size_t(samplesPerSide) * samplesPerSide, glm::vec3(0.0f))
    {}

    glm::vec3& at(uint32_t x, uint32_t y) { return texels[size_t(y) * size + x]; }
    const glm::vec3& at(uint32_t x, uint32_t y) const { return texels[size_t(y) * size + x]; }
    uint32_t resolution() const { return size > 0 ? size - 1 : 0; }
};

}  // namespace ngi
