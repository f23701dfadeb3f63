// ngi offline eval, peers: the paper's subdivision baselines, applied to a simplified mesh.
//   Loop:               C. T. Loop, "Smooth Subdivision Surfaces Based on Triangles", 1987
//                       (approximating: every vertex moves).
//   Modified Butterfly: D. Zorin, P. Schroeder, W. Sweldens, "Interpolating Subdivision for
//                       Meshes with Arbitrary Topology", 1996 (interpolating: old vertices stay).
// Both by OpenMesh's uniform subdividers; each iteration splits every triangle into four.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>

namespace ngi {

enum class SubdivisionScheme { loop, modifiedButterfly };

struct SubdivisionOptions {
    SubdivisionScheme scheme = SubdivisionScheme::loop;
    uint32_t iterations = 1;  // triangles x 4 per iteration
};

struct SubdivisionResult {
    TriangleMesh mesh;
    uint32_t detachedTriangles = 0;  // input triangles at a non-manifold edge or vertex that
                                     // were given their own vertices to be subdivided alone
};

// Subdivides `mesh` options.iterations times with the chosen scheme. Triangles OpenMesh
// cannot connect (non-manifold configurations) are subdivided as separate pieces and counted
// in detachedTriangles; degenerate triangles (a repeated vertex) are dropped. Prints
// nothing. Throws ngi::Error on an index out of range, a non-finite coordinate, no
// triangles, or iterations > 6 (4^6 = 4096 x the triangles).
SubdivisionResult subdivideMesh(const TriangleMesh& mesh, const SubdivisionOptions& options);

}  // namespace ngi
