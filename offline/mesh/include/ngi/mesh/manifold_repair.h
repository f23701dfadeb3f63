// ngi offline: ngi-bake stage 2, turning a triangle soup with non-manifold edges and
// vertices into a manifold mesh by cutting, never by refusing (DESIGN.md "repair").
//
// The same idea as CGAL's orient_polygon_soup + duplicate_non_manifold_vertices: every
// undirected edge keeps at most two of its triangles as neighbours, every vertex is
// duplicated once per fan of corners that the kept neighbourhoods join. At an edge shared
// by more than two triangles the triangles are sorted by their angle around the edge and
// consecutive ones of opposite direction are paired: two sheets that touch along an edge
// (two cubes sharing an edge, a fin on a wall) become two closed or bounded sheets, each
// consistently oriented, and nothing is dropped.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ngi {

struct ManifoldRepair {
    size_t nonManifoldEdges = 0;  // edges shared by more than two triangles (before repair)
    size_t cutEdgeSides = 0;      // triangle sides left without a neighbour by the repair
    size_t splitVertices = 0;     // vertex copies added (one per extra fan of a vertex)
    size_t droppedTriangles = 0;  // triangles that no cut could make manifold (pathological)
};

// Makes `mesh` edge- and vertex-manifold in place. `forcedCuts` are undirected edges
// (vertex pairs, any order) whose triangles must not stay neighbours, e.g. where the
// orientation of a non-orientable strip conflicts. Vertices are only added (copies of
// existing positions, appended); triangles keep their order and orientation, except the
// rare ones counted in droppedTriangles. Indices must be valid (the caller checks).
ManifoldRepair splitNonManifold(TriangleMesh& mesh, const std::vector<glm::uvec2>& forcedCuts = {});

}  // namespace ngi
