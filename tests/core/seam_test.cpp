// Seam tables and the weld (core/include/ngi/seam.h): perimeter convention, transitive mate
// classes, alignment levels, validation of hostile segments, and the weld itself.
#include "ngi/seam.h"

#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace {

TEST(Seam, PerimeterRunsCounterClockwiseFromTheOrigin)
{
    const uint32_t r = 8;
    EXPECT_EQ(ngi::perimeterSample(r, 0), glm::uvec2(0, 0));
    EXPECT_EQ(ngi::perimeterSample(r, 3), glm::uvec2(3, 0));
    EXPECT_EQ(ngi::perimeterSample(r, 8), glm::uvec2(8, 0));
    EXPECT_EQ(ngi::perimeterSample(r, 11), glm::uvec2(8, 3));
    EXPECT_EQ(ngi::perimeterSample(r, 16), glm::uvec2(8, 8));
    EXPECT_EQ(ngi::perimeterSample(r, 19), glm::uvec2(5, 8));
    EXPECT_EQ(ngi::perimeterSample(r, 24), glm::uvec2(0, 8));
    EXPECT_EQ(ngi::perimeterSample(r, 27), glm::uvec2(0, 5));
    EXPECT_EQ(ngi::perimeterSample(r, 32), glm::uvec2(0, 0));  // wraps to the origin
    // Every border sample exactly once.
    std::set<std::pair<uint32_t, uint32_t>> seen;
    for (uint32_t t = 0; t < 4 * r; ++t) {
        const glm::uvec2 p = ngi::perimeterSample(r, t);
        EXPECT_TRUE(p.x == 0 || p.y == 0 || p.x == r || p.y == r);
        seen.insert({p.x, p.y});
    }
    EXPECT_EQ(seen.size(), 4u * r);
}

TEST(Seam, MateClassesAreTransitiveWithTheSmallestIndexCanonical)
{
    // The genus-0 "slit" cut through three cut nodes: side [0, 8] mates [24, 32] (reversed),
    // side [8, 16] mates [16, 24]; the corner samples 0, 8, 16, 24 form the nodes.
    ngi::ChartSeams seams;
    seams.matched = true;
    seams.segments = {{0, 24, 8}, {8, 16, 8}};
    const auto table = ngi::seamWeldTable(seams, 8);
    ASSERT_EQ(table.size(), 32u);
    EXPECT_EQ(table[3], 3u);
    EXPECT_EQ(table[29], 3u);   // 24 + 8 - 3
    EXPECT_EQ(table[20], 12u);  // 16 + 8 - 12
    EXPECT_EQ(table[16], 16u);  // the slit's tip mates itself
    EXPECT_EQ(table[24], 8u);   // node: 8 (end of side one, start of side two) = 24 = 24
    EXPECT_EQ(table[0], 0u);    // 0 mates 32 = 0: itself
    for (uint32_t t = 0; t < 32; ++t) EXPECT_LE(table[t], t);
    EXPECT_EQ(ngi::seamAlignedLevel(seams.segments, 10), 3u);
    EXPECT_EQ(ngi::seamAlignedLevel({{0, 24, 8}, {8, 18, 6}}, 10), 1u);
    EXPECT_EQ(ngi::seamAlignedLevel({}, 5), 5u);
}

TEST(Seam, WeldMakesMatesBitwiseEqualAndMeasuresTheGap)
{
    ngi::GeometryImage image(9);
    for (uint32_t y = 0; y < 9; ++y)
        for (uint32_t x = 0; x < 9; ++x) image.at(x, y) = {float(x), float(y), 0.001f * float(x * y)};
    ngi::ChartSeams seams;
    seams.matched = true;
    seams.segments = {{0, 16, 8}};  // bottom row = top row (a cylinder)
    const auto table = ngi::seamWeldTable(seams, 8);
    const ngi::SeamGap before = ngi::measureSeamGap(image, table);
    EXPECT_EQ(before.unequalMates, 9u);  // top row x = 0..8
    EXPECT_NEAR(before.maxDistance, std::sqrt(64.0 + 0.064 * 0.064), 1e-4);
    ngi::weldSeams(image, table);
    for (uint32_t x = 0; x <= 8; ++x) EXPECT_EQ(image.at(x, 8), image.at(x, 0));
    EXPECT_EQ(image.at(4, 4), glm::vec3(4.0f, 4.0f, 0.016f));  // interior untouched
    EXPECT_EQ(ngi::measureSeamGap(image, table).unequalMates, 0u);
    // A welded image stays welded at every nested level the seam is aligned to.
    const auto pyramid = ngi::buildMipPyramid(image);
    for (uint32_t level = 1; level <= 3; ++level) {
        const ngi::GeometryImage& l = pyramid[level];
        for (uint32_t x = 0; x < l.size; ++x) EXPECT_EQ(l.at(x, l.size - 1), l.at(x, 0));
    }
    // The level tables are the full table on the level's samples.
    seams.coarsestWatertightLevel = 3;
    const auto level2 = ngi::seamWeldTable(seams, 8, 2);
    ASSERT_EQ(level2.size(), 8u);
    EXPECT_EQ(level2[5], 1u);  // full 20 -> canonical 4
    EXPECT_EQ(level2[1], 1u);
    EXPECT_THROW(ngi::seamWeldTable(seams, 8, 4), ngi::Error);
    ngi::GeometryImage wrong(5);
    EXPECT_THROW(ngi::weldSeams(wrong, table), ngi::Error);
}

