// ngi offline eval: the mesh the renderer draws for an asset (core's lod_grid.h definition),
// restored without the super-resolution network and de-normalized.
#include "ngi/eval/asset_mesh.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace ngi {

SurfacePyramid restoredPyramidWithoutSR(const Asset& asset)
{
    GeometryImage positions = storedPositions(asset), normals = storedNormals(asset);
    for (uint32_t level = asset.storedLevel; level > 0; --level) {
        positions = upsampleNested(positions, false);
        normals = upsampleNested(normals, true);
    }
    return buildSurfacePyramid(positions, normals);
}

AssetMesh assetMesh(const Asset& asset, const AssetMeshOptions& options)
{
    if (options.superResolution)
        throw Error("super-resolution restore is not available yet (no trained network): "
                    "use the bilinear restore (--no-sr)");
    const uint32_t levelCount = mipLevelCount(asset.fullSize());
    const float maxLod = float(levelCount - 1);
    if (!options.gridSize && (!std::isfinite(options.lod) || options.lod < 0.0f ||
                              options.lod > maxLod)) {
        char text[128];
        std::snprintf(text, sizeof text, "LoD %g is outside [0, %u] (this asset has %u levels)",
                      double(options.lod), levelCount - 1, levelCount);
        throw Error(text);
    }
    if (options.gridSize && (*options.gridSize < 2 || *options.gridSize > asset.fullSize()))
        throw Error("grid size " + std::to_string(*options.gridSize) + " is outside [2, " +
                    std::to_string(asset.fullSize()) + "]");

    const SurfacePyramid pyramid = restoredPyramidWithoutSR(asset);
    AssetMesh result;
    result.levelCount = pyramid.levelCount();
    LodMesh drawn;
    if (options.gridSize) {
        drawn = buildGridMesh(pyramid, *options.gridSize);
        result.selection.level = levelForGridSize(pyramid.fullSize(), *options.gridSize);
        result.selection.gridSize = *options.gridSize;
    } else {
        drawn = buildLodMesh(pyramid, options.lod);
        result.selection = selectLod(pyramid.levelCount(), pyramid.fullSize(), options.lod);
    }
    const glm::dvec3 offset(asset.offset), scale(asset.scale);
    result.mesh.positions.reserve(drawn.positions.size());
    for (const glm::vec3& p : drawn.positions)
        result.mesh.positions.push_back(offset + scale * glm::dvec3(p));
    result.mesh.triangles = std::move(drawn.triangles);
    return result;
}

} // namespace ngi
