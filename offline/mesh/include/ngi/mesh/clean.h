// ngi offline: ngi-bake stage 2, cleaning a mesh read from a file into a manifold,
// consistently oriented, single-component triangle mesh (DESIGN.md data flow, "clean").
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstddef>
#include <string>
#include <vector>

namespace ngi {

struct CleanOptions {
    // Names the mesh in error messages and warnings (normally the file path).
    std::string sourceName = "mesh";
    // A triangle whose area is below zeroAreaTolerance * (bbox diagonal)^2 is zero-area.
    double zeroAreaTolerance = 1e-14;
    // Zero-area triangles are removed by splitting their neighbour across the longest edge at the
    // middle vertex (which keeps the surface closed); after this many passes the rest are dropped.
    int zeroAreaRepairPasses = 8;
};

struct CleanReport {
    size_t inputVertices = 0, inputTriangles = 0;
    size_t mergedDuplicateVertices = 0;     // vertices merged into an earlier one at the same position
    size_t droppedDegenerateTriangles = 0;  // triangles with a repeated vertex (after merging)
    size_t droppedDuplicateTriangles = 0;   // same three vertices as an earlier triangle
    size_t repairedZeroAreaTriangles = 0;   // removed by splitting their neighbour (surface stays closed)
    size_t droppedZeroAreaTriangles = 0;    // removed outright (leaves a zero-width hole)
    size_t flippedTriangles = 0;            // re-oriented to agree with their component
    size_t splitNonManifoldVertices = 0;    // vertices duplicated because two fans met there
    size_t removedUnreferencedVertices = 0;
    size_t components = 0;                  // connected components found (through edges)
    size_t droppedComponentTriangles = 0;   // triangles of the components that were not kept
    double keptAreaFraction = 1.0;          // area of the kept component / total area
    bool reversedToOutward = false;         // closed mesh turned inside out, now outward
    std::vector<std::string> warnings;      // loud, user-facing: e.g. "kept 1 of 3 components"
};

struct CleanResult {
    TriangleMesh mesh;
    CleanReport report;
};

// Stage 2 of ngi-bake. Merges vertices with identical positions, drops degenerate, duplicate
// and zero-area triangles (zero-area ones repaired where possible, see CleanOptions), duplicates
// non-manifold vertices, orients every triangle consistently (outward for a closed mesh), keeps
// the largest connected component by area (warning in report.warnings when there were several)
// and removes unreferenced vertices.
// Throws ngi::Error "SOURCE: problem" for: no triangles, a NaN/Inf coordinate, an out-of-range
// index, an edge shared by more than two triangles (non-manifold edge: not repairable), a
// non-orientable surface, and nothing left after cleaning.
CleanResult cleanMesh(const TriangleMesh& input, const CleanOptions& options = {});

} // namespace ngi
