// ngi offline eval: how closed a drawn mesh is (the seam issue's measure): vertices welded
// within a tolerance, edges of one triangle counted, and the widest gap between open edges.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstddef>

namespace ngi {

struct OpenEdgeReport {
    size_t openEdges = 0;         // edges of exactly one triangle after the weld
    size_t nonManifoldEdges = 0;  // edges of more than two
    // The widest crack: the largest distance from a vertex of an open edge to the nearest
    // open edge that is not within two steps of it along the open edges (the other side of
    // the crack; its own side's neighbours excluded). 0 without open edges; for a mesh with
    // boundary loops of its own it also measures those loops' width.
    double largestGap = 0.0;
};

// Welds vertices whose positions round to one cell of `tolerance` (the same cell => one
// vertex), skips triangles the weld collapses, and measures the open edges.
OpenEdgeReport measureOpenEdges(const TriangleMesh& mesh, double tolerance);

}  // namespace ngi
