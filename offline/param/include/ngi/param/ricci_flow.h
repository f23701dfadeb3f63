// ngi offline: discrete Ricci flow (vertex-scaling / discrete Yamabe form) of a disk mesh to a
// flat metric whose boundary is a rectangle, and its embedding in the unit square
// (paper section 3.1, "Conformal Initialization", Eq. 1-2).
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/disk_topology.h"

#include <glm/vec2.hpp>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace ngi {

struct RicciFlowOptions {
    double tolerance = 1e-9;  // stop when max_i |Kbar_i - K_i| < tolerance (radians)
    int maxIterations = 100;  // Newton iterations
    int maxHalvings = 40;     // step halvings per iteration before giving up
    std::function<void(const std::string&)> progress;
};

struct RicciFlowResult {
    std::vector<double> u;  // conformal factor per vertex: l_ij = exp((u_i + u_j) / 2) L_ij
    int iterations = 0;
    double residual = 0.0;           // max |Kbar - K| at the end (radians)
    double aspect = 1.0;             // width / height of the flat rectangle before the squash
    size_t degenerateTriangles = 0;  // triangles of the final metric violating a triangle inequality
    std::vector<glm::dvec2> uv;      // the flat metric embedded in the unit square (see below)
};

// Runs the flow with target geodesic curvature pi/2 at the four corners (boundaryLoop
// positions `cornerPositions`), 0 on the rest of the boundary and Gaussian curvature 0 inside,
// then embeds the flat metric: the boundary is a rectangle W x H, placed on the square with
// the affine squash (x / W, y / H) (angles are exact only when W = H), and the interior is the
// harmonic extension under the flat metric's cotangent weights, which reproduces the flat
// layout exactly (linear functions are discrete-harmonic on a flat mesh) without the error
// accumulation of a triangle-by-triangle layout.
// Triangles whose target metric violates a triangle inequality are degenerate (convex
// extension, see ricci_flow.cpp) and counted; `uv` can then have flipped triangles.
// Throws ngi::Error if Newton's method does not reach `tolerance` in `maxIterations` or no
// step decreases the curvature error (message has the iteration and residual).
RicciFlowResult ricciFlowToSquare(const DiskMesh& disk, const DiskTopology& topology,
                                  const std::array<size_t, 4>& cornerPositions, const RicciFlowOptions& options = {});

}  // namespace ngi
