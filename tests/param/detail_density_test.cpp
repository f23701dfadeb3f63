// Tests of the detail-following OT target measure (ngi/param/detail_density.h).
#include "ngi/param/detail_density.h"

#include "disk_meshes.h"
#include "ngi/error.h"
#include "ngi/param/distortion.h"
#include "ngi/param/parameterize.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace {

using ngi::DiskMesh;

// An open tube (radius 1, height 2) cut along one line: column `columns` duplicates column 0
// and originalVertex joins them, as the cut stage records a seam.
DiskMesh cutTube(int columns, int rows)
{
    DiskMesh disk;
    auto index = [columns](int x, int y) { return uint32_t(y * (columns + 1) + x); };
    for (int y = 0; y <= rows; ++y)
        for (int x = 0; x <= columns; ++x) {
            const double a = 2.0 * std::numbers::pi * x / columns;
            disk.mesh.positions.push_back({std::cos(a), std::sin(a), 2.0 * y / rows});
            disk.originalVertex.push_back(uint32_t(y * columns + x % columns));
        }
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < columns; ++x) {
            const uint32_t a = index(x, y), b = index(x + 1, y), c = index(x + 1, y + 1), d = index(x, y + 1);
            disk.mesh.triangles.push_back({a, b, c});
            disk.mesh.triangles.push_back({a, c, d});
        }
    for (int x = 0; x < columns; ++x) disk.boundaryLoop.push_back(index(x, 0));
    for (int y = 0; y < rows; ++y) disk.boundaryLoop.push_back(index(columns, y));
    for (int x = columns; x > 0; --x) disk.boundaryLoop.push_back(index(x, rows));
    for (int y = rows; y > 0; --y) disk.boundaryLoop.push_back(index(0, y));
    return disk;
}

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

TEST(DetailDensity, StrengthZeroIsTheAreaMeasureExactly)
{
    const DiskMesh disk = ngi::test::spikeDisk(10);
    const std::vector<double> nu = ngi::detailDensityTargets(disk, 0.0);
    std::vector<double> area = ngi::vertexAreas(disk.mesh);
    const double total = sum(area);
    ASSERT_EQ(nu.size(), area.size());
    for (size_t v = 0; v < nu.size(); ++v)
        EXPECT_EQ(nu[v], area[v] / total) << v;  // bit for bit: the paper's map unchanged
}

TEST(DetailDensity, AFlatSurfaceKeepsTheAreaMeasureAtAnyStrength)
{
    const DiskMesh disk = ngi::test::planePatch(12, 0.3);
    const std::vector<double> area = ngi::detailDensityTargets(disk, 0.0), nu = ngi::detailDensityTargets(disk, 5.0);
    for (size_t v = 0; v < nu.size(); ++v) EXPECT_NEAR(nu[v], area[v], 1e-15) << v;
}

TEST(DetailDensity, TheSpikeGetsMoreThanItsAreaAndTheCapBoundsTheRatio)
{
    // A flat disk with a Gaussian spike at (0.2, 0.1), width 0.12: vertices near the spike bend,
    // those far away are flat. Per unit area the spike's share grows with S; the ratio of the
    // densest to the sparsest vertex is at most 1 + S * kMaxDetailRatio.
    const DiskMesh disk = ngi::test::spikeDisk(14);
    const double s = 3.0;
    const std::vector<double> area = ngi::detailDensityTargets(disk, 0.0), nu = ngi::detailDensityTargets(disk, s);
    EXPECT_NEAR(sum(nu), 1.0, 1e-12);
    double nearShare = 0.0, nearArea = 0.0, lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (size_t v = 0; v < nu.size(); ++v) {
        ASSERT_GT(nu[v], 0.0) << v;
        const glm::dvec3 p = disk.mesh.positions[v];
        if (std::hypot(p.x - 0.2, p.y - 0.1) < 0.2) nearShare += nu[v], nearArea += area[v];
        lo = std::min(lo, nu[v] / area[v]);
        hi = std::max(hi, nu[v] / area[v]);
    }
    EXPECT_GT(nearShare, 1.5 * nearArea) << "the spike's share " << nearShare << " vs its area " << nearArea;
    EXPECT_LE(hi / lo, 1.0 + s * ngi::kMaxDetailRatio + 1e-9);
    EXPECT_GT(hi / lo, 2.0);
}

TEST(DetailDensity, TheCutSeamDoesNotReadAsACrease)
{
    // A uniform tube: every column is alike, so the seam column (0, and its copy) gets the
    // density of a column opposite it. Without the join (no originalVertex) the seam's edges
    // are border edges with no dihedral and its density would fall below the rest.
    const int columns = 16, rows = 6;
    DiskMesh disk = cutTube(columns, rows);
    const auto ratio = [&](const std::vector<double>& nu, const std::vector<double>& area, int x, int y) {
        const size_t v = size_t(y) * (columns + 1) + size_t(x);
        return nu[v] / area[v];
    };
    const std::vector<double> area = ngi::detailDensityTargets(disk, 0.0), nu = ngi::detailDensityTargets(disk, 2.0);
    for (int y = 0; y <= rows; ++y) {
        EXPECT_NEAR(ratio(nu, area, 0, y), ratio(nu, area, columns / 2, y), 1e-9) << "row " << y;
        EXPECT_NEAR(ratio(nu, area, columns, y), ratio(nu, area, columns / 2, y), 1e-9) << "row " << y;
    }
    disk.originalVertex.clear();
    const std::vector<double> split = ngi::detailDensityTargets(disk, 2.0);
    EXPECT_LT(ratio(split, area, 0, rows / 2), 0.95 * ratio(split, area, columns / 2, rows / 2));
}

TEST(DetailDensity, BadStrengthsAreErrors)
{
    const DiskMesh disk = ngi::test::planePatch(4);
    EXPECT_THROW(ngi::detailDensityTargets(disk, -1.0), ngi::Error);
    EXPECT_THROW(ngi::detailDensityTargets(disk, std::numeric_limits<double>::quiet_NaN()), ngi::Error);
    EXPECT_THROW(ngi::detailDensityTargets(disk, std::numeric_limits<double>::infinity()), ngi::Error);
}

TEST(DetailDensity, TheOptimalTransportMapGivesTheSpikeMoreOfTheSquare)
{
    // Through parameterizeToSquare: the uv area of the triangles near the spike grows by more
    // than a third at S = 3 against the area-preserving map, and the map stays bijective.
    const DiskMesh disk = ngi::test::spikeDisk(14);
    auto spikeUvArea = [&](double s) {
        ngi::ParameterizeOptions options;
        options.detailDensity = s;
        const ngi::SquareMap map = ngi::parameterizeToSquare(disk, options);
        EXPECT_EQ(map.report.flippedTriangles, 0u) << "S " << s;
        double a = 0.0;
        for (const glm::uvec3& t : disk.mesh.triangles) {
            const glm::dvec3 c =
                (disk.mesh.positions[t[0]] + disk.mesh.positions[t[1]] + disk.mesh.positions[t[2]]) / 3.0;
            if (std::hypot(c.x - 0.2, c.y - 0.1) >= 0.2) continue;
            const glm::dvec2 e1 = map.uv[t[1]] - map.uv[t[0]], e2 = map.uv[t[2]] - map.uv[t[0]];
            a += 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x);
        }
        return a;
    };
    const double area = spikeUvArea(0.0), detail = spikeUvArea(3.0);
    EXPECT_GT(detail, 1.33 * area) << "uv area near the spike: area measure " << area << ", S 3 " << detail;
}

}  // namespace
