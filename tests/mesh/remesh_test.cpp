// Stage 3 isotropic remeshing keeps topology and reaches the requested density.
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

TEST(RemeshIsotropic, ReachesTargetDensityAndKeepsTopology)
{
    struct Case {
        const char* name;
        ngi::TriangleMesh mesh;
    };
    for (Case& c : std::vector<Case>{{"sphere", ngi::makeSphere(2)},
                                     {"torus", ngi::makeTorus(24, 10)},
                                     {"genus2", ngi::makeGenusSurface(2, 2)},
                                     {"cylinder", ngi::makeOpenCylinder(24, 6)}}) {
        ngi::MeshTopology before = ngi::analyzeTopology(c.mesh);
        ngi::RemeshResult result = ngi::remeshIsotropic(c.mesh, {.targetVertexCount = 1500});
        ngi::MeshTopology after = ngi::analyzeTopology(result.mesh);
        EXPECT_EQ(after.genus, before.genus) << c.name;
        EXPECT_EQ(after.boundaryLoops, before.boundaryLoops) << c.name;
        EXPECT_GT(result.report.outputVertices, 1000u) << c.name;
        EXPECT_LT(result.report.outputVertices, 2300u) << c.name;
        EXPECT_GT(result.report.minAngleDegrees, 15.0) << c.name;
    }
}

TEST(RemeshIsotropic, KeepsCreasesOfTheGenusSurface)
{
    // The slab's 90-degree edges are features: they must stay sharp, so every vertex stays on
    // the box surface (a coordinate at an integer lattice plane).
    ngi::RemeshResult result = ngi::remeshIsotropic(ngi::makeGenusSurface(1, 1), {.targetVertexCount = 800});
    EXPECT_GT(result.report.featureEdges, 0u);
    for (const glm::dvec3& p : result.mesh.positions) {
        double nearestPlane = 1.0;
        for (int c = 0; c < 3; ++c) nearestPlane = std::min(nearestPlane, std::abs(p[c] - std::round(p[c])));
        EXPECT_LT(nearestPlane, 1e-6);
    }
}

}  // namespace
