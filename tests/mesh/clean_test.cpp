// Stage 2 cleaning: repairs what is repairable, rejects the rest with a clear message.
#include "ngi/error.h"
#include "ngi/mesh/clean.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace {

std::string cleanError(const ngi::TriangleMesh& mesh)
{
    try {
        ngi::cleanMesh(mesh, {.sourceName = "bad.obj"});
    } catch (const ngi::Error& e) {
        return e.what();
    }
    return "";
}

double signedVolume(const ngi::TriangleMesh& mesh)
{
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        volume += glm::dot(mesh.positions[t.x], glm::cross(mesh.positions[t.y], mesh.positions[t.z])) / 6.0;
    return volume;
}

// A triangle soup: every triangle with its own three vertices (as STL files store them).
ngi::TriangleMesh toSoup(const ngi::TriangleMesh& mesh)
{
    ngi::TriangleMesh soup;
    for (const glm::uvec3& t : mesh.triangles) {
        uint32_t base = uint32_t(soup.positions.size());
        for (int k = 0; k < 3; ++k) soup.positions.push_back(mesh.positions[t[k]]);
        soup.triangles.push_back({base, base + 1, base + 2});
    }
    return soup;
}

TEST(CleanMesh, CleanMeshPassesThroughUnchanged)
{
    ngi::TriangleMesh torus = ngi::makeTorus(16, 8);
    ngi::CleanResult result = ngi::cleanMesh(torus);
    EXPECT_EQ(result.mesh.triangles, torus.triangles);
    EXPECT_EQ(result.report.components, 1u);
    EXPECT_TRUE(result.report.warnings.empty());
}

TEST(CleanMesh, MergesSoupVerticesAndDropsUnreferenced)
{
    ngi::TriangleMesh sphere = ngi::makeSphere(1);
    ngi::TriangleMesh soup = toSoup(sphere);
    soup.positions.push_back({5, 5, 5});  // unreferenced
    ngi::CleanResult result = ngi::cleanMesh(soup);
    EXPECT_EQ(result.mesh.positions.size(), sphere.positions.size());
    EXPECT_EQ(result.mesh.triangles.size(), sphere.triangles.size());
    EXPECT_EQ(result.report.mergedDuplicateVertices, soup.positions.size() - 1 - sphere.positions.size());
    EXPECT_EQ(ngi::analyzeTopology(result.mesh).genus, 0);
}

TEST(CleanMesh, MakesOrientationConsistentAndOutward)
{
    ngi::TriangleMesh sphere = ngi::makeSphere(2);
    for (size_t f = 0; f < sphere.triangles.size(); f += 3) std::swap(sphere.triangles[f].y, sphere.triangles[f].z);
    ngi::CleanResult result = ngi::cleanMesh(sphere);
    EXPECT_GT(result.report.flippedTriangles, 0u);
    EXPECT_GT(signedVolume(result.mesh), 3.9);
    EXPECT_EQ(ngi::analyzeTopology(result.mesh).nonManifoldEdges, 0u);
    // Fully inside-out: reversed to outward.
    ngi::TriangleMesh inverted = ngi::makeSphere(1);
    for (glm::uvec3& t : inverted.triangles) std::swap(t.y, t.z);
    ngi::CleanResult outward = ngi::cleanMesh(inverted);
    EXPECT_TRUE(outward.report.reversedToOutward);
    EXPECT_GT(signedVolume(outward.mesh), 0.0);
}

TEST(CleanMesh, DropsDegenerateAndDuplicateTriangles)
{
    ngi::TriangleMesh plane = ngi::makePlanePatch(4);
    const size_t triangles = plane.triangles.size();
    plane.triangles.push_back({0, 0, 1});           // repeated vertex
    plane.triangles.push_back(plane.triangles[3]);  // exact duplicate
    plane.triangles.push_back(
        {plane.triangles[5].x, plane.triangles[5].z, plane.triangles[5].y});  // reversed duplicate
    ngi::CleanResult result = ngi::cleanMesh(plane);
    EXPECT_EQ(result.mesh.triangles.size(), triangles);
    EXPECT_EQ(result.report.droppedDegenerateTriangles, 1u);
    EXPECT_EQ(result.report.droppedDuplicateTriangles, 2u);
}

