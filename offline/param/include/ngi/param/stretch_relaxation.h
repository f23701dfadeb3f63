// ngi offline: a start map for optimal transport with less clustering than the conformal or
// harmonic one: the stretch-minimizing fixed-border iteration of Yoshizawa, Belyaev, Seidel
// 2004 ("A fast and simple stretch-minimizing mesh parameterization").
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/disk_topology.h"

#include <glm/vec2.hpp>

#include <array>
#include <vector>

namespace ngi {

struct StretchRelaxationOptions {
    int maxIterations = 40;  // fixed-border solves after the first (mean-value) one
    double eta = 1.0;        // exponent of the weight update w_ij <- w_ij / sigma_j^eta
    // Stop at the first iterate whose max |log area ratio| is at most this: the fewer updates,
    // the closer the map stays to the (nearly conformal) mean-value map. 0: run to the best.
    double targetAreaMax = 0.0;
};

struct StretchRelaxationReport {
    int iterations = 0;         // reweighted solves run
    double startAreaMax = 0.0;  // max |log area ratio| of the first (mean-value) map
    double areaMax = 0.0;       // of the returned map
};

// A bijective map of `disk` onto the unit square (boundary spaced by 3D arc length between the
// corners at `cornerPositions`) that keeps the largest |log(uv area / 3D area)| small: Floater's
// 3D mean-value map, then fixed-border solves whose weights are divided by each neighbour's
// L2 stretch (Sander et al. 2001) of the previous map. Every weight stays positive, so every
// iterate is an embedding (Floater's theorem); the iterate with the smallest max |log area
// ratio| is returned. Throws what solveFixedBorderMap throws.
std::vector<glm::dvec2> stretchMinimizingMap(const DiskMesh& disk, const DiskTopology& topology,
                                             const std::array<size_t, 4>& cornerPositions,
                                             const StretchRelaxationOptions& options = {},
                                             StretchRelaxationReport* report = nullptr);

}  // namespace ngi
