// makeBijectiveOnSquare's relaxation (untangle.cpp) on a layout whose mean-value weights span
// many orders of magnitude: a row of interior vertices collapsed onto a side (what OT's
// centroid map did on cheese). The relaxation must lift the row off the side with no flips.
// Note: the raised floors of 9f46a61 (1e-2 .. 1) are not reached here: the first floor (1e-3)
// already untangles this layout and every squeeze towards a side tried (columns at 1 - r^k,
// r down to 1e-6); cheese's flips after floor 1e-3 come from a layout not reproduced yet.
#include "disk_meshes.h"

#include "ngi/param/disk_topology.h"
#include "ngi/param/fixed_border_maps.h"
#include "ngi/param/untangle.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>

namespace ngi {
namespace {

// An n x n plane patch laid out on the unit square, with the interior vertices of row 1
// collapsed onto the bottom side, `offset` to the right of the boundary vertex below them.
struct Collapsed {
    DiskMesh disk;
    DiskTopology topology;
    std::array<size_t, 4> corners{};
    std::vector<glm::dvec2> uv;
};
Collapsed collapsedRow(int n, double offset)
{
    Collapsed c;
    c.disk = test::planePatch(n, 0.0);
    c.topology = analyzeDisk(c.disk);
    c.corners = {0, size_t(n), size_t(2 * n), size_t(3 * n)};
    for (const glm::dvec3& p : c.disk.mesh.positions) c.uv.push_back({p.x, p.y});
    for (int x = 1; x < n; ++x) c.uv[size_t(n + 1 + x)] = {double(x) / n + offset, 0.0};
    return c;
}

TEST(Untangle, RowCollapsedOntoASideIsLiftedOff)
{
    const Collapsed c = collapsedRow(8, 1e-15);
    ASSERT_GT(countFlippedTriangles(c.disk, c.uv), 0u);  // the collapsed strip has zero area

    UntangleReport report;
    const std::vector<glm::dvec2> uv = makeBijectiveOnSquare(c.disk, c.topology, c.corners, c.uv, &report);
    EXPECT_TRUE(report.relaxed);
    EXPECT_GT(report.flippedBefore, 0u);
    EXPECT_EQ(report.flippedAfter, 0u);
    EXPECT_EQ(countFlippedTriangles(c.disk, uv), 0u);
    EXPECT_GE(report.weightFloor, 1e-3);
    // Every interior vertex is inside the square, off its sides.
    for (size_t v = 0; v < uv.size(); ++v)
        if (c.topology.boundaryPosition[v] < 0) {
            EXPECT_GT(std::min({uv[v].x, uv[v].y, 1.0 - uv[v].x, 1.0 - uv[v].y}), 1e-6) << "vertex " << v;
        }
}

TEST(Untangle, ValidLayoutIsLeftAlone)
{
    Collapsed c = collapsedRow(6, 0.0);
    for (size_t v = 0; v < c.uv.size(); ++v) c.uv[v] = {c.disk.mesh.positions[v].x, c.disk.mesh.positions[v].y};
    UntangleReport report;
    const std::vector<glm::dvec2> uv = makeBijectiveOnSquare(c.disk, c.topology, c.corners, c.uv, &report);
    EXPECT_FALSE(report.relaxed);
    EXPECT_EQ(report.flippedAfter, 0u);
    for (size_t v = 0; v < uv.size(); ++v) EXPECT_NEAR(glm::distance(uv[v], c.uv[v]), 0.0, 1e-15);
}

}  // namespace
}  // namespace ngi
