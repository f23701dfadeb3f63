// ngi tests: every square map is bijective, Ricci flow converges and is conformal on a plane,
// bad input throws ngi::Error.
#include "disk_meshes.h"

#include "ngi/error.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/distortion.h"
#include "ngi/param/parameterize.h"
#include "ngi/param/ricci_flow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace ngi {
namespace {

struct NamedDisk {
    const char* name;
    DiskMesh disk;
};

std::vector<NamedDisk> testDisks()
{
    return {{"planePatch", test::planePatch(16)},
            {"flatDisk", test::flatDisk(10)},
            {"hemisphere", test::sphericalCap(10, 0.5 * std::numbers::pi)},
            {"bumpy", test::bumpyHeightField(12)},
            {"spike", test::spikeDisk(14)}};
}

// Asserts the map is a bijection onto the square: no flipped triangle, all uv in [0,1]^2,
// corners on the square's corners, every boundary vertex on the border, in order.
void expectBijectiveOnSquare(const DiskMesh& disk, const SquareMap& map, const std::string& what)
{
    SCOPED_TRACE(what);
    ASSERT_EQ(map.uv.size(), disk.mesh.positions.size());
    EXPECT_EQ(map.report.flippedTriangles, 0u);
    size_t flipped = 0;
    for (const glm::uvec3& t : disk.mesh.triangles) {
        const glm::dvec2 a = map.uv[t[1]] - map.uv[t[0]], b = map.uv[t[2]] - map.uv[t[0]];
        if (a.x * b.y - a.y * b.x <= 0.0) ++flipped;
    }
    EXPECT_EQ(flipped, 0u);
    for (const glm::dvec2& x : map.uv) {
        ASSERT_GE(x.x, 0.0);
        ASSERT_LE(x.x, 1.0);
        ASSERT_GE(x.y, 0.0);
        ASSERT_LE(x.y, 1.0);
    }
    const glm::dvec2 corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int c = 0; c < 4; ++c) EXPECT_EQ(map.uv[map.corners[c]], corner[c]) << "corner " << c;
    // Boundary: on the border, and the loop turns once around the square (signed area = 1).
    double signedArea = 0.0;
    const auto& loop = disk.boundaryLoop;
    for (size_t k = 0; k < loop.size(); ++k) {
        const glm::dvec2 u = map.uv[loop[k]], w = map.uv[loop[(k + 1) % loop.size()]];
        const bool onBorder = u.x == 0.0 || u.x == 1.0 || u.y == 0.0 || u.y == 1.0;
        EXPECT_TRUE(onBorder) << "boundary vertex " << loop[k] << " at (" << u.x << ", " << u.y << ")";
        signedArea += 0.5 * (u.x * w.y - u.y * w.x);
        // Consecutive boundary vertices share a side (or one of them is a corner).
        const bool sameSide = (u.x == w.x && (u.x == 0.0 || u.x == 1.0)) || (u.y == w.y && (u.y == 0.0 || u.y == 1.0));
        EXPECT_TRUE(sameSide) << "boundary edge " << k << " cuts through the square";
    }
    EXPECT_NEAR(signedArea, 1.0, 1e-9);
    // The uv triangles tile the square exactly once.
    double total = 0.0;
    for (const glm::uvec3& t : disk.mesh.triangles) {
        const glm::dvec2 a = map.uv[t[1]] - map.uv[t[0]], b = map.uv[t[2]] - map.uv[t[0]];
        total += 0.5 * (a.x * b.y - a.y * b.x);
    }
    EXPECT_NEAR(total, 1.0, 1e-9);
}

class EveryMethod : public ::testing::TestWithParam<ParameterizationMethod> {};

TEST_P(EveryMethod, mapsEveryTestDiskBijectivelyOntoTheSquare)
{
    for (const NamedDisk& d : testDisks()) {
        ParameterizeOptions options;
        options.method = GetParam();
        const SquareMap map = parameterizeToSquare(d.disk, options);
        expectBijectiveOnSquare(d.disk, map, std::string(parameterizationName(GetParam())) + " on " + d.name);
        EXPECT_TRUE(std::isfinite(map.report.areaDistortionMax));
        EXPECT_GE(map.report.angleDistortionMax, map.report.angleDistortionMean);
    }
}

INSTANTIATE_TEST_SUITE_P(Methods, EveryMethod,
                         ::testing::Values(ParameterizationMethod::Tutte, ParameterizationMethod::Harmonic,
                                           ParameterizationMethod::RicciConformal, ParameterizationMethod::Authalic,
                                           ParameterizationMethod::OptimalTransport),
                         [](const auto& info) { return std::string(parameterizationName(info.param)); });

