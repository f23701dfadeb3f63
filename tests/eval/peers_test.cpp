// The peers of docs/DESIGN.md "Metrics": meshoptimizer simplification (QSlim-style), Draco bytes
// (14-bit positions), the equal-bytes search, and Loop / modified-Butterfly subdivision.
#include "ngi/error.h"
#include "ngi/eval/draco_codec.h"
#include "ngi/eval/equal_bytes.h"
#include "ngi/eval/simplify.h"
#include "ngi/eval/subdivision.h"
#include "ngi/eval/surface_distance.h"
#include "ngi/mesh/procedural_meshes.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

namespace {

using ngi::TriangleMesh;
namespace t = ngi::test;

ngi::SurfaceDistanceOptions fewSamples(uint32_t count = 20000)
{
    ngi::SurfaceDistanceOptions o;
    o.sampleCount = count;
    return o;
}

// Each undirected edge -> the number of triangles using it.
std::map<std::pair<uint32_t, uint32_t>, int> edgeUse(const TriangleMesh& m)
{
    std::map<std::pair<uint32_t, uint32_t>, int> use;
    for (const glm::uvec3& tri : m.triangles)
        for (int k = 0; k < 3; ++k) ++use[std::minmax(tri[k], tri[(k + 1) % 3])];
    return use;
}

bool isClosedManifold(const TriangleMesh& m)
{
    for (const auto& [edge, count] : edgeUse(m))
        if (count != 2) return false;
    return true;
}

double signedVolume(const TriangleMesh& m)
{
    double v = 0.0;
    for (const glm::uvec3& tri : m.triangles)
        v += glm::dot(m.positions[tri.x], glm::cross(m.positions[tri.y], m.positions[tri.z])) / 6.0;
    return v;
}

auto positionSet(const TriangleMesh& m)
{
    std::set<std::tuple<double, double, double>> s;
    for (const glm::dvec3& p : m.positions) s.insert({p.x, p.y, p.z});
    return s;
}

TEST(SimplifyMesh, reachesTheTargetKeepingTopologyOrientationAndInputVertices)
{
    const TriangleMesh sphere = t::octaSphere(32);  // 8192 triangles
    ngi::SimplifyOptions o;
    o.targetTriangleCount = 1000;
    const ngi::SimplifyResult r = ngi::simplifyMesh(sphere, o);
    EXPECT_TRUE(r.reachedTarget);
    EXPECT_LE(r.mesh.triangles.size(), 1000u);
    EXPECT_GE(r.mesh.triangles.size(), 900u);
    EXPECT_TRUE(isClosedManifold(r.mesh));
    EXPECT_EQ(r.mesh.positions.size(), r.mesh.triangles.size() / 2 + 2);  // genus 0, compact
    EXPECT_GT(signedVolume(r.mesh), 0.0);
    const auto input = positionSet(sphere);
    for (const glm::dvec3& p : r.mesh.positions)
        ASSERT_TRUE(input.count({p.x, p.y, p.z})) << "a vertex that is not an input vertex";
    // Vertices stay on the unit sphere: HD is a chordal sag, well under 1% of the bbox.
    const auto d = ngi::surfaceDistance(sphere, r.mesh, fewSamples());
    EXPECT_LT(d.hausdorff, 0.01);
    EXPECT_GT(r.relativeError, 0.0);
}

TEST(SimplifyMesh, stopsAtTheErrorLimitAndCanLockTheBorder)
{
    const TriangleMesh bumpy =
        t::heightField(24, true, [](double x, double y) { return 0.2 * std::sin(6.0 * x) * std::sin(5.0 * y); });
    ngi::SimplifyOptions o;
    o.targetTriangleCount = 2;
    o.maxRelativeError = 0.001f;
    const auto limited = ngi::simplifyMesh(bumpy, o);
    EXPECT_FALSE(limited.reachedTarget);
    EXPECT_LE(limited.relativeError, 0.001 + 1e-7);

    // lockBorder: every boundary vertex of the patch survives.
    o.maxRelativeError = 1.0f;
    o.lockBorder = true;
    const auto locked = ngi::simplifyMesh(bumpy, o);
    const auto kept = positionSet(locked.mesh);
    int border = 0;
    for (const glm::dvec3& p : bumpy.positions)
        if (p.x == 0.0 || p.x == 1.0 || p.y == 0.0 || p.y == 1.0) {
            ++border;
            EXPECT_TRUE(kept.count({p.x, p.y, p.z}));
        }
    EXPECT_EQ(border, 4 * 24);
    EXPECT_LT(locked.mesh.triangles.size(), bumpy.triangles.size() / 2);
}

// 14-bit quantization over the bbox's longest side L moves each coordinate by at most
// L / (2^14 - 1) / 2: in the DESIGN frame (L = 1) HD <= sqrt(3) / 2 / 16383 = 5.3e-5.
TEST(DracoCodec, roundTripIsWithinTheQuantizationBound)
{
    const TriangleMesh sphere = t::octaSphere(24);
    const std::vector<uint8_t> bytes = ngi::encodeDraco(sphere);
    const TriangleMesh decoded = ngi::decodeDraco(bytes);
    EXPECT_EQ(decoded.triangles.size(), sphere.triangles.size());
    EXPECT_EQ(decoded.positions.size(), sphere.positions.size());
    EXPECT_GT(signedVolume(decoded), 0.0);  // orientation kept
    const auto d = ngi::surfaceDistance(sphere, decoded, fewSamples());
    EXPECT_LE(d.hausdorff, 1.01 * std::sqrt(3.0) / 2.0 / 16383.0);
    EXPECT_GT(d.hausdorff, 0.0);
    // Fewer bits: fewer bytes, a larger error.
    ngi::DracoOptions coarse;
    coarse.positionQuantizationBits = 8;
    const std::vector<uint8_t> small = ngi::encodeDraco(sphere, coarse);
    EXPECT_LT(small.size(), bytes.size());
    EXPECT_GT(ngi::surfaceDistance(sphere, ngi::decodeDraco(small), fewSamples()).hausdorff, d.hausdorff);
    // Deterministic.
    EXPECT_EQ(ngi::encodeDraco(sphere), bytes);
}

TEST(DracoCodec, skipsUnusedVerticesAndDegenerateTriangles)
{
    TriangleMesh m = t::octaSphere(6);
    const size_t proper = m.triangles.size();
    m.positions.push_back({9.0, 9.0, 9.0});
    m.triangles.push_back({0, 0, 1});
    const TriangleMesh decoded = ngi::decodeDraco(ngi::encodeDraco(m));
    EXPECT_EQ(decoded.triangles.size(), proper);
    EXPECT_EQ(decoded.positions.size(), m.positions.size() - 1);
}

TEST(DracoCodec, rejectsBadBytesAndOptions)
{
    const std::vector<uint8_t> bytes = ngi::encodeDraco(t::octaSphere(3));
    EXPECT_THROW(ngi::decodeDraco(std::vector<uint8_t>{}), ngi::Error);
    EXPECT_THROW(ngi::decodeDraco(std::vector<uint8_t>(64, 0x5a)), ngi::Error);
    // Every truncation: an ngi::Error or (rarely) a mesh, never a crash.
    for (size_t n = 0; n < bytes.size(); ++n) {
        try {
            ngi::decodeDraco(std::span(bytes.data(), n), "truncated");
        } catch (const ngi::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("truncated: ", 0), 0u) << e.what();
        }
    }
    ngi::DracoOptions o;
    o.positionQuantizationBits = 0;
    EXPECT_THROW(ngi::encodeDraco(t::octaSphere(3), o), ngi::Error);
    o = {};
    o.compressionLevel = 11;
    EXPECT_THROW(ngi::encodeDraco(t::octaSphere(3), o), ngi::Error);
    EXPECT_THROW(ngi::encodeDraco(TriangleMesh{}), ngi::Error);
}

