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
};

} // namespace ngi
