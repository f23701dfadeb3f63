// Stage 4 with cut augmentation (Gu, Gortler, Hoppe 2002, section 3.2): a protrusion the first
// cut leaves closed is cut through, which removes the exponential shrink of the conformal
// start, and OT from the augmented cut converges bijectively.
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"
#include "ngi/param/extremity_cut.h"
#include "ngi/param/parameterize.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

namespace ngi {
namespace {

// A sphere with three long spikes along +x, +y and +z: the first cut (shortest path between
// the two farthest vertices) runs through two spike tips and leaves the third spike closed.
// Measured: the first cut's conformal start shrinks by e^15.8, after one path by e^5.5.
TriangleMesh tripod(size_t vertices = 4000)
{
    TriangleMesh mesh = makeSphere(4);
    for (glm::dvec3& p : mesh.positions) {
        const glm::dvec3 n = glm::normalize(p);
        double r = 1.0;
        for (const glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)})
            r += 3.0 * std::exp(-(1.0 - glm::dot(n, axis)) / 0.01);
        p = n * r;
    }
    return remeshIsotropic(mesh, {.targetVertexCount = vertices}).mesh;
}

TEST(CutThroughExtremities, OpensTheSpikeTheFirstCutMissed)
{
    const TriangleMesh mesh = tripod();
    const ExtremityCutResult result = cutThroughExtremities(mesh);
    ASSERT_GE(result.rounds.size(), 2u);
    const double first = result.rounds.front().conformalShrink;
    EXPECT_GT(first, ExtremityCutOptions{}.maxConformalShrink);  // the closed spike is squeezed
    EXPECT_GE(result.cut.report.extremityPaths, 1u);
    EXPECT_LT(result.conformalShrink, first - 3.0);  // at least e^3 less
    // The third spike's tip (distance ~3.5 along one axis) is on the cut now.
    int tipsOnCut = 0;
    for (const glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}) {
        bool onCut = false;
        for (uint32_t v : result.cut.disk.boundaryLoop)
            onCut = onCut || glm::dot(result.cut.disk.mesh.positions[v], axis) > 2.5;
        tipsOnCut += onCut;
    }
    EXPECT_EQ(tipsOnCut, 3);
    // OT from the augmented cut: converged, bijective.
    const SquareMap map = parameterizeToSquare(result.cut.disk);
    EXPECT_LT(map.report.otResidual, 1e-3);
    EXPECT_EQ(map.report.flippedTriangles, 0u);
}

TEST(CutThroughExtremities, LeavesAWellShapedCutAlone)
{
    // A round sphere: the first cut's conformal start is mild, nothing is added.
    const ExtremityCutResult result = cutThroughExtremities(makeSphere(3));
    EXPECT_EQ(result.cut.report.extremityPaths, 0u);
    EXPECT_LT(result.conformalShrink, ExtremityCutOptions{}.maxConformalShrink);
}

TEST(CutThroughExtremities, KeepsTheShorterOfTwoGoodCutGraphsForHandles)
{
    const ExtremityCutResult result = cutThroughExtremities(makeTorus(32, 16));
    ASSERT_GE(result.rounds.size(), 2u);  // both cut graphs were measured
    // A smooth torus needs no extremity path: the two rounds are the two cut graphs, both mild.
    const ExtremityCutRound& a = result.rounds[0];
    const ExtremityCutRound& b = result.rounds[1];
    ASSERT_LE(std::max(a.conformalShrink, b.conformalShrink), ExtremityCutOptions{}.maxConformalShrink);
    ASSERT_GT(std::abs(a.cutLength - b.cutLength), 0.05 * std::min(a.cutLength, b.cutLength));  // a real choice
    EXPECT_NEAR(result.cut.report.cutLength, std::min(a.cutLength, b.cutLength), 1e-12);
}

// The two cut graphs are augmented side by side on 2 threads: the rounds, the chosen cut and
// the progress lines (the second graph's after the first's) are those of a 1-thread run.
TEST(CutThroughExtremities, TwoThreadsGiveTheSameSearchAsOne)
{
    const TriangleMesh mesh = makeTorus(32, 16);
    std::vector<std::string> lines[2];
    ExtremityCutResult results[2];
    for (unsigned threads : {1u, 2u}) {
        ExtremityCutOptions options;
        options.threads = threads;
        options.progress = [&, threads](const std::string& line) { lines[threads - 1].push_back(line); };
        results[threads - 1] = cutThroughExtremities(mesh, options);
    }
    ASSERT_GE(results[0].rounds.size(), 2u);  // both graphs ran
    ASSERT_EQ(results[1].rounds.size(), results[0].rounds.size());
    for (size_t r = 0; r < results[0].rounds.size(); ++r) {
        EXPECT_EQ(results[1].rounds[r].cutLength, results[0].rounds[r].cutLength) << "round " << r;
        EXPECT_EQ(results[1].rounds[r].conformalShrink, results[0].rounds[r].conformalShrink) << "round " << r;
    }
    EXPECT_EQ(results[1].cut.report.method, results[0].cut.report.method);
    EXPECT_EQ(results[1].cut.disk.boundaryLoop, results[0].cut.disk.boundaryLoop);
    ASSERT_EQ(lines[1].size(), results[0].rounds.size());  // one line per measured cut
    for (auto& run : lines)
        for (std::string& line : run)
            line = std::regex_replace(line, std::regex("[0-9.e+-]+ s\\b"), "T s");  // timings differ
    EXPECT_EQ(lines[1], lines[0]);
}

TEST(CutByPlan, MakesTheSearchedCutOnADenserRemesh)
{
    // The search on a coarse tripod opens the third spike; the plan makes the same cut on a
    // 2x denser remesh of the same surface: the same paths, all three tips on the cut, and a
    // conformal start as mild as the search's within e^2.
    const TriangleMesh coarse = tripod(3000);
    const TriangleMesh dense = tripod(6000);
    const ExtremityCutResult search = cutThroughExtremities(coarse);
    ASSERT_GE(search.plan.tips.size(), 1u);
    const ExtremityCutResult made = cutByPlan(dense, search.plan);
    EXPECT_EQ(made.rounds.size(), 1u);
    EXPECT_EQ(made.cut.report.extremityPaths, search.cut.report.extremityPaths);
    int tipsOnCut = 0;
    for (const glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}) {
        bool onCut = false;
        for (uint32_t v : made.cut.disk.boundaryLoop)
            onCut = onCut || glm::dot(made.cut.disk.mesh.positions[v], axis) > 2.5;
        tipsOnCut += onCut;
    }
    EXPECT_EQ(tipsOnCut, 3);
    ASSERT_FALSE(std::isnan(made.conformalShrink));
    EXPECT_LT(made.conformalShrink, search.conformalShrink + 2.0);
    EXPECT_TRUE(made.conformalStart.has_value());  // handed to the parameterization, not re-run
}

}  // namespace
}  // namespace ngi
