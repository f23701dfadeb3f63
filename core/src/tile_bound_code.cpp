// The tile bound's 16-byte code (tile_bound_code.h).
#include "ngi/tile_bound_code.h"

#include "ngi/compact_texel.h"
#include "ngi/error.h"

#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ngi {
namespace {

constexpr uint16_t kHalfInfinity = 0x7C00;
constexpr uint16_t kHalfMinusOne = 0xBC00;
constexpr uint16_t kHalfSmallestNormal = 0x0400;  // 2^-14: a GPU may flush subnormal halves to 0

// The half bits of the smallest normal half >= v (or 0), for v >= 0 (NaN and values past the
// range: +inf).
uint16_t halfAtLeast(double v)
{
    if (!(v <= double(std::numeric_limits<float>::max()))) return kHalfInfinity;
    if (v <= 0.0) return 0;
    if (v <= double(glm::unpackHalf1x16(kHalfSmallestNormal))) return kHalfSmallestNormal;
    uint16_t h = glm::packHalf1x16(float(v));
    while (h < kHalfInfinity && double(glm::unpackHalf1x16(h)) < v) ++h;
    return h;
}

// The half bits of the largest half <= v, for 0 < v <= 1.
uint16_t halfAtMost(double v)
{
    uint16_t h = glm::packHalf1x16(float(v));
    while (h > 0 && double(glm::unpackHalf1x16(h)) > v) --h;
    return h;
}

// The angle between two directions, in double and accurate when small (acos of the dot is not).
double angleBetween(glm::dvec3 a, glm::dvec3 b)
{
    a = glm::normalize(a), b = glm::normalize(b);
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// The centre's lattice: code q stands for q * kCentreStep + kCompactOrigin, with a step of
// 1.25 / 2^16 = 5 * 2^-18, so that the product and the sum are exact in float (19 significant
// bits at most): a GPU that fuses them into one fma finds the same floats.
constexpr float kCentreStep = kCompactExtent / 65536.0f;
static_assert(kCompactExtent == 1.25f && kCompactOrigin == -0.125f, "the exact decode assumes this lattice");

uint16_t centreCode(float v)
{
    const double q = std::round((double(v) - double(kCompactOrigin)) / double(kCentreStep));
    return uint16_t(q > 0.0 ? std::min(q, 65535.0) : 0.0);  // NaN: 0
}

float centreOf(uint32_t q) { return float(q) * kCentreStep + kCompactOrigin; }

// The cone axis of an octahedral 2 x 8-bit code (compact_texel.h's), normalized as n / sqrt(n . n)
// (correctly rounded operations) so that shaders/tile_selection.glsl's coneAxisOf finds the same
// floats on a device that rounds them so too: the CPU and the GPU cull by the same cone.
glm::vec3 coneAxisOf(uint32_t code)
{
    const float ex = (float(std::min(code & 0xFFu, 254u)) - 127.0f) / 127.0f;
    const float ey = (float(std::min(code >> 8, 254u)) - 127.0f) / 127.0f;
    glm::vec3 n(ex, ey, 1.0f - std::abs(ex) - std::abs(ey));
    if (n.z < 0.0f) {
        n.x = (1.0f - std::abs(ey)) * (ex >= 0.0f ? 1.0f : -1.0f);
        n.y = (1.0f - std::abs(ex)) * (ey >= 0.0f ? 1.0f : -1.0f);
    }
    const float squared = n.x * n.x + n.y * n.y + n.z * n.z;
    return n / std::sqrt(squared);
}

}  // namespace

float roundUpToHalf(float v) { return glm::unpackHalf1x16(halfAtLeast(std::isnan(v) ? HUGE_VAL : double(v))); }

TileBoundCode encodeTileBound(const TileBound& bound)
{
    const glm::u16vec4 texel(centreCode(bound.centre.x), centreCode(bound.centre.y), centreCode(bound.centre.z),
                             packCompactTexel(glm::vec3(0.0f), bound.coneAxis).w);
    const glm::vec3 centre(centreOf(texel.x), centreOf(texel.y), centreOf(texel.z));
    const glm::vec3 axis = coneAxisOf(texel.w);

    // The sphere about the rounded centre holds the one about the exact centre.
    const bool finite = std::isfinite(bound.centre.x) && std::isfinite(bound.centre.y) &&
        std::isfinite(bound.centre.z) && std::isfinite(bound.radius);
    const double radius =
        finite ? double(bound.radius) + glm::distance(glm::dvec3(bound.centre), glm::dvec3(centre)) : HUGE_VAL;
    uint16_t coneCos = kHalfMinusOne;
    if (bound.coneCos > 0.0f && bound.coneCos <= 1.0f) {
        // The cone about the rounded axis holds the one about the exact axis; a margin of 1e-6
        // rad covers acos and cos in float and double.
        const double between = angleBetween(bound.coneAxis, axis);
        const double halfAngle = std::acos(double(bound.coneCos)) + between + 1e-6;
        if (halfAngle < 0.5 * std::numbers::pi) {
            const uint16_t h = halfAtMost(std::cos(halfAngle));
            if (h >= kHalfSmallestNormal) coneCos = h;  // else a hemisphere: no cone
        }
    }
    const auto error = [](float e) { return halfAtLeast(std::isnan(e) ? HUGE_VAL : double(std::max(e, 0.0f))); };
    // Non-negative halves order as their bits: errorUp >= error, a NaN error included.
    const uint16_t errorBits = error(bound.error), errorUpBits = std::max(errorBits, error(bound.errorUp));
    TileBoundCode code;
    code.words[0] = uint32_t(texel.x) | uint32_t(texel.y) << 16;
    code.words[1] = uint32_t(texel.z) | uint32_t(texel.w) << 16;
    code.words[2] = uint32_t(halfAtLeast(radius)) | uint32_t(coneCos) << 16;
    code.words[3] = uint32_t(errorBits) | uint32_t(errorUpBits) << 16;
    return code;
}

TileBoundCode recodeTileBound(const TileBound& bound)
{
    TileBoundCode code;
    const uint32_t axis = packCompactTexel(glm::vec3(0.0f), bound.coneAxis).w;
    code.words[0] = uint32_t(centreCode(bound.centre.x)) | uint32_t(centreCode(bound.centre.y)) << 16;
    code.words[1] = uint32_t(centreCode(bound.centre.z)) | axis << 16;
    code.words[2] = uint32_t(glm::packHalf1x16(bound.radius)) | uint32_t(glm::packHalf1x16(bound.coneCos)) << 16;
    code.words[3] = uint32_t(glm::packHalf1x16(bound.error)) | uint32_t(glm::packHalf1x16(bound.errorUp)) << 16;
    const TileBound again = decodeTileBound(code);
    if (!(again.centre == bound.centre && again.coneAxis == bound.coneAxis && again.radius == bound.radius &&
          again.coneCos == bound.coneCos && again.error == bound.error && again.errorUp == bound.errorUp))
        throw Error("tile bound code: the bound is not one that decodeTileBound returned");
    return code;
}

TileBound decodeTileBound(const TileBoundCode& code)
{
    const glm::u16vec4 texel(code.words[0] & 0xFFFFu, code.words[0] >> 16, code.words[1] & 0xFFFFu,
                             code.words[1] >> 16);
    TileBound b;
    b.centre = glm::vec3(centreOf(texel.x), centreOf(texel.y), centreOf(texel.z));
    b.coneAxis = coneAxisOf(texel.w);
    b.radius = glm::unpackHalf1x16(uint16_t(code.words[2] & 0xFFFFu));
    b.coneCos = glm::unpackHalf1x16(uint16_t(code.words[2] >> 16));
    b.error = glm::unpackHalf1x16(uint16_t(code.words[3] & 0xFFFFu));
    b.errorUp = glm::unpackHalf1x16(uint16_t(code.words[3] >> 16));
    return b;
}

}  // namespace ngi