TEST(CleanMesh, RepairsZeroAreaCapWithoutOpeningTheSurface)
{
    // Tetrahedron-like closed mesh with a collinear "cap": split edge 0-1 at vertex 4, but the
    // triangle on the other side still uses edge 0-1 (a T-junction closed by a zero-area cap).
    ngi::TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {1, 0, 0}};
    mesh.triangles = {{0, 2, 1}, {0, 4, 3}, {4, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 1, 4}};  // last: zero area
    ngi::CleanResult result = ngi::cleanMesh(mesh);
    EXPECT_EQ(result.report.repairedZeroAreaTriangles, 1u);
    EXPECT_EQ(result.report.droppedZeroAreaTriangles, 0u);
    ngi::MeshTopology topology = ngi::analyzeTopology(result.mesh);
    EXPECT_EQ(topology.boundaryLoops, 0u);
    EXPECT_EQ(topology.genus, 0);
    for (const glm::uvec3& t : result.mesh.triangles)
        EXPECT_GT(glm::length(glm::cross(result.mesh.positions[t.y] - result.mesh.positions[t.x],
                                         result.mesh.positions[t.z] - result.mesh.positions[t.x])),
                  1e-9);
}

TEST(CleanMesh, KeepsEveryComponent)
{
    ngi::TriangleMesh big = ngi::makeSphere(2, 2.0), small = ngi::makeSphere(1, 0.5);
    const uint32_t base = uint32_t(big.positions.size());
    for (glm::dvec3 p : small.positions) big.positions.push_back(p + glm::dvec3(10, 0, 0));
    for (glm::uvec3 t : small.triangles) big.triangles.push_back(t + glm::uvec3(base));
    ngi::CleanResult result = ngi::cleanMesh(big, {.sourceName = "two.obj"});
    EXPECT_EQ(result.report.components, 2u);
    EXPECT_EQ(result.mesh.triangles.size(), 320u + 80u);
    EXPECT_EQ(result.mesh.positions.size(), 162u + 42u);
    EXPECT_TRUE(result.report.warnings.empty());
    // splitComponents: largest first, each a closed sphere with its own vertices.
    const std::vector<ngi::TriangleMesh> parts = ngi::splitComponents(result.mesh);
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0].triangles.size(), 320u);
    EXPECT_EQ(parts[1].triangles.size(), 80u);
    EXPECT_EQ(parts[1].positions.size(), 42u);
    for (const ngi::TriangleMesh& part : parts) {
        EXPECT_EQ(ngi::analyzeTopology(part).boundaryLoops, 0u);
        EXPECT_GT(signedVolume(part), 0.0);
    }
}

// Two closed tetrahedra glued along one edge (4 triangles on it): cut into two closed
// surfaces, both outward, nothing dropped.
TEST(CleanMesh, CutsAnEdgeSharedByTwoClosedSurfaces)
{
    ngi::TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0.2}, {0.5, 0.4, 1}, {0.5, -1, 0.2}, {0.5, -0.4, -1}};
    // Tetrahedron A = (0 1 2 3), B = (0 1 4 5), both sharing edge 0-1; orientation scrambled.
    mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2},   // A, outward
                      {0, 1, 4}, {1, 0, 5}, {1, 5, 4}, {0, 4, 5}};  // B, some faces inward
    ngi::CleanResult result = ngi::cleanMesh(mesh, {.sourceName = "glued.obj"});
    EXPECT_EQ(result.report.nonManifoldEdges, 1u);
    EXPECT_EQ(result.report.cutEdgeSides, 0u);  // both pairs around the edge found partners
    EXPECT_EQ(result.report.splitNonManifoldVertices, 2u);
    EXPECT_EQ(result.mesh.triangles.size(), 8u);
    EXPECT_EQ(result.report.components, 2u);
    ngi::MeshTopology topology = ngi::analyzeTopology(result.mesh);
    EXPECT_EQ(topology.nonManifoldEdges, 0u);
    EXPECT_EQ(topology.boundaryLoops, 0u);
    for (const ngi::TriangleMesh& part : ngi::splitComponents(result.mesh)) EXPECT_GT(signedVolume(part), 0.0);
    ASSERT_FALSE(result.report.warnings.empty());
    EXPECT_NE(result.report.warnings[0].find("glued.obj: repaired 1 non-manifold edges"), std::string::npos);
}

