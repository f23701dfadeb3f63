// The tile bound's 16-byte code (ngi/tile_bound_code.h): a decoded bound holds the measured one
// (sphere, cone, errors), loses little, codes again to the same bound, and codes what is not
// finite as a bound that still holds.
#include "ngi/compact_texel.h"
#include "ngi/error.h"
#include "ngi/tile_bound_code.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace {

double angleBetween(glm::vec3 a, glm::vec3 b)
{
    const glm::dvec3 u = glm::normalize(glm::dvec3(a)), v = glm::normalize(glm::dvec3(b));
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

ngi::TileBound randomBound(std::mt19937& rng)
{
    std::uniform_real_distribution<float> inside(0.0f, 1.0f), unit(0.0f, 1.0f);
    std::normal_distribution<float> gauss;
    ngi::TileBound b;
    b.centre = {inside(rng), inside(rng), inside(rng)};
    b.radius = std::pow(10.0f, -4.0f + 4.0f * unit(rng));  // 1e-4 .. 1
    b.error = unit(rng) < 0.1f ? 0.0f : std::pow(10.0f, -7.0f + 6.0f * unit(rng));
    b.errorUp = b.error * (1.0f + 8.0f * unit(rng));
    b.coneAxis = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    b.coneCos = unit(rng) < 0.2f ? -1.0f : std::cos(0.5f * std::numbers::pi_v<float> * unit(rng));
    return b;
}

TEST(TileBoundCode, TheDecodedBoundHoldsTheMeasuredOne)
{
    std::mt19937 rng(5);
    int cones = 0;
    for (int i = 0; i < 50000; ++i) {
        const ngi::TileBound b = randomBound(rng);
        const ngi::TileBound d = ngi::decodeTileBound(ngi::encodeTileBound(b));
        // The sphere: every point of the measured one lies in the decoded one.
        EXPECT_GE(double(d.radius), double(b.radius) + glm::distance(glm::dvec3(b.centre), glm::dvec3(d.centre)));
        // ... and it is at most a half's rounding (2^-10) and two lattice steps larger.
        EXPECT_LE(d.radius, b.radius * (1.0f + 1.0f / 1024.0f) + 2.0f * ngi::kCompactPositionError);
        // The errors round up, by at most a half's rounding (or to its smallest normal value).
        EXPECT_GE(d.error, b.error);
        EXPECT_LE(d.error, std::max(b.error * (1.0f + 1.0f / 1024.0f), std::ldexp(1.0f, -14)));
        EXPECT_GE(d.errorUp, b.errorUp);
        EXPECT_GE(d.errorUp, d.error);
        if (b.error == 0.0f) {
            EXPECT_EQ(d.error, 0.0f);  // a flat tile stays flat
        }
        // The cone: the decoded one holds the measured one, and is none when the measured is none.
        if (b.coneCos <= 0.0f) {
            EXPECT_LE(d.coneCos, 0.0f);
        } else if (d.coneCos > 0.0f) {
            ++cones;
            EXPECT_NEAR(glm::length(d.coneAxis), 1.0f, 1e-5f);
            EXPECT_GE(std::acos(double(d.coneCos)),
                      std::acos(double(b.coneCos)) + angleBetween(b.coneAxis, d.coneAxis));
            // The axis turns by at most 0.7 degrees (compact_texel.h), and the cos by a half's rounding more.
            EXPECT_LE(std::acos(double(d.coneCos)),
                      std::acos(double(b.coneCos)) + 0.7 * std::numbers::pi / 180.0 + 0.03);
        }
    }
    EXPECT_GT(cones, 20000);  // most measured cones survive as cones
}

TEST(TileBoundCode, ADecodedBoundCodesToTheSameBound)
{
    std::mt19937 rng(9);
    for (int i = 0; i < 20000; ++i) {
        const ngi::TileBound once = ngi::decodeTileBound(ngi::encodeTileBound(randomBound(rng)));
        const ngi::TileBound twice = ngi::decodeTileBound(ngi::recodeTileBound(once));
        ASSERT_EQ(twice.centre, once.centre) << "bound " << i;
        ASSERT_EQ(twice.radius, once.radius) << "bound " << i;
        ASSERT_EQ(twice.coneAxis, once.coneAxis) << "bound " << i;  // -0 == 0: one axis on the fold
        ASSERT_EQ(twice.coneCos, once.coneCos) << "bound " << i;
        ASSERT_EQ(twice.error, once.error) << "bound " << i;
        ASSERT_EQ(twice.errorUp, once.errorUp) << "bound " << i;
        // Encoding it as a measured bound again widens only the cone (its margin), never narrows.
        const ngi::TileBound again = ngi::decodeTileBound(ngi::encodeTileBound(once));
        ASSERT_EQ(again.radius, once.radius) << "bound " << i;
        ASSERT_LE(again.coneCos, once.coneCos) << "bound " << i;
    }
    // A bound that no code stands for is not recoded silently.
    ngi::TileBound measured;
    measured.centre = {0.3f, 0.4f, 0.5f};
    measured.radius = 0.1f;
    EXPECT_THROW(ngi::recodeTileBound(measured), ngi::Error);
}

TEST(TileBoundCode, NoHalfIsSubnormalAndANaNErrorStaysBelowItsErrorUp)
{
    ngi::TileBound b;
    b.centre = {0.5f, 0.5f, 0.5f};
    b.radius = 1e-9f;
    b.error = 1e-30f;
    b.errorUp = 2e-30f;
    ngi::TileBound d = ngi::decodeTileBound(ngi::encodeTileBound(b));
    const float smallestNormal = std::ldexp(1.0f, -14);
    EXPECT_GE(d.error, smallestNormal);  // a GPU that flushes subnormal halves would read 0
    EXPECT_GE(d.errorUp, smallestNormal);
    EXPECT_GE(d.radius, smallestNormal);
    b.error = std::numeric_limits<float>::quiet_NaN();
    b.errorUp = 0.5f;
    d = ngi::decodeTileBound(ngi::encodeTileBound(b));
    EXPECT_EQ(d.error, std::numeric_limits<float>::infinity());
    EXPECT_GE(d.errorUp, d.error);
}

TEST(TileBoundCode, WhatIsNotFiniteStillBounds)
{
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    ngi::TileBound b;
    b.centre = {0.5f, 0.5f, 0.5f};
    b.radius = nan;
    b.error = 1e30f;  // past half's range
    b.errorUp = inf;
    b.coneCos = 0.99999f;
    b.coneAxis = {0.0f, 0.0f, 1.0f};
    ngi::TileBound d = ngi::decodeTileBound(ngi::encodeTileBound(b));
    EXPECT_EQ(d.radius, inf);
    EXPECT_EQ(d.error, inf);
    EXPECT_EQ(d.errorUp, inf);
    EXPECT_GT(d.coneCos, 0.99f);  // +z is exact on the octahedral lattice: the cone stays narrow
    // A cone that the axis's rounding would widen past a hemisphere is none.
    b.radius = 0.1f;
    b.coneCos = 1e-5f;
    b.coneAxis = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
    d = ngi::decodeTileBound(ngi::encodeTileBound(b));
    EXPECT_LE(d.coneCos, 0.0f);
    EXPECT_EQ(ngi::roundUpToHalf(nan), inf);
    EXPECT_EQ(ngi::roundUpToHalf(0.0f), 0.0f);
    EXPECT_GE(ngi::roundUpToHalf(0.1f), 0.1f);
    EXPECT_EQ(ngi::roundUpToHalf(1e-30f), std::ldexp(1.0f, -14));
}

}  // namespace
