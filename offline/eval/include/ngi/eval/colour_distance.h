// ngi offline eval: the colour error of a candidate surface against a reference, in the
// spirit of the attribute metric of MPEG's point cloud compression common test conditions
// (the pc_error tool: each point's colour against its nearest neighbour's in the other cloud,
// as PSNR of Y, Cb and Cr from 8-bit values, BT.709; MPEG's mesh metric applies it to meshes
// by sampling their surfaces). Here the reference surface is sampled uniformly by area
// (sampleSurfacePoints, the fixed seed of the geometric distance), each sample's colour is
// the reference's base colour there (SurfaceColor), and it is compared with the candidate's
// base colour at the closest point of the candidate's surface (CGAL AABB tree, as
// surface_distance.h). One-sided: reference samples against the candidate's surface.
//
//   colour     SurfaceColor::baseColor (linear RGB; alpha is not compared), footprint = the
//              sample spacing sqrt(reference area / samples), encoded as sRGB and rounded to
//              8-bit values R, G, B in 0..255
//   YCbCr      BT.709, full range: Y = 0.2126 R + 0.7152 G + 0.0722 B,
//              Cb = (B - Y) / 1.8556 + 128, Cr = (R - Y) / 1.5748 + 128
//   PSNR       10 log10(255^2 / MSE) per channel, MSE over the samples; +infinity when MSE = 0
#pragma once

#include "ngi/eval/surface_distance.h"
#include "ngi/mesh/appearance.h"
#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>

namespace ngi {

struct ColourDistanceOptions {
    uint32_t sampleCount = 200000;                  // reference samples (docs/DESIGN.md: 200,000)
    uint64_t seed = SurfaceDistanceOptions{}.seed;  // the geometric distance's fixed seed
    unsigned threadCount = 2;                       // closest-point queries run on this many threads
};

struct ColourDistance {
    double psnrY = 0.0, psnrCb = 0.0, psnrCr = 0.0;  // dB; +infinity where the MSE is 0
    double mseY = 0.0, mseCb = 0.0, mseCr = 0.0;     // mean squared error, in squared 8-bit units
    double footprint = 0.0;                          // side of the square each sample stands for, reference units
    uint32_t sampleCount = 0;
};

// BT.709 full-range Y, Cb, Cr of 8-bit sRGB values `rgb` (each in [0, 255]), as above.
glm::dvec3 ycbcrBt709(const glm::dvec3& rgb);

// PSNR of a mean squared error on 8-bit values: 10 log10(255^2 / mse); +infinity for 0.
double psnr8(double mse);

// The colour error of `candidate` (with `candidateAppearance`) against `reference` (with
// `referenceAppearance`), as defined above. Each appearance is read as SurfaceColor reads it
// (an empty one is the default white material); a base colour texture's transform
// (KHR_texture_transform) is applied to the texture coordinates first, so that the texel
// density that sets the mip level is the transformed one. Deterministic for given options,
// whatever the thread count. Triangles of zero area are left out of the candidate's tree.
// Throws ngi::Error (naming "reference mesh" or "candidate mesh") on an empty mesh, an index
// out of range, a non-finite coordinate, zero total area, an appearance that does not match its
// mesh (SurfaceColor's errors), or sampleCount == 0.
ColourDistance colourDistance(const TriangleMesh& reference, const MeshAppearance& referenceAppearance,
                              const TriangleMesh& candidate, const MeshAppearance& candidateAppearance,
                              const ColourDistanceOptions& options = {});

}  // namespace ngi
