// The nested-grid mip pyramid keeps the boundary exact at every level.
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

// A geometry image of the unit square itself: texel (x, y) holds its own uv, so each
// level's texels show where its samples sit in the parameter domain.
ngi::GeometryImage uvImage(uint32_t size)
{
    ngi::GeometryImage g(size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) g.at(x, y) = {float(x) / (size - 1), float(y) / (size - 1), 0.0f};
    return g;
}

TEST(MipPyramid, LevelSizes)
{
    EXPECT_TRUE(ngi::isNestedGridSize(1025));
    EXPECT_TRUE(ngi::isNestedGridSize(2));
    EXPECT_FALSE(ngi::isNestedGridSize(1024));
    EXPECT_FALSE(ngi::isNestedGridSize(1));
    EXPECT_EQ(ngi::mipLevelCount(1025), 11u);
    EXPECT_EQ(ngi::mipLevelSize(1025, 3), 129u);
    EXPECT_EQ(ngi::mipLevelSize(1025, 10), 2u);
    EXPECT_THROW(ngi::mipLevelCount(1024), ngi::Error);
}

TEST(MipPyramid, EveryLevelTouchesTheSquaresBorder)
{
    const auto levels = ngi::buildMipPyramid(uvImage(65));
    ASSERT_EQ(levels.size(), 7u);
    for (size_t l = 0; l < levels.size(); ++l) {
        const auto& g = levels[l];
        ASSERT_EQ(g.size, ngi::mipLevelSize(65, uint32_t(l)));
        const uint32_t last = g.size - 1;
        for (uint32_t i = 0; i <= last; ++i) {
            // First/last column at u = 0 / 1, first/last row at v = 0 / 1, exactly.
            EXPECT_EQ(g.at(0, i).x, 0.0f);
            EXPECT_EQ(g.at(last, i).x, 1.0f);
            EXPECT_EQ(g.at(i, 0).y, 0.0f);
            EXPECT_EQ(g.at(i, last).y, 1.0f);
            // Samples stay uniformly spaced in the square (no half-texel drift).
            EXPECT_NEAR(g.at(i, 0).x, float(i) / last, 1e-6f);
        }
    }
}

TEST(MipPyramid, CoarseSamplesAreSubsetOfFine)
{
    ngi::GeometryImage g(33);
    for (size_t i = 0; i < g.texels.size(); ++i) g.texels[i] = {std::sin(float(i)), float(i), 1.0f};
    const auto coarse = ngi::downsampleNested(g, 2);
    ASSERT_EQ(coarse.size, 9u);
    for (uint32_t y = 0; y < 9; ++y)
        for (uint32_t x = 0; x < 9; ++x) EXPECT_EQ(coarse.at(x, y), g.at(4 * x, 4 * y));
    EXPECT_THROW(ngi::downsampleNested(g, 6), ngi::Error);
    EXPECT_EQ(ngi::downsampleNested(g, 5).size, 2u);
}

}  // namespace