TEST(SimplifyToByteBudget, findsTheLargestMeshThatFits)
{
    const TriangleMesh sphere = t::octaSphere(40);  // 12800 triangles
    const size_t full = ngi::encodeDraco(sphere).size();
    const size_t budget = full / 5;
    const ngi::EqualBytesResult r = ngi::simplifyToByteBudget(sphere, budget);
    EXPECT_TRUE(r.budgetMet);
    EXPECT_LE(r.dracoBytes, budget);
    EXPECT_EQ(ngi::encodeDraco(r.simplified).size(), r.dracoBytes);
    EXPECT_EQ(r.decoded.triangles.size(), r.simplified.triangles.size());
    EXPECT_LT(r.simplified.triangles.size(), sphere.triangles.size());
    EXPECT_LE(r.evaluations, 2u + 14u);  // ends + bisection over 12800 targets
    // The bisection's neighbour one triangle up no longer fits.
    ngi::SimplifyOptions up;
    up.targetTriangleCount = r.targetTriangleCount + 1;
    EXPECT_GT(ngi::encodeDraco(ngi::simplifyMesh(sphere, up).mesh).size(), budget);
    // The budget is used, not wasted (Draco grows smoothly with the triangle count).
    EXPECT_GT(double(r.dracoBytes), 0.9 * double(budget));
}

