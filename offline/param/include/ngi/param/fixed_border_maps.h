// ngi offline: fixed-border linear maps of a disk onto the unit square (Tutte 1963 uniform,
// Eck et al. 1995 harmonic/cotangent, Desbrun-Meyer-Alliez 2002 authalic, Floater 2003 mean
// value) and the linear solve they share.
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/disk_topology.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <vector>

namespace ngi {

// One directed coefficient of a fixed-border map: the row of `from` says
// sum over `to` of weight * (uv[to] - uv[from]) = 0. Duplicates are summed.
struct DirectedWeight {
    uint32_t from;
    uint32_t to;
    double weight;
};

enum class EdgeWeightKind { Uniform, Cotangent, Authalic };

// The edge weights of the named linear map, computed on the 3D mesh:
// Uniform: w_ij = 1; Cotangent: w_ij = (cot alpha_ij + cot beta_ij) / 2 (angles opposite ij);
// Authalic (chi weights): w_ij = (cot gamma_ij + cot delta_ij) / |x_i - x_j|^2 (angles at x_j).
// Cotangent and authalic weights are negative next to obtuse angles.
std::vector<DirectedWeight> edgeWeights(const DiskMesh& disk, EdgeWeightKind kind);

// Mean-value weights (Floater 2003) of the 2D layout `uv`: w_ij = (tan(a/2) + tan(b/2)) / |uv_i - uv_j|
// with a, b the UNSIGNED angles at uv_i of the two triangles at edge ij, so every weight is > 0
// even where the layout is tangled, and a valid (star-shaped) 1-ring is reproduced exactly.
std::vector<DirectedWeight> meanValueWeights(const DiskMesh& disk, const std::vector<glm::dvec2>& uv);

struct FixedBorderSolveReport {
    size_t negativeWeights = 0;  // interior rows' off-diagonal weights <= 0 before clamping
    size_t clampedWeights = 0;   // weights raised to the positive floor (only if clampNegative)
};

// Solves the fixed-border system: boundary vertices at `boundaryUv` (one per boundaryLoop
// entry), each interior vertex the weighted average of its neighbours. If `clampNegative`,
// weights below `floor` * (mean |weight| of the row) are raised to it, which makes every
// weight positive: with a convex border, Floater's theorem then guarantees an embedding,
// except for triangles whose three vertices lie on one side of the square (a mesh with an
// interior edge joining two boundary vertices of the same side cannot be mapped without them).
// `symmetric` selects LDLT (symmetric weights, no clamping) instead of LU. Throws ngi::Error if the solve fails.
std::vector<glm::dvec2> solveFixedBorderMap(const DiskMesh& disk, const DiskTopology& topology,
                                            const std::vector<glm::dvec2>& boundaryUv,
                                            const std::vector<DirectedWeight>& weights, bool symmetric,
                                            bool clampNegative, FixedBorderSolveReport* report = nullptr,
                                            double floor = 1e-3);

// Counts triangles with uv area <= 0 (counter-clockwise is positive).
size_t countFlippedTriangles(const DiskMesh& disk, const std::vector<glm::dvec2>& uv);

}  // namespace ngi