// A fin: three triangles on one edge. Two become one sheet, the third keeps its own copy
// of the edge (an open side), nothing is dropped.
TEST(CleanMesh, CutsAFinOffItsEdge)
{
    ngi::TriangleMesh fin;
    fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    ngi::CleanResult result = ngi::cleanMesh(fin, {.sourceName = "fin.obj"});
    EXPECT_EQ(result.report.nonManifoldEdges, 1u);
    EXPECT_EQ(result.report.cutEdgeSides, 1u);
    EXPECT_EQ(result.mesh.triangles.size(), 3u);
    EXPECT_EQ(ngi::analyzeTopology(result.mesh).nonManifoldEdges, 0u);
    EXPECT_EQ(result.report.droppedNonManifoldTriangles, 0u);
}

TEST(CleanMesh, SplitsNonManifoldVertex)
{
    // A 4x1 strip whose last corner is glued onto its first: one component, one pinch vertex.
    ngi::TriangleMesh strip = ngi::makePlanePatch(4);
    ngi::TriangleMesh band;
    for (uint32_t j = 0; j <= 1; ++j)
        for (uint32_t i = 0; i <= 4; ++i) band.positions.push_back({double(i), double(j), 0.0});
    auto index = [](uint32_t i, uint32_t j) { return (j == 0 && i == 4) ? 0u : j * 5 + i; };
    for (uint32_t i = 0; i < 4; ++i) {
        band.triangles.push_back({index(i, 0), index(i + 1, 0), index(i + 1, 1)});
        band.triangles.push_back({index(i, 0), index(i + 1, 1), index(i, 1)});
    }
    ngi::CleanResult result = ngi::cleanMesh(band);
    EXPECT_EQ(result.report.splitNonManifoldVertices, 1u);
    EXPECT_EQ(result.mesh.positions.size(), 10u);
    EXPECT_EQ(ngi::analyzeTopology(result.mesh).boundaryLoops, 1u);
}

TEST(CleanMesh, RejectsWhatHasNoSurfaceAndRepairsTheRest)
{
    EXPECT_NE(cleanError(ngi::TriangleMesh{}).find("bad.obj: the mesh is empty"), std::string::npos);

    ngi::TriangleMesh nan = ngi::makeSphere(0);
    nan.positions[3].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(cleanError(nan).find("NaN or infinite"), std::string::npos);
    ngi::TriangleMesh inf = ngi::makeSphere(0);
    inf.positions[0].z = std::numeric_limits<double>::infinity();
    EXPECT_NE(cleanError(inf).find("NaN or infinite"), std::string::npos);

    ngi::TriangleMesh strip;  // Moebius strip, 5 quads with a half twist
    const int n = 5;
    for (int i = 0; i < n; ++i) {
        double a = 2.0 * std::numbers::pi * i / n;
        for (int s : {-1, 1}) {
            double w = 0.3 * s;
            strip.positions.push_back({(1 + w * std::cos(a / 2)) * std::cos(a), (1 + w * std::cos(a / 2)) * std::sin(a),
                                       w * std::sin(a / 2)});
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t a0 = 2 * i, a1 = 2 * i + 1;
        uint32_t b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;  // twist at the seam
        strip.triangles.push_back({a0, b0, b1});
        strip.triangles.push_back({a0, b1, a1});
    }
    // A Moebius strip is cut open where its orientation conflicts: an orientable strip.
    ngi::CleanResult opened = ngi::cleanMesh(strip, {.sourceName = "moebius.obj"});
    EXPECT_GE(opened.report.orientationCutEdges, 1u);
    EXPECT_EQ(opened.mesh.triangles.size(), 10u);
    const ngi::MeshTopology topology = ngi::analyzeTopology(opened.mesh);
    EXPECT_EQ(topology.components, 1u);
    EXPECT_EQ(topology.eulerCharacteristic, 1);  // a disk: the strip cut across once

    ngi::TriangleMesh degenerate;
    degenerate.positions = {{0, 0, 0}, {1, 0, 0}};
    degenerate.triangles = {{0, 1, 1}};
    EXPECT_NE(cleanError(degenerate).find("degenerate"), std::string::npos);
}

}  // namespace
