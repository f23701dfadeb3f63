// A surface folded back flat onto itself (two triangles on each other across an edge): the
// cleaning stage cuts it open there, because CGAL's remesher collapses such a fold into a line
// of coincident vertices and then crashes in its tangential relaxation.
#include "ngi/mesh/clean.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <gtest/gtest.h>

namespace {

// Seven vertices in a plane and seven triangles around the origin whose fan overlaps itself:
// two of them lie on their neighbours, folded back. Before the cut, remeshing it at 1000
// vertices crashed (SIGSEGV in CGAL::Polygon_mesh_processing::tangential_relaxation).
ngi::TriangleMesh foldedFan() {
    ngi::TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {2, -2, 0}, {2, 0, 0}, {1, 1, 0}, {0, 2, 0}, {-2, 2, 0}, {-1, 0, 0}};
    mesh.triangles = {{4, 3, 1}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}, {3, 6, 1}};
    return mesh;
}

TEST(FlatFold, AFanFoldedOntoItselfIsCutOpenAndRemeshes) {
    const ngi::CleanResult cleaned = ngi::cleanMesh(foldedFan(), {.sourceName = "fan.obj"});
    EXPECT_EQ(cleaned.report.foldCutEdges, 3u);
    EXPECT_EQ(cleaned.mesh.triangles.size(), 7u);  // nothing dropped
    bool warned = false;
    for (const std::string& w : cleaned.report.warnings) warned |= w.rfind("fan.obj: cut open 3 edges", 0) == 0;
    EXPECT_TRUE(warned);
    for (size_t target : {500, 1000, 2000})
        for (const ngi::TriangleMesh& part : ngi::splitComponents(cleaned.mesh)) {
            const ngi::RemeshResult remeshed = ngi::remeshIsotropic(part, {.targetVertexCount = target});
            EXPECT_EQ(ngi::analyzeTopology(remeshed.mesh).genus, ngi::analyzeTopology(part).genus);
        }
}

TEST(FlatFold, ASharpButOpenCreaseIsNotCut) {
    // A closed sphere squashed to 2% of its height: its rim is sharp, but no two triangles
    // lie on each other.
    ngi::TriangleMesh lens = ngi::makeSphere(2);
    for (glm::dvec3& p : lens.positions) p.z *= 0.02;
    const ngi::CleanResult cleaned = ngi::cleanMesh(lens);
    EXPECT_EQ(cleaned.report.foldCutEdges, 0u);
    EXPECT_EQ(ngi::analyzeTopology(cleaned.mesh).boundaryLoops, 0u);
}

} // namespace