TEST(RicciFlow, convergesToTheToleranceInFewNewtonIterations)
{
    for (const NamedDisk& d : testDisks()) {
        SCOPED_TRACE(d.name);
        const DiskTopology topology = analyzeDisk(d.disk);
        RicciFlowOptions options;
        options.tolerance = 1e-10;
        const RicciFlowResult flow = ricciFlowToSquare(d.disk, topology, chooseCornerPositions(d.disk), options);
        EXPECT_LT(flow.residual, 1e-10);
        EXPECT_LE(flow.iterations, 12);
    }
}

TEST(RicciFlow, squarePlanePatchIsAlreadyFlatAndMapsToItself)
{
    // A planar square with its corners on the loop's quarter points is its own conformal map.
    const DiskMesh disk = test::planePatch(12, 0.3, 2.0);
    ParameterizeOptions options;
    options.method = ParameterizationMethod::RicciConformal;
    const SquareMap map = parameterizeToSquare(disk, options);
    EXPECT_EQ(map.report.ricciIterations, 0);
    for (size_t v = 0; v < disk.mesh.positions.size(); ++v) {
        EXPECT_NEAR(map.uv[v].x, disk.mesh.positions[v].x / 2.0, 1e-9);
        EXPECT_NEAR(map.uv[v].y, disk.mesh.positions[v].y / 2.0, 1e-9);
    }
    EXPECT_LT(map.report.angleDistortionMax, 1e-8);
}

TEST(RicciFlow, roundPlaneDiskMapsNearlyConformally)
{
    // Disk -> square: a genuine conformal map (Schwarz-Christoffel); discrete conformal maps
    // preserve angles up to the discretization. Harmonic (cotangent) is the reference.
    const DiskMesh disk = test::flatDisk(16);
    ParameterizeOptions options;
    options.method = ParameterizationMethod::RicciConformal;
    const SquareMap ricci = parameterizeToSquare(disk, options);
    EXPECT_NEAR(ricci.report.rectangleAspect, 1.0, 5e-3);  // symmetric corners: nearly a square
    EXPECT_LT(ricci.report.angleDistortionMean, 0.03);
    options.method = ParameterizationMethod::Tutte;
    const SquareMap tutte = parameterizeToSquare(disk, options);
    EXPECT_LT(ricci.report.angleDistortionMean, 0.5 * tutte.report.angleDistortionMean);
}

TEST(Parameterize, parsesMethodNamesAndRejectsUnknownOnes)
{
    for (const char* name : {"tutte", "harmonic", "ricci", "authalic", "ot"})
        EXPECT_STREQ(parameterizationName(parseParameterizationMethod(name)), name);
    try {
        parseParameterizationMethod("lscm");
        FAIL() << "no exception";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("lscm"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("authalic"), std::string::npos);
    }
}

TEST(Parameterize, rejectsMeshesThatAreNotDisks)
{
    // Closed: a tetrahedron has no boundary.
    DiskMesh tetrahedron;
    tetrahedron.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetrahedron.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    EXPECT_THROW(parameterizeToSquare(tetrahedron), Error);

    // Annulus: two boundary loops (the flat disk with its centre fan removed).
    DiskMesh annulus = test::flatDisk(5);
    annulus.mesh.triangles.erase(annulus.mesh.triangles.begin(), annulus.mesh.triangles.begin() + 6);
    annulus.mesh.positions[0] = {5, 5, 5};  // isolated now, and also rejected as such
    EXPECT_THROW(parameterizeToSquare(annulus), Error);

    // Boundary loop given clockwise.
    DiskMesh reversed = test::planePatch(4);
    std::reverse(reversed.boundaryLoop.begin(), reversed.boundaryLoop.end());
    EXPECT_THROW(parameterizeToSquare(reversed), Error);

    // Two triangles sharing only a vertex (non-manifold bow tie), and a mesh with an empty loop.
    DiskMesh empty;
    EXPECT_THROW(parameterizeToSquare(empty), Error);
}

TEST(Parameterize, rejectsNaNAndInfPositions)
{
    DiskMesh disk = test::planePatch(6);
    disk.mesh.positions[10].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(parameterizeToSquare(disk), Error);
    disk.mesh.positions[10].y = std::numeric_limits<double>::infinity();
    EXPECT_THROW(parameterizeToSquare(disk), Error);
}

TEST(Distortion, isZeroForAnIsometryAndCountsFlips)
{
    const DiskMesh disk = test::planePatch(8, 0.3, 1.0);
    std::vector<glm::dvec2> uv;
    for (const glm::dvec3& p : disk.mesh.positions) uv.emplace_back(p.x, p.y);
    MapDistortion d = measureDistortion(disk.mesh, uv);
    EXPECT_LT(d.areaMax, 1e-12);
    EXPECT_LT(d.angleMax, 1e-12);
    EXPECT_EQ(d.flipped, 0u);
    for (glm::dvec2& x : uv) x.x = -x.x;  // mirror: every triangle flips
    d = measureDistortion(disk.mesh, uv);
    EXPECT_EQ(d.flipped, disk.mesh.triangles.size());
}

}  // namespace
}  // namespace ngi
