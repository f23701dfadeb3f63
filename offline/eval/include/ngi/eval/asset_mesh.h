// ngi offline eval: the triangle mesh the renderer draws for an asset, in the input mesh's
// original coordinates, so it can be measured (CD/HD) and exported. The grid, the diagonal
// choice and the geomorph are core's one definition (ngi/lod_grid.h, mirrored by
// shaders/surface.vert); this file only restores the full-resolution image the way the
// engine does and de-normalizes.
#pragma once

#include "ngi/asset.h"
#include "ngi/lod_grid.h"
#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <optional>

namespace ngi {

struct AssetMeshOptions {
    float lod = 0.0f;                  // continuous LoD in [0, levelCount - 1], 0 = full
    std::optional<uint32_t> gridSize;  // instead of lod: a fixed N x N grid (ngi-render --grid)
    bool superResolution = false;      // restore with the SR network (not available yet)
};

struct AssetMesh {
    TriangleMesh mesh;          // object space: offset + scale * normalized position
    LodSelection selection;     // level, morph and grid size drawn
    uint32_t levelCount = 0;    // levels of the restored pyramid (max LoD = levelCount - 1)
};

// The full-resolution restored pyramid of `asset` without the network: the stored level
// upsampled level by level with upsampleNested (bilinear; what the engine's
// mip_upsample.comp does), then its nested mip chain.
SurfacePyramid restoredPyramidWithoutSR(const Asset& asset);

// The mesh drawn for `asset` at options.lod (or options.gridSize): exactly buildLodMesh
// (buildGridMesh) of the restored pyramid, de-normalized. Its triangle count is
// gridTriangleCount(selection.gridSize). Throws ngi::Error if superResolution is asked (the
// network does not exist yet), if lod is not finite or outside [0, levelCount - 1], or if
// gridSize is outside [2, full size].
AssetMesh assetMesh(const Asset& asset, const AssetMeshOptions& options = {});

} // namespace ngi
