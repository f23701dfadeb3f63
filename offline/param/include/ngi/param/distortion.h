// ngi offline: distortion of a uv map against the 3D surface (the statistics of ngi-bake's
// JSON summary and of the paper's Table 1 comparison).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec2.hpp>

#include <vector>

namespace ngi {

struct MapDistortion {
    double areaMax = 0.0;    // max over triangles of |log(uv area / 3D area)|, areas normalized to total 1
    double areaMean = 0.0;   // the same, weighted by 3D area
    double angleMax = 0.0;   // max over triangle corners of |uv angle - 3D angle| (radians)
    double angleMean = 0.0;  // mean over corners
    size_t flipped = 0;      // triangles with uv area <= 0 (left out of the statistics above)
};

// Measures `uv` (one per vertex) over `mesh`. Flipped triangles only count in `flipped`.
MapDistortion measureDistortion(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv);

// The 3D area around each vertex: a third of the area of each incident triangle.
std::vector<double> vertexAreas(const TriangleMesh& mesh);

}  // namespace ngi
