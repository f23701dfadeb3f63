// ngi offline eval: the drawn mesh of an asset as a textured mesh, so that it can be exported
// (glTF) and measured (colour distance) like any textured input. Each chart's base colour
// image (AssetChart::baseColor, sampled by the grid uv) becomes a glTF texture of S x S
// texels, and each vertex's chart uv the texture coordinate that samples that texture where
// the engine samples the image.
#pragma once

#include "ngi/asset.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/mesh/appearance.h"

#include <glm/vec2.hpp>

#include <cstdint>

namespace ngi {

// The glTF texture coordinate of grid uv `gridUV` in [0, 1]^2 for a chart image of `size`
// texels per side: (gridUV (size - 1) + 0.5) / size. A grid uv addresses texel centres (uv 0
// is texel 0's centre, uv 1 texel size - 1's), glTF's texture coordinates the texels' edges
// (0 is texel 0's outer edge), so a bilinear lookup at the result reads texel coordinates
// gridUV (size - 1), as the engine does. size >= 2 (a chart image has at least 2 texels per side).
glm::dvec2 chartTextureCoordinate(glm::dvec2 gridUV, uint32_t size);

// The appearance of `drawn` (assetMesh(asset, ...)): per corner, the chart texture coordinate
// of its vertex's chart uv (chartTextureCoordinate with the chart's baseColorSize()); one
// material per chart that has a base colour, named "chart C", whose base colour texture is
// that chart's image (8-bit sRGB RGBA as stored, named "chart C base colour", clamp-to-edge),
// factor 1, a dielectric (metallic 0, roughness 1: the asset carries base colour only),
// opaque unless a texel's alpha is below 255 (then Blend); and one material "default" (white
// dielectric) for every chart without one. triangleMaterial gives each triangle its chart's
// material. An asset none of whose charts has a base colour gives an empty appearance.
// Throws ngi::Error if `drawn` does not hold its per-vertex uvs and per-triangle charts (an
// AssetMesh not made by assetMesh) or names a chart `asset` lacks, or a chart's base colour
// is not baseColorSize()^2 x 4 bytes.
MeshAppearance assetMeshAppearance(const Asset& asset, const AssetMesh& drawn);

}  // namespace ngi
