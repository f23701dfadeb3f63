// ngi core: geometry images of analytic surfaces, sampled exactly (tests, benchmarks, and
// the default asset until a baked real mesh replaces it).
#pragma once

#include "ngi/asset.h"
#include "ngi/geometry_image.h"
#include "ngi/seam.h"

#include <cstdint>
#include <string>

namespace ngi {

struct AnalyticSurface {
    GeometryImage positions;  // normalized: the surface fits [0,1]^3
    GeometryImage normals;    // unit, outward
    ChartSeams seams;         // its mates in closed form (both images welded), seam.h
};

// The sphere of centre (0.5, 0.5, 0.5) and radius 0.5 through the octahedral map of Praun
// and Hoppe 2003 ("Spherical Parametrization and Remeshing"): the square's border folds onto
// four arcs, mirrored seam mates ((x, 0) <-> (R - x, 0) on each side). `size` samples per side.
AnalyticSurface sphereGeometryImage(uint32_t size);

// A rippled torus (major radius 1, tube radius 0.35 modulated by `ripple` * sin(5u) sin(3v)),
// u and v periodic across the square's border (mates (x, 0) <-> (x, R), (0, y) <-> (R, y)),
// normalized into [0,1]^3.
AnalyticSurface rippledTorusGeometryImage(uint32_t size, float ripple = 0.06f);

// An asset holding `surface`'s level `storedLevel` (surface.size must be 2^k + 1).
// Offset/scale are the identity (the surface is already normalized); the chart keeps the
// surface's seams.
Asset makeAnalyticAsset(const std::string& name, const AnalyticSurface& surface, uint32_t storedLevel);

}  // namespace ngi
