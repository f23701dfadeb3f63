// ngi offline: ngi-bake stage 2, cleaning a mesh read from a file into a manifold,
// consistently oriented triangle mesh of one or more components (DESIGN.md data flow,
// "repair"): what can be repaired is repaired, and every component with a surface is kept.
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
    // A component whose area is below nearZeroAreaRatio * (its bbox diagonal)^2 has (near) zero
    // area: a sliver or a needle about 1/10,000 of its length wide, narrower than an edge of the
    // default 16,384-vertex remesh, so the remesh follows only its outline. It is dropped with a
    // warning; a mesh made only of such components is refused. <= 0: keep all.
    double nearZeroAreaRatio = 1e-4;
};

struct CleanReport {
    size_t inputVertices = 0, inputTriangles = 0;
    size_t mergedDuplicateVertices = 0;      // vertices merged into an earlier one at the same position
    size_t droppedDegenerateTriangles = 0;   // triangles with a repeated vertex (after merging)
    size_t droppedDuplicateTriangles = 0;    // same three vertices as an earlier triangle
    size_t repairedZeroAreaTriangles = 0;    // removed by splitting their neighbour (surface stays closed)
    size_t droppedZeroAreaTriangles = 0;     // removed outright (leaves a zero-width hole)
    size_t flippedTriangles = 0;             // re-oriented to agree with their component
    size_t nonManifoldEdges = 0;             // edges shared by more than two triangles, cut apart
    size_t cutEdgeSides = 0;                 // triangle sides opened by the non-manifold repair
    size_t orientationCutEdges = 0;          // edges cut to make a non-orientable strip orientable
    size_t droppedNonManifoldTriangles = 0;  // triangles no cut could make manifold (pathological)
    size_t splitNonManifoldVertices = 0;     // vertex copies made (fans split apart)
    size_t removedUnreferencedVertices = 0;
    size_t components = 0;                 // connected components (through edges) kept
    size_t droppedZeroAreaComponents = 0;  // components of (near) zero area dropped (CleanOptions::nearZeroAreaRatio)
    size_t droppedComponentTriangles = 0;  // their triangles
    double keptAreaFraction = 1.0;         // area kept / total area
    size_t reversedComponents = 0;         // closed components turned from inside-out to outward
    bool reversedToOutward = false;        // reversedComponents > 0
    std::vector<std::string> warnings;     // loud, user-facing: e.g. "kept 1 of 3 components"
};

struct CleanResult {
    TriangleMesh mesh;
    CleanReport report;
};

// Stage 2 of ngi-bake. Merges vertices with identical positions, drops degenerate, duplicate
// and zero-area triangles (zero-area ones repaired where possible, see CleanOptions), cuts
// non-manifold edges and vertices apart (splitNonManifold), cuts a non-orientable strip
// where its orientation conflicts, orients every component consistently (outward for a
// closed one), keeps every component with a surface (one of (near) zero area is dropped, see
// CleanOptions::nearZeroAreaRatio) and removes unreferenced vertices. Every repair is counted in the report and summarized in report.warnings.
// Throws ngi::Error "SOURCE: problem" only for what has no surface: no triangles, a
// NaN/Inf coordinate, an out-of-range index, nothing left after cleaning, all vertices at
// one point, only components of (near) zero area, or a strip still non-orientable after
// cutting.
CleanResult cleanMesh(const TriangleMesh& input, const CleanOptions& options = {});

// The connected components (through shared edges) of a manifold mesh as separate meshes,
// largest surface area first; each keeps its triangles' order and orientation.
std::vector<TriangleMesh> splitComponents(const TriangleMesh& mesh);

}  // namespace ngi
