// ngi offline: rasterizes a mapped disk mesh into a geometry image (paper section 4,
// "Implementation Details"): positions and normals interpolated barycentrically over the uv
// triangulation; samples outside every triangle filled from the nearest boundary.
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <span>

namespace ngi {

struct RasterizedGeometryImage {
    GeometryImage positions;         // object-space positions (not normalized)
    GeometryImage normals;           // unit normals (vertex normals of the uncut mesh, so seam mates agree)
    size_t extrapolatedSamples = 0;  // samples outside every uv triangle, filled from the nearest boundary point
};

// Samples `disk` at (resolution + 1)^2 points, sample (x, y) at uv = (x, y) / resolution.
// `uv` has one entry per disk vertex. Each sample takes the barycentric interpolation of the
// positions and of the area-weighted vertex normals (accumulated over `originalVertex`, so
// seam mates share one normal) of the uv triangle containing it; a sample in no triangle
// takes the values at the closest point of the uv boundary loop. Throws ngi::Error on size
// mismatch, resolution 0 or non-finite uv.
RasterizedGeometryImage rasterizeGeometryImage(const DiskMesh& disk, std::span<const glm::dvec2> uv,
                                               uint32_t resolution);

}  // namespace ngi
