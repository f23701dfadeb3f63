// ngi offline: ngi-bake stage 4, cutting a surface of any genus with any number of boundary
// loops open into a topological disk whose single boundary loop the parameterization maps
// onto the square's border.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace ngi {

struct CutOptions {
    // Split every uncut edge whose two endpoints both lie on the cut graph (or on the mesh's
    // boundary) at its midpoint, before cutting. Afterwards no disk triangle has all three
    // vertices on the disk boundary and no interior edge joins two boundary vertices, so a map
    // onto a convex square cannot squash a triangle flat onto one side (Tutte/Floater
    // condition). The midpoints lie on the surface (they are points of mesh edges).
    bool splitBoundaryBridges = true;
};

struct CutReport {
    long genus = 0;
    size_t boundaryLoops = 0;     // boundary loops of the uncut mesh
    size_t cutEdges = 0;          // interior edges of the uncut mesh the cut runs along
    double cutLength = 0.0;       // their total length (mesh units)
    size_t seamVertices = 0;      // vertices added by the cut (copies along the seam)
    size_t splitBridgeEdges = 0;  // edges split by CutOptions::splitBoundaryBridges
    size_t diskBoundaryVertices = 0;
    std::string method;           // "already a disk", "shortest path between far vertices", "tree-cotree"
};

struct CutResult {
    TriangleMesh uncut;           // the mesh that was cut: the input plus split-edge midpoints
    DiskMesh disk;
    CutReport report;
};

// Cuts a connected, manifold, oriented mesh (see clean.h) into a disk: one boundary loop,
// Euler characteristic 1. result.uncut is `mesh` with bridge edges split (same vertices first,
// then the midpoints; see CutOptions); disk triangles are result.uncut's triangles in order and
// orientation, and disk.originalVertex maps every disk vertex to its vertex in result.uncut.
// disk.boundaryLoop follows the triangles' orientation. Throws ngi::Error if the mesh is not connected or not manifold, or if the cut
// does not yield a disk (an internal failure, reported with the counts found).
CutResult cutToDisk(const TriangleMesh& mesh, const CutOptions& options = {});

// The seam as pairs of mate edges on the disk boundary. Boundary edge i runs from
// boundaryLoop[i] to boundaryLoop[(i + 1) % n]. Each pair {i, j} holds two boundary edges that
// are the same edge of the uncut mesh (traversed in opposite directions); edges of an original
// boundary of the mesh have no mate and are listed in `unmatched`.
struct SeamEdges {
    std::vector<std::array<uint32_t, 2>> mates;
    std::vector<uint32_t> unmatched;
};
SeamEdges findSeamEdges(const DiskMesh& disk);

} // namespace ngi
