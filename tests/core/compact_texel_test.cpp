// The adaptive draw's compact texel (ngi/compact_texel.h): how far it moves a position and
// turns a normal, and what it does with values outside the lattice.
#include "ngi/compact_texel.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

TEST(CompactTexel, PositionsMoveAtMostHalfAStepPerAxis)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> inside(-0.1f, 1.1f);
    float worst = 0.0f;
    for (int i = 0; i < 100000; ++i) {
        const glm::vec3 p(inside(rng), inside(rng), inside(rng));
        worst = std::max(worst, glm::distance(p, ngi::compactTexelPosition(ngi::packCompactTexel(p, {0, 0, 1}))));
    }
    // The bound holds up to float rounding of the decode (a few ulp at 1.0).
    EXPECT_LE(worst, ngi::kCompactPositionError * 1.01f);
    EXPECT_GT(worst, ngi::kCompactPositionError * 0.5f);  // the lattice is 16-bit, not finer
}

TEST(CompactTexel, NormalsTurnLessThanSevenTenthsOfADegree)
{
    std::mt19937 rng(11);
    std::normal_distribution<float> gauss;
    double worstDegrees = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        const glm::vec3 back = ngi::compactTexelNormal(ngi::packCompactTexel({0.5f, 0.5f, 0.5f}, n));
        EXPECT_NEAR(glm::length(back), 1.0f, 1e-5f);
        worstDegrees = std::max(worstDegrees, std::acos(std::min(1.0, double(glm::dot(n, back)))) * 180.0 / M_PI);
    }
    // 2 x 8-bit octahedral, best of the four roundings: 0.63 degrees at most over these 100,000 directions.
    EXPECT_LT(worstDegrees, 0.7);
    // Axis directions (flat CAD faces) come back exactly up to float rounding.
    for (const glm::vec3 axis : {glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)})
        EXPECT_GT(glm::dot(axis, ngi::compactTexelNormal(ngi::packCompactTexel({}, axis))), 1.0f - 1e-6f);
}

TEST(CompactTexel, EqualPointsGetEqualBitsAndOutsidersAreClamped)
{
    const glm::vec3 p(0.123456f, 0.654321f, 0.999f);
    EXPECT_EQ(ngi::packCompactTexel(p, {1, 0, 0}).x, ngi::packCompactTexel(p, {0, 1, 0}).x);
    EXPECT_EQ(glm::u16vec3(ngi::packCompactTexel(p, {1, 0, 0})), glm::u16vec3(ngi::packCompactTexel(p, {0, 1, 0})));
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const glm::u16vec4 outside = ngi::packCompactTexel({-5.0f, 7.0f, nan}, {nan, 0, 0});
    EXPECT_EQ(outside.x, 0);
    EXPECT_EQ(outside.y, 65535);
    EXPECT_EQ(outside.z, 0);
    EXPECT_GT(ngi::compactTexelNormal(outside).z, 0.999f);  // not finite: +z
    EXPECT_EQ(ngi::packCompactTexel({inf, -inf, 0}, {0, 0, 0}).x, 65535);
    EXPECT_FLOAT_EQ(ngi::compactTexelPosition({0, 0, 0, 0}).x, ngi::kCompactOrigin);
    EXPECT_NEAR(ngi::compactTexelPosition({65535, 65535, 65535, 0}).y, ngi::kCompactOrigin + ngi::kCompactExtent,
                1e-6f);
}

}  // namespace
