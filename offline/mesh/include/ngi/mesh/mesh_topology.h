// ngi offline: edge connectivity and topological invariants of a triangle mesh (Euler
// characteristic V - E + F = 2 - 2g - b for a connected orientable surface of genus g with b
// boundary loops). Shared by the cleaning, cutting and parameterization stages and tests.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace ngi {

inline constexpr uint32_t kNoFace = std::numeric_limits<uint32_t>::max();

// Undirected edges of a triangle mesh. Edge e joins vertices[e].x < vertices[e].y and is
// shared by faces[e].x and faces[e].y (kNoFace when absent: a boundary edge). Edge k of
// triangle t (k = 0, 1, 2) runs from corner k to corner (k + 1) % 3: faceEdges[t][k].
// Edges with more than two incident triangles are counted in nonManifoldEdges; their
// faces[] keep only the first two.
struct MeshEdges {
    std::vector<glm::uvec2> vertices;
    std::vector<glm::uvec2> faces;
    std::vector<glm::uvec3> faceEdges;
    size_t nonManifoldEdges = 0;
    uint32_t nonManifoldExample = kNoFace;  // one such edge, and how many triangles share it
    size_t nonManifoldExampleFaces = 0;

    bool isBoundary(uint32_t e) const { return faces[e].y == kNoFace; }
};

// Builds the edge table in O(F log F). Throws ngi::Error if a triangle index is out of range.
MeshEdges buildMeshEdges(const TriangleMesh& mesh);

// Boundary loops, each a closed vertex sequence that follows the triangles' orientation
// (interior on the left for counter-clockwise triangles). Throws ngi::Error if the boundary is
// not a union of simple loops (a vertex with more than one outgoing boundary edge).
std::vector<std::vector<uint32_t>> findBoundaryLoops(const TriangleMesh& mesh, const MeshEdges& edges);

// Per vertex, the sum of its triangles' angles at it (radians): 2 pi less the angle defect
// inside, the interior angle on a boundary. Degenerate corners (an edge of zero length) add
// nothing.
std::vector<double> vertexAngleSums(const TriangleMesh& mesh);

// Connected components through shared edges: per-triangle component id, ids 0..count-1.
struct FaceComponents {
    std::vector<uint32_t> componentOfFace;
    uint32_t count = 0;
};
FaceComponents findFaceComponents(const TriangleMesh& mesh, const MeshEdges& edges);

// Invariants of a mesh. Counts only referenced vertices. genus is meaningful for a connected,
// manifold, orientable mesh: (2 - boundaryLoops - eulerCharacteristic) / 2.
struct MeshTopology {
    size_t vertices = 0, edges = 0, faces = 0;
    size_t boundaryLoops = 0;
    uint32_t components = 0;
    long eulerCharacteristic = 0;
    long genus = 0;
    size_t nonManifoldEdges = 0;
};
MeshTopology analyzeTopology(const TriangleMesh& mesh);

}  // namespace ngi
