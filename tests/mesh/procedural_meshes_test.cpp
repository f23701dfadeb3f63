// Procedural meshes have the topology procedural_meshes.h promises.
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace {

double signedVolume(const ngi::TriangleMesh& mesh)
{
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        volume += glm::dot(mesh.positions[t.x], glm::cross(mesh.positions[t.y], mesh.positions[t.z])) / 6.0;
    return volume;
}

void expectTopology(const ngi::TriangleMesh& mesh, long genus, size_t boundaryLoops)
{
    ngi::MeshTopology topology = ngi::analyzeTopology(mesh);
    EXPECT_EQ(topology.components, 1u);
    EXPECT_EQ(topology.nonManifoldEdges, 0u);
    EXPECT_EQ(topology.vertices, mesh.positions.size());
    EXPECT_EQ(topology.boundaryLoops, boundaryLoops);
    EXPECT_EQ(topology.genus, genus);
}

TEST(ProceduralMeshes, SphereIsClosedGenusZeroOutward)
{
    ngi::TriangleMesh sphere = ngi::makeSphere(2);
    EXPECT_EQ(sphere.positions.size(), 162u);
    EXPECT_EQ(sphere.triangles.size(), 320u);
    expectTopology(sphere, 0, 0);
    EXPECT_GT(signedVolume(sphere), 3.9);  // 4/3 pi = 4.19 for the true sphere
}

TEST(ProceduralMeshes, TorusIsGenusOneOutward)
{
    ngi::TriangleMesh torus = ngi::makeTorus(24, 12);
    expectTopology(torus, 1, 0);
    EXPECT_GT(signedVolume(torus), 0.0);
}

TEST(ProceduralMeshes, GenusSurfaceHasRequestedGenus)
{
    for (uint32_t genus : {1u, 2u, 3u}) {
        ngi::TriangleMesh surface = ngi::makeGenusSurface(genus, 2);
        expectTopology(surface, long(genus), 0);
        EXPECT_NEAR(signedVolume(surface), double(3 * (2 * genus + 1) - genus), 1e-9);
    }
}

TEST(ProceduralMeshes, OpenCylinderHasTwoBoundaryLoops) { expectTopology(ngi::makeOpenCylinder(16, 4), 0, 2); }

TEST(ProceduralMeshes, PlanePatchIsADisk)
{
    ngi::TriangleMesh plane = ngi::makePlanePatch(8, 1.0, 0.2);
    expectTopology(plane, 0, 1);
    EXPECT_EQ(ngi::analyzeTopology(plane).eulerCharacteristic, 1);
}

}  // namespace