TEST(Seam, ValidationNamesTheBadSegment)
{
    auto problem = [](ngi::ChartSeams s, uint32_t resolution = 16, uint32_t levels = 5) {
        try {
            ngi::validateSeams(s, resolution, levels, "x.ngi");
        } catch (const ngi::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    ngi::ChartSeams good;
    good.matched = true;
    good.coarsestWatertightLevel = 2;
    good.segments = {{0, 32, 16}, {16, 48, 16}};
    EXPECT_EQ(problem(good), "");
    ngi::ChartSeams s = good;
    s.segments[1].length = 0;
    EXPECT_NE(problem(s).find("x.ngi: seam segment 1 is empty"), std::string::npos);
    s = good;
    s.segments[0].b = 60;
    EXPECT_NE(problem(s).find("seam segment 0 runs past the border's 64 samples"), std::string::npos);
    s = good;
    s.segments[0].a = 0xfffffff0u;  // wraps in 32 bits
    EXPECT_NE(problem(s).find("runs past"), std::string::npos);
    s = good;
    s.segments[1].a = 18;
    EXPECT_NE(problem(s).find("does not end on samples of level 2"), std::string::npos);
    s = good;
    s.coarsestWatertightLevel = 5;
    EXPECT_NE(problem(s).find("beyond the chart's 5 levels"), std::string::npos);
}

TEST(Seam, AssetKeepsTheSeamAndRejectsABadOne)
{
    ngi::Asset a;
    a.sourceName = "analytic:cylinder";
    ngi::AssetChart chart;
    chart.fullResolution = 16;
    chart.storedLevel = 1;
    ngi::GeometryImage p(chart.storedSize()), n(chart.storedSize());
    for (auto& t : n.texels) t = {0, 0, 1};
    ngi::storeGeometryImage(chart, p, n);
    chart.seams.matched = true;
    chart.seams.coarsestWatertightLevel = 3;
    chart.seams.segments = {{0, 32, 16}};
    a.charts.push_back(chart);
    const ngi::Asset b = ngi::parseAsset(ngi::serializeAsset(a), "c.ngi");
    ASSERT_TRUE(b.charts[0].seams.matched);
    EXPECT_EQ(b.charts[0].coarsestDrawnLevel(), 3u);  // the seam's level 3, coarser than the 5 x 5 cap (level 2)
    EXPECT_EQ(b.charts[0].levelCount(), 5u);
    ASSERT_EQ(b.charts[0].seams.segments.size(), 1u);
    EXPECT_EQ(b.charts[0].seams.segments[0].b, 32u);
    a.charts[0].seams.segments[0].a = 3;  // not on a level-3 sample
    EXPECT_THROW(ngi::serializeAsset(a), ngi::Error);
    a.charts[0].seams.matched = false;  // an unmatched chart draws every level
    const ngi::Asset c = ngi::parseAsset(ngi::serializeAsset(a), "c.ngi");
    EXPECT_FALSE(c.charts[0].seams.matched);
    EXPECT_EQ(c.charts[0].coarsestDrawnLevel(), 4u);
    a.charts[0].seams.matched = true;               // watertight only to level 1 (finer than the 5 x 5 cap):
    a.charts[0].seams.coarsestWatertightLevel = 1;  // the LoD range ends there, no level opens
    a.charts[0].seams.segments[0].a = 2;
    const ngi::Asset d = ngi::parseAsset(ngi::serializeAsset(a), "d.ngi");
    EXPECT_EQ(d.charts[0].coarsestDrawnLevel(), 1u);
}

// Two charts of 8 cells sharing a curve: chart 0's bottom side (perimeter 0..8) is chart 1's top
// side (16..24), and chart 1's right side is its own left side (a cut path).
// The group weld makes every mate bitwise chart 0's value (the smallest index), transitively,
// at level 0 and level 1, and refuses a level the seams are not aligned to.
TEST(Seam, GroupWeldCopiesTheCanonicalAcrossCharts)
{
    const uint32_t r = 8;
    auto image = [&](float base, uint32_t size) {
        ngi::GeometryImage g;
        g.size = size;
        g.texels.resize(size_t(size) * size);
        for (size_t i = 0; i < g.texels.size(); ++i) g.texels[i] = glm::vec3(base + float(i), base, -base);
        return g;
    };
    std::vector<ngi::ChartSeams> seams(2);
    for (ngi::ChartSeams& s : seams) s.matched = true, s.coarsestWatertightLevel = 1;
    seams[1].segments = {{8, 24, 8}};  // right side (8..16) against left side (24..32)
    const std::vector<ngi::CrossSeamSegment> cross{{0, 0, 1, 16, 8}};
    for (uint32_t level : {0u, 1u}) {
        const uint32_t n = (r >> level) + 1;
        ngi::GeometryImage a = image(0.0f, n), b = image(1000.0f, n);
        std::vector<ngi::GeometryImage*> images{&a, &b};
        const double moved = ngi::weldGroupSeams(images, seams, {r, r}, cross, level);
        EXPECT_GT(moved, 100.0);
        // Chart 1's top side runs from x = R to 0 along its perimeter, so against chart 0's
        // bottom side (x = 0 to R) the curve pairs equal x.
        for (uint32_t i = 0; i < n; ++i) EXPECT_EQ(b.at(i, n - 1), a.at(i, 0)) << level << " " << i;
        // Chart 1's cut path joins its top corners, so chart 0's bottom corners are one class
        // too (transitively), chart 0's origin its canonical.
        EXPECT_EQ(a.at(n - 1, 0), a.at(0, 0));
        EXPECT_EQ(b.at(n - 1, n - 1), a.at(0, 0));
        EXPECT_EQ(a.at(0, 0), glm::vec3(0.0f, 0.0f, -0.0f));
    }
    ngi::GeometryImage a = image(0.0f, 3), b = image(1.0f, 3);
    std::vector<ngi::GeometryImage*> images{&a, &b};
    EXPECT_THROW(ngi::weldGroupSeams(images, seams, {r, r}, cross, 2), ngi::Error);
}

}  // namespace
