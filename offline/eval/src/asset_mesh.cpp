// ngi offline eval: the mesh the renderer draws for an asset (core's lod_grid.h definition),
// restored by bilinear or bicubic upsampling or by the super-resolution network, de-normalized.
#include "ngi/eval/asset_mesh.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/stored_level.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace ngi {

SurfacePyramid restoredPyramidWithoutSR(const Asset& asset)
{
    const RestoredImages restored = restoreFullResolution(asset, AssetRestore::Bilinear);
    return buildSurfacePyramid(restored.positions, restored.normals);
}

RestoredImages restoreFullResolution(const Asset& asset, AssetRestore restore, const NetworkWeights* network)
{
    const GeometryImage stored = storedPositions(asset), storedNormalImage = storedNormals(asset);
    RestoredImages images{stored, storedNormalImage};
    // Normals: bilinear for every method; positions: bilinear only when asked.
    for (uint32_t level = asset.storedLevel; level > 0; --level) {
        if (restore == AssetRestore::Bilinear) images.positions = upsampleNested(images.positions, false);
        images.normals = upsampleNested(images.normals, true);
    }
    const uint32_t factor = restoreFactor(asset.storedLevel);
    if (restore == AssetRestore::Bicubic && factor > 1) {
        // Exactly the network's CubicSkip with a zero residual (one definition of the cubic).
        const nn::FeatureMap coarse = nn::featureMapFromGeometryImage(stored);
        const nn::FeatureMap zero(3, images.normals.size, images.normals.size);
        images.positions = nn::geometryImageFromFeatureMap(nn::cubicSkip(coarse, zero, factor));
    }
    if (restore == AssetRestore::Network) {
        NetworkWeights own;
        if (!network) {
            if (asset.weights.empty())
                throw Error("super-resolution restore needs a network: the asset has no WGHT chunk (give --weights NET.ngiw)");
            own = parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
            network = &own;
        }
        if (network->scaleFactor != factor)
            throw Error("the network '" + network->name + "' upsamples x" + std::to_string(network->scaleFactor) +
                        " but the asset stores level " + std::to_string(asset.storedLevel) + " (needs x" +
                        std::to_string(factor) + ")");
        const nn::FeatureMap restored = nn::referenceForward(*network, nn::featureMapFromGeometryImage(stored),
                                                             nn::featureMapFromGeometryImage(storedNormalImage));
        images.positions = nn::geometryImageFromFeatureMap(restored);
    }
    return images;
}

AssetMesh assetMesh(const Asset& asset, const AssetMeshOptions& options)
{
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

    const RestoredImages restored = restoreFullResolution(asset, options.restore, options.network);
    const SurfacePyramid pyramid = buildSurfacePyramid(restored.positions, restored.normals);
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
