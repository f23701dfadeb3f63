// The compact GPU texel (compact_texel.h). Octahedral normals after Cigolle et al. 2014,
// "A Survey of Efficient Representations for Independent Unit Vectors", JCGT 3(2),
// section 3.3 and its precise (best-rounding) encoder.
#include "ngi/compact_texel.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi {
namespace {

float signNotZero(float v) { return v >= 0.0f ? 1.0f : -1.0f; }

uint16_t latticeCoordinate(float v)
{
    const float t = (v - kCompactOrigin) / kCompactExtent;
    if (!(t > 0.0f)) return 0;  // below the lattice, or NaN
    return uint16_t(std::lround(std::min(t, 1.0f) * 65535.0f));
}

// The unit vector of 8-bit codes (cx, cy): snorm-like, code c stands for (c - 127) / 127, so
// that 0 and +-1 (the axes) are exact; 255 is never written and reads as 254.
glm::vec3 octDecode(uint32_t cx, uint32_t cy)
{
    const float ex = (float(std::min(cx, 254u)) - 127.0f) / 127.0f, ey = (float(std::min(cy, 254u)) - 127.0f) / 127.0f;
    glm::vec3 n(ex, ey, 1.0f - std::abs(ex) - std::abs(ey));
    if (n.z < 0.0f) {
        n.x = (1.0f - std::abs(ey)) * signNotZero(ex);
        n.y = (1.0f - std::abs(ex)) * signNotZero(ey);
    }
    return glm::normalize(n);
}

uint16_t packNormal8x8(glm::vec3 n)
{
    const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(l1 > 0.0f) || !std::isfinite(l1)) return uint16_t(127 | 127 << 8);  // +z
    n /= l1;
    float ex = n.x, ey = n.y;
    if (n.z < 0.0f) {
        ex = (1.0f - std::abs(n.y)) * signNotZero(n.x);
        ey = (1.0f - std::abs(n.x)) * signNotZero(n.y);
    }
    const float fx = std::clamp(ex * 127.0f + 127.0f, 0.0f, 254.0f);
    const float fy = std::clamp(ey * 127.0f + 127.0f, 0.0f, 254.0f);
    const glm::vec3 unit = glm::normalize(n);
    uint32_t best = 0;
    float bestDot = -2.0f;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const uint32_t cx = std::min(uint32_t(std::floor(fx)) + dx, 254u);
            const uint32_t cy = std::min(uint32_t(std::floor(fy)) + dy, 254u);
            const float d = glm::dot(octDecode(cx, cy), unit);
            if (d > bestDot) bestDot = d, best = cx | cy << 8;
        }
    return uint16_t(best);
}

}  // namespace

glm::u16vec4 packCompactTexel(glm::vec3 position, glm::vec3 normal)
{
    return {latticeCoordinate(position.x), latticeCoordinate(position.y), latticeCoordinate(position.z),
            packNormal8x8(normal)};
}

glm::vec3 compactTexelPosition(glm::u16vec4 texel)
{
    // As shaders/texel.glsl: code * (extent / 65535) + origin, in float.
    const float step = kCompactExtent / 65535.0f;
    return glm::vec3(float(texel.x), float(texel.y), float(texel.z)) * step + kCompactOrigin;
}

glm::vec3 compactTexelNormal(glm::u16vec4 texel) { return octDecode(texel.w & 0xFFu, texel.w >> 8); }

std::vector<glm::u16vec4> makeLevelCompact(GeometryImage& positions, GeometryImage& normals)
{
    std::vector<glm::u16vec4> compact(positions.texels.size());
    for (size_t i = 0; i < compact.size(); ++i) {
        compact[i] = packCompactTexel(positions.texels[i], normals.texels[i]);
        positions.texels[i] = compactTexelPosition(compact[i]);
        normals.texels[i] = compactTexelNormal(compact[i]);
    }
    return compact;
}

}  // namespace ngi
