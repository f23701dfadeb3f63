// A surface folded back flat onto itself (two triangles on each other across an edge): CGAL
// 5.5's remesher collapses such a fold into coincident vertices and then crashed in its
// tangential relaxation (github.com/CGAL/cgal/issues/7345; remesh.cpp includes the fixed relaxation).
#include "ngi/error.h"
#include "ngi/mesh/clean.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <gtest/gtest.h>

namespace {

// Seven vertices in a plane and seven triangles around the origin whose fan overlaps itself:
// two of them lie on their neighbours, folded back. Remeshing it at 1000
// vertices crashed (SIGSEGV in CGAL::Polygon_mesh_processing::tangential_relaxation).
ngi::TriangleMesh foldedFan()
{
    ngi::TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {2, -2, 0}, {2, 0, 0}, {1, 1, 0}, {0, 2, 0}, {-2, 2, 0}, {-1, 0, 0}};
    mesh.triangles = {{4, 3, 1}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}, {3, 6, 1}};
    return mesh;
}

TEST(FlatFold, AFanFoldedOntoItselfRemeshes)
{
    const ngi::CleanResult cleaned = ngi::cleanMesh(foldedFan(), {.sourceName = "fan.obj"});
    for (size_t target : {500, 1000, 2000}) {
        // Any outcome but a crash: a remesh, or an ngi::Error (a fold may change the topology).
        try {
            ngi::remeshIsotropic(cleaned.mesh, {.targetVertexCount = target});
        } catch (const ngi::Error&) {}
    }
}

}  // namespace
