// ngi offline: ngi-bake stage 3, isotropic remeshing (the paper's input preconditioning,
// section 3.2 "Input Precondition", after Botsch & Kobbelt 2004 as implemented by CGAL's
// Polygon Mesh Processing: split long edges, collapse short ones, flip towards valence 6,
// tangential relaxation, projection back onto the input surface).
//
// Sizing: Debian 12's CGAL 5.5 offers only a uniform target edge length (its adaptive sizing
// field arrived in CGAL 6.0). We remesh uniformly on purpose: the optimal-transport stage
// already redistributes image samples by 3D area, and near-equal vertex areas give it
// well-conditioned target masses. Sharp feature edges (dihedral angle above
// featureAngleDegrees) and boundary edges are kept as constrained polylines so that creases
// (fandisk) survive, unless they make slivers (minAngleWithFeatures), as the tessellation
// creases of coarse organic meshes (elk) do.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstddef>
#include <cstdint>

namespace ngi {

struct RemeshOptions {
    size_t targetVertexCount = 16384;   // approximate vertex count of the result (fewer on slivers: RemeshReport)
    double targetEdgeLength = 0.0;      // if > 0, used instead of targetVertexCount (mesh units)
    uint32_t iterations = 3;            // remeshing iterations (split, collapse, flip, relax)
    double featureAngleDegrees = 60.0;  // dihedral angle above which an edge is a crease; <= 0: none
    // If creases leave a triangle angle below this (degrees), the mesh is remeshed again
    // without creases (reported in RemeshReport::droppedFeatureEdges).
    double minAngleWithFeatures = 10.0;
};

// Target edge length giving about `vertexCount` vertices of equilateral triangles on a surface
// of `area` (each vertex owns two triangles: area = vertexCount * sqrt(3)/2 * L^2).
double edgeLengthForVertexCount(double area, size_t vertexCount);

struct RemeshReport {
    size_t inputVertices = 0, inputTriangles = 0;
    size_t outputVertices = 0, outputTriangles = 0;
    double targetEdgeLength = 0.0;  // the length remeshed to (see vertexCountEdgeLength)
    // The length RemeshOptions::targetVertexCount gives on the input's area. targetEdgeLength is
    // longer where the input's boundary or bounding box diagonal would need more than
    // targetVertexCount vertices at it (slivers, needles: their area is small for their length).
    double vertexCountEdgeLength = 0.0;
    size_t featureEdges = 0;                   // input edges kept as creases
    size_t droppedFeatureEdges = 0;            // creases detected but dropped (they made slivers)
    double minAngleWithFeaturesDegrees = 0.0;  // the smallest angle they made
    double minAngleDegrees = 0.0;              // smallest triangle angle of the result (before the repair below)
    size_t closedHoles = 0;                    // boundary loops the remesher shrank to nothing (merged)
    size_t repairedZeroAreaTriangles = 0;      // zero-area triangles CGAL left, removed as clean.h does
    double meanEdgeLength = 0.0;
};

struct RemeshResult {
    TriangleMesh mesh;
    RemeshReport report;
};

// Remeshes a cleaned mesh (manifold, oriented: see clean.h). Keeps the genus and the
// boundary loops (except tiny holes the remesher shrinks to a point: closedHoles) and orientation. Throws ngi::Error if the mesh is not a valid manifold
// surface for CGAL or if the topology changed.
RemeshResult remeshIsotropic(const TriangleMesh& mesh, const RemeshOptions& options = {});

}  // namespace ngi
