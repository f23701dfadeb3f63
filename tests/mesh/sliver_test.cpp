// Parts of (near) zero area: the cleaning stage drops them beside a real surface and refuses a
// mesh made only of them, and the remesh bounds the vertices it asks for on a sliver's outline
// (a length from the area alone would split a 1000 x 1e-7 sliver into billions of vertices).
#include "ngi/error.h"
#include "ngi/mesh/clean.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <gtest/gtest.h>

#include <string>

namespace {

// One triangle `length` long and `width` wide, from `at`.
ngi::TriangleMesh sliver(double length, double width, glm::dvec3 at = glm::dvec3(0.0))
{
    ngi::TriangleMesh mesh;
    mesh.positions = {at, at + glm::dvec3(length, 0.0, 0.0), at + glm::dvec3(0.5 * length, width, 0.0)};
    mesh.triangles = {{0, 1, 2}};
    return mesh;
}

void append(ngi::TriangleMesh& mesh, const ngi::TriangleMesh& part)
{
    const uint32_t base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
    for (const glm::uvec3& t : part.triangles) mesh.triangles.push_back(t + glm::uvec3(base));
}

std::string cleanError(const ngi::TriangleMesh& mesh, const std::string& name)
{
    try {
        ngi::cleanMesh(mesh, {.sourceName = name});
    } catch (const ngi::Error& e) {
        return e.what();
    }
    return "";
}

TEST(NearZeroArea, ALoneSliverIsRefusedNamingTheFile)
{
    for (const auto& [length, width] : {std::pair{1000.0, 1e-7}, std::pair{1.0, 1e-6}}) {
        const std::string message = cleanError(sliver(length, width), "sliver.obj");
        EXPECT_EQ(message.rfind("sliver.obj: ", 0), 0u) << message;
        EXPECT_NE(message.find("(near) zero area"), std::string::npos) << message;
    }
}

TEST(NearZeroArea, ASliverBesideASphereIsDroppedWithAWarning)
{
    ngi::TriangleMesh mesh = ngi::makeSphere(2);
    const size_t sphereTriangles = mesh.triangles.size();
    append(mesh, sliver(1000.0, 1e-7, {3.0, 0.0, 0.0}));
    const ngi::CleanResult result = ngi::cleanMesh(mesh, {.sourceName = "two.obj"});
    EXPECT_EQ(result.mesh.triangles.size(), sphereTriangles);
    EXPECT_EQ(result.report.components, 1u);
    EXPECT_EQ(result.report.droppedZeroAreaComponents, 1u);
    EXPECT_EQ(result.report.droppedComponentTriangles, 1u);
    EXPECT_GT(result.report.keptAreaFraction, 0.9999);  // 5e-5 of the sphere's 12.5
    ASSERT_EQ(result.report.warnings.size(), 1u);
    EXPECT_EQ(result.report.warnings[0].rfind("two.obj: dropped 1 of 2 components for (near) zero area", 0), 0u)
        << result.report.warnings[0];
}

TEST(NearZeroArea, ThinButRealPartsAreKept)
{
    // A strip 1000 times longer than wide (area / diagonal^2 = 5e-4) and the option turned off.
    EXPECT_EQ(ngi::cleanMesh(sliver(1.0, 1e-3)).report.droppedZeroAreaComponents, 0u);
    const ngi::CleanResult kept = ngi::cleanMesh(sliver(1000.0, 1e-7), {.nearZeroAreaRatio = 0.0});
    EXPECT_EQ(kept.mesh.triangles.size(), 1u);
}

TEST(RemeshIsotropic, ASliverIsAskedForAtMostTheTargetCountOnItsOutline)
{
    const ngi::TriangleMesh mesh = sliver(1000.0, 1e-3);
    const size_t target = 400;
    const ngi::RemeshResult result = ngi::remeshIsotropic(mesh, {.targetVertexCount = target});
    // The area alone asks for an edge of about 0.02: 100,000 vertices on the outline.
    EXPECT_LT(result.report.vertexCountEdgeLength, 0.05);
    EXPECT_GE(result.report.targetEdgeLength, 2000.0 / double(target));  // perimeter / target
    EXPECT_LT(result.report.outputVertices, 3 * target);
}

TEST(RemeshIsotropic, AFatSurfaceKeepsTheLengthItsAreaGives)
{
    const ngi::RemeshResult result = ngi::remeshIsotropic(ngi::makeSphere(2), {.targetVertexCount = 1500});
    EXPECT_EQ(result.report.targetEdgeLength, result.report.vertexCountEdgeLength);
}

}  // namespace
