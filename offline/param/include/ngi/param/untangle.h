// ngi offline: turns the optimal-transport centroid map into a bijective map of the square.
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/disk_topology.h"

#include <glm/vec2.hpp>

#include <array>
#include <vector>

namespace ngi {

struct UntangleReport {
    size_t flippedBefore = 0;      // flipped triangles after snapping the boundary, before relaxing
    size_t flippedAfter = 0;       // flipped (or degenerate) triangles of the returned map
    bool relaxed = false;          // true if the mean-value relaxation ran
    double maxDisplacement = 0.0;  // largest uv move of an interior vertex made by the relaxation
    double weightFloor = 0.0;      // the relaxation's floor on weights / row mean (1e-3 unless flips made it raise it)
};

// Makes `uv` (e.g. power-cell centroids) a map onto the square that keeps the boundary on the
// border: each boundary vertex is projected onto the side it belongs to (corners exactly on
// the corners), with the boundary order restored along each side if the projection broke it;
// interior vertices are clamped into the square. If a triangle is then flipped, the interior is
// re-solved with the positive mean-value weights of the current layout (Floater 2003): a
// vertex whose 1-ring is already valid reproduces its position, a tangled one is relaxed, and
// positive weights with the convex border guarantee an embedding (Floater's theorem).
std::vector<glm::dvec2> makeBijectiveOnSquare(const DiskMesh& disk, const DiskTopology& topology,
                                              const std::array<size_t, 4>& cornerPositions, std::vector<glm::dvec2> uv,
                                              UntangleReport* report = nullptr);

}  // namespace ngi