TEST(SimplifyToByteBudget, wholeMeshWhenItFitsAndFlagsImpossibleBudgets)
{
    const TriangleMesh sphere = t::octaSphere(8);
    const size_t full = ngi::encodeDraco(sphere).size();
    const auto all = ngi::simplifyToByteBudget(sphere, full);
    EXPECT_TRUE(all.budgetMet);
    EXPECT_EQ(all.simplified.triangles.size(), sphere.triangles.size());
    EXPECT_EQ(all.evaluations, 1u);
    const auto none = ngi::simplifyToByteBudget(sphere, 8);
    EXPECT_FALSE(none.budgetMet);
    EXPECT_GT(none.dracoBytes, 8u);
    EXPECT_FALSE(none.decoded.triangles.empty());
}

// On a closed genus-1 surface a tiny target collapses everything (the knot1 case): such
// targets never meet a budget, and the search still finds the largest mesh that fits.
TEST(SimplifyToByteBudget, handlesTargetsThatCollapseEverything)
{
    const TriangleMesh torus = ngi::makeTorus(48, 24, 1.0, 0.3);
    ngi::SimplifyOptions tiny;
    tiny.targetTriangleCount = 4;
    const auto collapsed = ngi::simplifyMesh(torus, tiny);
    SCOPED_TRACE("triangles at target 4: " + std::to_string(collapsed.mesh.triangles.size()));
    const size_t budget = ngi::encodeDraco(torus).size() / 6;
    const auto r = ngi::simplifyToByteBudget(torus, budget);
    EXPECT_TRUE(r.budgetMet);
    EXPECT_LE(r.dracoBytes, budget);
    EXPECT_GT(r.simplified.triangles.size(), 0u);
    const auto none = ngi::simplifyToByteBudget(torus, 20);
    EXPECT_FALSE(none.budgetMet);
    EXPECT_GT(none.decoded.triangles.size(), 0u);
}

TEST(SubdivideMesh, quadruplesTrianglesAndFollowsEachSchemesRule)
{
    const TriangleMesh coarse = t::octaSphere(4);  // 128 triangles, 66 vertices, 192 edges
    for (auto scheme : {ngi::SubdivisionScheme::loop, ngi::SubdivisionScheme::modifiedButterfly}) {
        const auto r = ngi::subdivideMesh(coarse, {scheme, 2});
        EXPECT_EQ(r.mesh.triangles.size(), 128u * 16u);
        EXPECT_EQ(r.mesh.positions.size(), r.mesh.triangles.size() / 2 + 2);
        EXPECT_TRUE(isClosedManifold(r.mesh));
        EXPECT_GT(signedVolume(r.mesh), 0.0);
        EXPECT_EQ(r.detachedTriangles, 0u);
    }
    // Butterfly interpolates: the input vertices are still there, exactly.
    const auto butterfly = ngi::subdivideMesh(coarse, {ngi::SubdivisionScheme::modifiedButterfly, 1});
    const auto kept = positionSet(butterfly.mesh);
    for (const glm::dvec3& p : coarse.positions) EXPECT_TRUE(kept.count({p.x, p.y, p.z}));
    // Loop approximates and shrinks a convex polyhedron: every vertex moves inside the sphere.
    const auto loop = ngi::subdivideMesh(coarse, {ngi::SubdivisionScheme::loop, 1});
    for (const glm::dvec3& p : loop.mesh.positions) EXPECT_LT(glm::length(p), 1.0);
    // On a sphere, butterfly's new vertices get closer to it: CD to a fine sphere drops.
    const TriangleMesh fine = t::octaSphere(48);
    const double before = ngi::chamferDistance(fine, coarse, fewSamples());
    const double after = ngi::chamferDistance(
        fine, ngi::subdivideMesh(coarse, {ngi::SubdivisionScheme::modifiedButterfly, 2}).mesh, fewSamples());
    EXPECT_LT(after, 0.2 * before);
}

TEST(SubdivideMesh, detachesNonManifoldTrianglesAndPrintsNothing)
{
    TriangleMesh fin;  // three triangles on one edge
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
    fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    testing::internal::CaptureStderr();
    testing::internal::CaptureStdout();
    const auto r = ngi::subdivideMesh(fin, {ngi::SubdivisionScheme::loop, 1});
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
    EXPECT_EQ(r.detachedTriangles, 1u);
    EXPECT_EQ(r.mesh.triangles.size(), 12u);
    EXPECT_THROW(ngi::subdivideMesh(fin, {ngi::SubdivisionScheme::loop, 7}), ngi::Error);
    EXPECT_THROW(ngi::subdivideMesh(TriangleMesh{}, {}), ngi::Error);
}

}  // namespace
