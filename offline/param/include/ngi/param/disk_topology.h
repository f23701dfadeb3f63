// ngi offline: the combinatorics every square map shares: validation of a disk mesh, the
// choice of the four corners, and the placement of the boundary loop on the square's border.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace ngi {

// Connectivity facts of a validated disk mesh.
struct DiskTopology {
    std::vector<std::array<uint32_t, 2>> edges;  // unique undirected edges (i < j)
    std::vector<int32_t> boundaryPosition;       // per vertex: index into boundaryLoop, or -1 (interior)
    size_t interiorVertexCount = 0;
};

// Validates `disk` and returns its connectivity. Throws ngi::Error when the mesh is empty,
// has NaN/Inf positions, out-of-range or repeated indices in a triangle, zero-area triangles,
// an edge with more than two triangles or inconsistent orientation, a boundary other than
// exactly `boundaryLoop` (one loop, counter-clockwise with the triangles), fewer than four
// boundary vertices, Euler characteristic != 1 (not a disk), or isolated vertices.
DiskTopology analyzeDisk(const DiskMesh& disk);

// Positions in `boundaryLoop` of the four corners, in loop order (cyclically increasing).
// If `disk.cornerHints` names four distinct boundary vertices (the cut's polygon-schema
// corners for genus >= 1, cut.h), those, sorted by loop position. Otherwise, where the whole
// loop is the surface's own boundary (every vertex in `disk.surfaceBoundary`, where the cut
// recorded it, and met once: an open part the cut left as it was), its sharp corners first:
// vertices where it turns by more than 45 degrees within 1/64 of its length, at most four,
// sharpest first and 1/16 of the length apart; with two or more, the rest of the four split the longest stretches between
// them at their middle. Otherwise the boundary vertices closest to four equally spaced arc
// lengths (3D), from the one sharp corner if there is one, so the four sides have nearly equal
// length. Within 1/16 of the boundary length of each target an "ear" (boundary vertex of a
// single triangle) is preferred, since an ear that is not a corner gets a zero-area triangle on a
// straight side. Requires analyzeDisk to pass.
std::array<size_t, 4> chooseCornerPositions(const DiskMesh& disk);

// Places the boundary loop on the unit square's border, counter-clockwise: corner c goes to
// (0,0), (1,0), (1,1), (0,1) for c = 0..3, and the vertices between corner c and c+1 go on
// side c, spaced proportionally to `edgeLength[k]` = length of the boundary edge from
// boundaryLoop[k] to boundaryLoop[k+1] (any metric: 3D, or the flat metric of Ricci flow).
// Returns one uv per boundary loop entry.
std::vector<glm::dvec2> placeBoundaryOnSquare(const std::vector<double>& edgeLength,
                                              const std::array<size_t, 4>& cornerPositions);

// Side s runs from loop position `begin` to `end` (exclusive, may exceed the loop size: take
// positions modulo the loop size): corner s to corner s+1.
struct SideRange {
    size_t begin, end;
};
SideRange sideRange(int side, const std::array<size_t, 4>& cornerPositions, size_t loopSize);

// The side (0..3) of the square a boundary-loop entry lies on; a corner belongs to the side
// that starts at it. Used to keep boundary vertices on the border.
int boundarySide(size_t loopPosition, const std::array<size_t, 4>& cornerPositions, size_t loopSize);

}  // namespace ngi
