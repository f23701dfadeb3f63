// measureOpenEdges: the weld, the open-edge count and the crack width on tiny meshes.
#include "ngi/eval/open_edges.h"

#include <gtest/gtest.h>

namespace {

ngi::TriangleMesh tetrahedron()
{
    ngi::TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    return m;
}

TEST(OpenEdges, ClosedIsZeroAndAMissingFaceOpensItsThreeEdges)
{
    ngi::TriangleMesh m = tetrahedron();
    EXPECT_EQ(ngi::measureOpenEdges(m, 1e-6).openEdges, 0u);
    m.triangles.pop_back();
    EXPECT_EQ(ngi::measureOpenEdges(m, 1e-6).openEdges, 3u);
}

TEST(OpenEdges, DuplicatedVerticesWeldWithinTheToleranceOnly)
{
    // Two strips of a 4 x 1 grid sharing a row, the shared row duplicated with an offset d.
    auto strips = [](double d) {
        ngi::TriangleMesh m;
        for (int row = 0; row < 4; ++row)
            for (int x = 0; x <= 4; ++x)
                m.positions.push_back({double(x), row < 2 ? double(row) : double(row - 1) + (row == 2 ? d : 0.0), 0.0});
        auto quad = [&](int r0, int r1) {
            for (int x = 0; x < 4; ++x) {
                const uint32_t a = r0 * 5 + x, b = a + 1, c = r1 * 5 + x + 1, e = r1 * 5 + x;
                m.triangles.push_back({a, b, c});
                m.triangles.push_back({a, c, e});
            }
        };
        quad(0, 1);
        quad(2, 3);
        return m;
    };
    // Welded: one 4 x 2 strip, its boundary has 2 * 4 + 2 * 2 = 12 edges.
    EXPECT_EQ(ngi::measureOpenEdges(strips(0.0), 1e-6).openEdges, 12u);
    EXPECT_EQ(ngi::measureOpenEdges(strips(1e-9), 1e-6).openEdges, 12u);
    // A crack of 0.01: the two seam rows (4 edges each) stay open.
    const ngi::OpenEdgeReport cracked = ngi::measureOpenEdges(strips(0.01), 1e-6);
    EXPECT_EQ(cracked.openEdges, 20u);
    // The gap measure sees any opening, the strips' own boundary too: here across the strip.
    EXPECT_NEAR(cracked.largestGap, 1.01, 1e-9);
    EXPECT_EQ(ngi::measureOpenEdges(tetrahedron(), 1e-6).largestGap, 0.0);
}

}  // namespace
