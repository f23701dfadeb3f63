// ngi offline: the plain triangle mesh every offline stage passes along, and the disk
// (cut) mesh that parameterization maps to the unit square.
#pragma once

#include <glm/vec3.hpp>
#include <glm/vec2.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ngi {

// An indexed triangle mesh: connectivity (triangles) separate from geometry (positions).
// Triangles are counter-clockwise seen from outside (consistent orientation after cleaning).
struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<glm::uvec3> triangles;
};

// A mesh cut open into a topological disk (one boundary loop), ready to be mapped to the
// unit square. The seam is recorded through `originalVertex`: cut vertices that came from
// the same vertex of the uncut mesh are mates along the seam.
struct DiskMesh {
    TriangleMesh mesh;
    std::vector<uint32_t> boundaryLoop;    // boundary vertices in order, counter-clockwise
                                           // with respect to the triangles' orientation
    std::vector<uint32_t> originalVertex;  // per vertex of `mesh`: its vertex in the uncut mesh
    // Optional: four boundary vertices (in boundaryLoop order) that make good square corners,
    // or empty. For a surface of genus g >= 1 cut by tree-cotree these are copies of the cut
    // graph's junctions, where the 2g loops meet: corners of the polygon schema (a b a^-1 b^-1
    // for a torus), the four with the smallest angle sums. Measured on knot1 at
    // 1024: Ricci flow 6 iterations with no degenerate triangle, OT 10 iterations, where
    // corners at equal arc-length quarters made OT fail.
    std::vector<uint32_t> cornerHints;
    // Optional, per vertex: 1 where its vertex of the uncut mesh lies on that mesh's own boundary
    // (not on a cut made to open it). Where given, the square's corners may go on the sharp turns
    // of that boundary (chooseCornerPositions).
    std::vector<uint8_t> surfaceBoundary;
};

}  // namespace ngi
