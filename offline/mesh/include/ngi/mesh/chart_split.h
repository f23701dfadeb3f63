// ngi offline: one connected surface cut into pieces of about equal area, each to become its
// own chart (docs/cross-chart-seams.md, sections 2 and 9).
//
// The partition is a geodesic Voronoi diagram on the faces (Peyré and Cohen 2006, "Geodesic
// remeshing using front propagation": farthest-point seeds, then Lloyd-style relaxation that
// moves each seed to the face of its region farthest from the region's border), with
// distances along the dual graph (face centroid to face centroid across a shared edge).
// Why Voronoi and not necks: a surface of high genus (cheese, genus 133) has handles, not
// necks, and pieces of about equal area keep the charts' resolutions alike.
//
// The pieces are NOT joined by matched seams yet: the border a piece shares with another is
// an open boundary of each chart, sampled independently, so a bake of split pieces cracks
// along it. This file is what measures whether splitting pays (plan section 9) before the
// cross-chart seams are built.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace ngi {

struct ChartPartitionOptions {
    uint32_t pieces = 2;           // seeds; a mesh with fewer faces gets one piece per face
    uint32_t relaxIterations = 3;  // Lloyd-style moves of every seed to its region's centre
};

struct ChartPartition {
    std::vector<uint32_t> pieceOfFace;  // per triangle, in [0, pieces)
    uint32_t pieces = 0;
    std::vector<double> pieceArea;  // 3D area per piece
};

// Partitions `mesh` (manifold, connected through edges: one cleaned component) into
// options.pieces geodesic Voronoi regions of its faces. Each region is connected through
// edges (a Voronoi cell of a graph metric holds the shortest paths to its seed). Throws
// ngi::Error on a mesh without triangles or options.pieces == 0.
ChartPartition partitionByGeodesicVoronoi(const TriangleMesh& mesh, const ChartPartitionOptions& options = {});

// The vertex farthest along edges from the boundary (the deepest point of a piece, where a slit
// to the border starts), or kNoFace for a mesh without boundary or interior vertex.
uint32_t deepestVertex(const TriangleMesh& mesh);

// Splits every edge between two pieces at its midpoint, `rounds` times (each round halves the
// border edges again), splitting both triangles beside it; the halves keep their piece. The
// surface is unchanged (midpoints of edges); what changes is that a curve two pieces share has
// 2^rounds times the vertices, so a matched border finds a vertex near every square corner on
// it (matched_group.h). `pieceOfFace` is updated with the new triangles.
void refinePieceBorders(TriangleMesh& mesh, std::vector<uint32_t>& pieceOfFace, uint32_t rounds);

// The pieces of a partition as separate meshes, each with its own copy of the vertices it
// shares with another piece, its triangles in the input's order and orientation. A piece
// whose faces meet at a vertex only (two fans of one piece around a vertex) gets a copy of
// that vertex per fan, so each piece is manifold; a piece that then falls apart is returned
// as several meshes. Unreferenced vertices are removed. Largest area first. With
// `sourceVertex`, (*sourceVertex)[p][v] is the vertex of `mesh` that vertex v of piece p copies
// (what tells the pieces' shared borders apart: matched_group.h's groupVertex).
std::vector<TriangleMesh> splitIntoPieces(const TriangleMesh& mesh, std::span<const uint32_t> pieceOfFace,
                                          std::vector<std::vector<uint32_t>>* sourceVertex = nullptr);

}  // namespace ngi
