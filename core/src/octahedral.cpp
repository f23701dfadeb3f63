// Octahedral unit vectors: Cigolle et al. 2014, JCGT 3(2), section 3.3. Matches GLSL's
// packUnorm2x16 rounding (round(clamp(v, 0, 1) * 65535)).
#include "ngi/octahedral.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi {
namespace {

float signNotZero(float v) { return v >= 0.0f ? 1.0f : -1.0f; }
uint32_t unorm16(float v) { return uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f)); }

}  // namespace

uint32_t packNormalOctahedral(glm::vec3 n)
{
    const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(l1 > 0.0f)) return unorm16(0.5f) | unorm16(0.5f) << 16;
    n /= l1;
    float ex = n.x, ey = n.y;
    if (n.z < 0.0f) {
        ex = (1.0f - std::abs(n.y)) * signNotZero(n.x);
        ey = (1.0f - std::abs(n.x)) * signNotZero(n.y);
    }
    return unorm16(ex * 0.5f + 0.5f) | unorm16(ey * 0.5f + 0.5f) << 16;
}

glm::vec3 unpackNormalOctahedral(uint32_t bits)
{
    const float ex = float(bits & 0xffffu) / 65535.0f * 2.0f - 1.0f;
    const float ey = float(bits >> 16) / 65535.0f * 2.0f - 1.0f;
    glm::vec3 n(ex, ey, 1.0f - std::abs(ex) - std::abs(ey));
    if (n.z < 0.0f) {
        n.x = (1.0f - std::abs(ey)) * signNotZero(ex);
        n.y = (1.0f - std::abs(ex)) * signNotZero(ey);
    }
    return glm::normalize(n);
}

}  // namespace ngi
