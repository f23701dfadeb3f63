// ngi tests: where a disk's four square corners go (chooseCornerPositions): on the boundary's own
// sharp corners where it has them (a flat part, a single triangle), at equal arc lengths where
// its border is smooth or ragged.
#include "disk_meshes.h"

#include "ngi/param/disk_topology.h"
#include "ngi/param/ricci_flow.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ngi {
namespace {

// A flat triangle of side 1 cut into n^2 triangles; the boundary loop starts at corner 0 and
// meets corners 1 and 2 at positions n and 2n.
DiskMesh subdividedTriangle(int n)
{
    DiskMesh disk;
    const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0.5, std::sqrt(3.0) / 2.0, 0);
    auto index = [n](int i, int j) {  // row j from the a-b side, i along it; rows have n + 1 - j vertices
        uint32_t start = 0;
        for (int r = 0; r < j; ++r) start += uint32_t(n + 1 - r);
        return start + uint32_t(i);
    };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n - j; ++i)
            disk.mesh.positions.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n - j; ++i) {
            disk.mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i, j + 1)});
            if (i + 1 < n - j) disk.mesh.triangles.push_back({index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)});
        }
    for (int i = 0; i < n; ++i) disk.boundaryLoop.push_back(index(i, 0));      // a -> b
    for (int j = 0; j < n; ++j) disk.boundaryLoop.push_back(index(n - j, j));  // b -> c
    for (int j = n; j > 0; --j) disk.boundaryLoop.push_back(index(0, j));      // c -> a
    for (uint32_t v = 0; v < disk.mesh.positions.size(); ++v) disk.originalVertex.push_back(v);
    return disk;
}

// The disk with its boundary marked as the surface's own (as cutToDisk marks it with
// CutOptions::cornersAtBoundaryTurns).
DiskMesh ownBoundary(DiskMesh disk)
{
    disk.surfaceBoundary.assign(disk.mesh.positions.size(), 0);
    for (uint32_t v : disk.boundaryLoop) disk.surfaceBoundary[v] = 1;
    return disk;
}

// The largest conformal shrink of the flow's metric against its area-weighted mean (as the
// extremity cut measures it), on the disk with the given corners.
double conformalShrink(const DiskMesh& disk, const std::array<size_t, 4>& corners)
{
    const RicciFlowResult flow = ricciFlowToSquare(disk, analyzeDisk(disk), corners, RicciFlowOptions{});
    double uMean = 0.0;
    for (double u : flow.u) uMean += u;
    uMean /= double(flow.u.size());
    double worst = 0.0;
    for (double u : flow.u) worst = std::max(worst, uMean - u);
    return worst;
}

TEST(SquareCorners, aTrianglesThreeCornersAreCornersOfTheSquareAndTheFourthHalvesASide)
{
    const int n = 24;
    const DiskMesh disk = ownBoundary(subdividedTriangle(n));
    ASSERT_NO_THROW(analyzeDisk(disk));
    const std::array<size_t, 4> corners = chooseCornerPositions(disk);
    for (size_t corner : {size_t(0), size_t(n), size_t(2 * n)})
        EXPECT_NE(std::find(corners.begin(), corners.end(), corner), corners.end()) << corner;
    int halves = 0;
    for (size_t corner : corners)
        halves += corner == size_t(n / 2) || corner == size_t(3 * n / 2) || corner == size_t(5 * n / 2);
    EXPECT_EQ(halves, 1);
    EXPECT_TRUE(std::is_sorted(corners.begin(), corners.end()));
    // Quarter points instead would open at least one 60-degree corner to 180 degrees. With 24
    // subdivisions the flow then shrinks the surface near it by e^6.8 against the mean (e^8.2 on
    // the bake's 16,764-vertex remesh of a one-triangle STL, which read as a thin part); on the
    // triangle's own corners by e^1.9.
    const std::array<size_t, 4> quarters{0, size_t(3 * n / 4), size_t(6 * n / 4), size_t(9 * n / 4)};
    EXPECT_LT(conformalShrink(disk, corners), 0.5 * conformalShrink(disk, quarters));
}

TEST(SquareCorners, aRectanglesCornersAreCornersOfTheSquare)
{
    // A 2:1 plane patch: equal arc lengths would put two corners in the middle of the long sides.
    const int n = 12;
    DiskMesh disk = ownBoundary(test::planePatch(n, 0.3, 1.0));
    for (glm::dvec3& p : disk.mesh.positions) p.x *= 2.0;
    const std::array<size_t, 4> corners = chooseCornerPositions(disk);
    EXPECT_EQ(corners, (std::array<size_t, 4>{0, size_t(n), size_t(2 * n), size_t(3 * n)}));
    // A boundary that is not the surface's own (a cut, a seam to other pieces) keeps equal arc
    // lengths: the quarter points of the 6-unit perimeter, two of them 3/4 along the long sides.
    disk.surfaceBoundary.clear();
    const std::array<size_t, 4> quarters{0, size_t(3 * n / 4), size_t(2 * n), size_t(11 * n / 4)};
    EXPECT_EQ(chooseCornerPositions(disk), quarters);
    // Nor does a border only partly the surface's own (a cut joining boundary loops): the left
    // side here stands for the cut.
    disk = ownBoundary(disk);
    for (size_t k = size_t(3 * n); k < disk.boundaryLoop.size(); ++k) disk.surfaceBoundary[disk.boundaryLoop[k]] = 0;
    EXPECT_EQ(chooseCornerPositions(disk), quarters);
}

TEST(SquareCorners, aSmoothOrRaggedBorderGetsEqualArcLengths)
{
    // A flat round disk, and the same with every other border vertex pulled in by 2% of the
    // radius: a zigzag whose vertices turn by up to 52 degrees each, which cancel over 1/64 of the border.
    for (const double pull : {0.0, 0.02}) {
        DiskMesh disk = ownBoundary(test::ringDisk(24, [](double x, double y) { return glm::dvec3(x, y, 0.0); }));
        for (size_t k = 1; k < disk.boundaryLoop.size(); k += 2)
            disk.mesh.positions[disk.boundaryLoop[k]] *= 1.0 - pull;
        const std::array<size_t, 4> corners = chooseCornerPositions(disk);
        const size_t m = disk.boundaryLoop.size();
        std::vector<double> arc(m + 1, 0.0);
        for (size_t k = 0; k < m; ++k)
            arc[k + 1] = arc[k] +
                glm::length(disk.mesh.positions[disk.boundaryLoop[(k + 1) % m]] -
                            disk.mesh.positions[disk.boundaryLoop[k]]);
        for (int c = 0; c < 4; ++c) {
            const size_t a = corners[c], b = corners[(c + 1) % 4];
            const double side = b > a ? arc[b] - arc[a] : arc[m] - arc[a] + arc[b];
            EXPECT_NEAR(side / arc[m], 0.25, 1.0 / 16.0) << "pull " << pull << ", side " << c;
        }
    }
}

}  // namespace
}  // namespace ngi
