// ngi tests: closed surfaces of genus >= 1 cut by cutToDisk map bijectively onto the square,
// with the cut's corner hints (polygon-schema corners) as the square's corners.
#include "ngi/mesh/cut.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/parameterize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace ngi {
namespace {

void expectBijective(const DiskMesh& disk, const SquareMap& map)
{
    EXPECT_EQ(map.report.flippedTriangles, 0u);
    for (const glm::dvec2& x : map.uv) {
        ASSERT_TRUE(x.x >= 0.0 && x.x <= 1.0 && x.y >= 0.0 && x.y <= 1.0);
    }
    double total = 0.0;
    for (const glm::uvec3& t : disk.mesh.triangles) {
        const glm::dvec2 a = map.uv[t[1]] - map.uv[t[0]], b = map.uv[t[2]] - map.uv[t[0]];
        EXPECT_GT(a.x * b.y - a.y * b.x, 0.0);
        total += 0.5 * (a.x * b.y - a.y * b.x);
    }
    EXPECT_NEAR(total, 1.0, 1e-9);
}

TEST(CornerHints, cutJunctionCopiesBecomeTheSquareCorners)
{
    for (const TriangleMesh& mesh : {makeTorus(24, 12), makeGenusSurface(2, 2)}) {
        const DiskMesh disk = cutToDisk(mesh).disk;
        ASSERT_EQ(disk.cornerHints.size(), 4u);
        const std::array<size_t, 4> corners = chooseCornerPositions(disk);
        for (int c = 0; c < 4; ++c) {
            EXPECT_TRUE(std::find(disk.cornerHints.begin(), disk.cornerHints.end(), disk.boundaryLoop[corners[c]]) !=
                        disk.cornerHints.end());
            if (c > 0) {
                EXPECT_LT(corners[c - 1], corners[c]);
            }
        }
    }
}

TEST(CornerHints, badHintsFallBackToArcLengthCorners)
{
    DiskMesh disk = cutToDisk(makeTorus(24, 12)).disk;
    DiskMesh noHints = disk;
    noHints.cornerHints.clear();
    disk.cornerHints = {disk.boundaryLoop[0], disk.boundaryLoop[0], disk.boundaryLoop[1], disk.boundaryLoop[2]};
    EXPECT_EQ(chooseCornerPositions(disk), chooseCornerPositions(noHints));
}

class GenusSurfaces : public ::testing::TestWithParam<ParameterizationMethod> {};

TEST_P(GenusSurfaces, torusAndDoubleTorusMapBijectively)
{
    for (const TriangleMesh& mesh : {makeTorus(32, 16), makeGenusSurface(2, 3)}) {
        const DiskMesh disk = cutToDisk(mesh).disk;
        ParameterizeOptions options;
        options.method = GetParam();
        const SquareMap map = parameterizeToSquare(disk, options);
        expectBijective(disk, map);
        if (GetParam() == ParameterizationMethod::OptimalTransport) {
            EXPECT_LT(map.report.otResidual, 1e-3);
            // Small smooth surfaces: the conformal start is well spread, OT starts from it.
            EXPECT_EQ(map.report.otStart, "ricci");
            EXPECT_LT(map.report.otStartAreaDistortionMax, 20.0);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Methods, GenusSurfaces,
                         ::testing::Values(ParameterizationMethod::Tutte, ParameterizationMethod::Harmonic,
                                           ParameterizationMethod::RicciConformal, ParameterizationMethod::Authalic,
                                           ParameterizationMethod::OptimalTransport),
                         [](const auto& info) { return std::string(parameterizationName(info.param)); });

}  // namespace
}  // namespace ngi
