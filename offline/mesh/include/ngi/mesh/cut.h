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

// How the cut graph of a surface of genus >= 1 or with several boundary loops is built:
// TreeCotree: the greedy shortest loops (Erickson & Whittlesey 2005) through one root; short,
//   but the two halves of a loop through a far handle run side by side back to the root.
// FacePeeling: Gu, Gortler, Hoppe 2002: faces grown from a seed in order of distance, the
//   cut is where the growth fronts meet; longer, but with no thin channel between branches.
enum class CutGraph { TreeCotree, FacePeeling };

struct CutOptions {
    CutGraph graph = CutGraph::TreeCotree;
    // Split every uncut edge whose two endpoints both lie on the cut graph (or on the mesh's
    // boundary) at its midpoint, before cutting. Afterwards no disk triangle has all three
    // vertices on the disk boundary and no interior edge joins two boundary vertices, so a map
    // onto a convex square cannot squash a triangle flat onto one side (Tutte/Floater
    // condition). The midpoints lie on the surface (they are points of mesh edges).
    bool splitBoundaryBridges = true;
    // Extremities (vertices of the input mesh) to cut through: after the cut graph is built,
    // each is joined to it, in order, by the shortest edge path from it to the graph so far
    // (Gu, Gortler, Hoppe 2002, "Geometry Images", section 3.2 "cut augmentation"). A path
    // that meets the graph only at its end adds a slit to the disk, so the result stays a
    // disk; it opens a protrusion that a map to the square would otherwise shrink
    // exponentially. Vertices already on the cut or the boundary are skipped.
    std::vector<uint32_t> extremities;
    // Record which disk vertices lie on the uncut mesh's own boundary (DiskMesh::surfaceBoundary),
    // so that the square's corners may go on that boundary's sharp turns (disk_topology.h). For
    // a surface whose boundary is its own (an open part, a single triangle); not for a piece of
    // a split, whose boundary is the seam to the other pieces and whose corners the matched
    // borders place.
    bool cornersAtBoundaryTurns = false;
};

struct CutReport {
    long genus = 0;
    size_t boundaryLoops = 0;     // boundary loops of the uncut mesh
    size_t cutEdges = 0;          // interior edges of the uncut mesh the cut runs along
    double cutLength = 0.0;       // their total length (mesh units)
    size_t seamVertices = 0;      // vertices added by the cut (copies along the seam)
    size_t splitBridgeEdges = 0;  // edges split by CutOptions::splitBoundaryBridges
    size_t diskBoundaryVertices = 0;
    size_t extremityPaths = 0;     // paths added for CutOptions::extremities
    double extremityLength = 0.0;  // their total length (part of cutLength)
    std::string method;  // "already a disk", "shortest path between far vertices", "tree-cotree", "face peeling"
};

struct CutResult {
    TriangleMesh uncut;  // the mesh that was cut: the input plus split-edge midpoints
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

}  // namespace ngi
