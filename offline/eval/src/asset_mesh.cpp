// ngi offline eval: the mesh the renderer draws for an asset (core's lod_grid.h definition),
// restored by bilinear or bicubic upsampling or by the super-resolution network, de-normalized.
#include "ngi/eval/asset_mesh.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/reference_forward.h"

#include <algorithm>
#include <bit>

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

namespace {

// Keys cubic convolution kernel weights for fractional offset t with a = -1/2 (Catmull-Rom),
// the only a for which the interpolation is third-order accurate (Keys 1981); PyTorch's
// a = -0.75 does not reproduce linear functions and measured worse than bilinear on every
// development geometry image.
std::array<double, 4> cubicWeights(double t)
{
    constexpr double a = -0.5;
    auto near = [](double x) { return ((a + 2.0) * x - (a + 3.0)) * x * x + 1.0; };          // |x| <= 1
    auto far = [](double x) { return ((a * x - 5.0 * a) * x + 8.0 * a) * x - 4.0 * a; };     // 1 < |x| < 2
    return {far(t + 1.0), near(t), near(1.0 - t), far(2.0 - t)};
}

// Bicubic upsampling by `factor` of a nested grid: fine sample X sits at coarse coordinate
// X / factor (coarse samples are reproduced exactly); indices clamped at the border.
GeometryImage upsampleBicubic(const GeometryImage& coarse, uint32_t factor)
{
    const uint32_t n = coarse.size, m = (n - 1) * factor + 1;
    auto clampIndex = [n](int64_t i) { return uint32_t(std::clamp<int64_t>(i, 0, int64_t(n) - 1)); };
    // Rows first (n rows x m columns), then columns.
    std::vector<glm::dvec3> rows(size_t(n) * m);
    for (uint32_t x = 0; x < m; ++x) {
        const int64_t x0 = x / factor;
        const std::array<double, 4> w = cubicWeights(double(x % factor) / factor);
        for (uint32_t y = 0; y < n; ++y) {
            glm::dvec3 sum(0.0);
            for (int k = 0; k < 4; ++k) sum += w[k] * glm::dvec3(coarse.texels[size_t(y) * n + clampIndex(x0 - 1 + k)]);
            rows[size_t(y) * m + x] = sum;
        }
    }
    GeometryImage fine(m);
    for (uint32_t y = 0; y < m; ++y) {
        const int64_t y0 = y / factor;
        const std::array<double, 4> w = cubicWeights(double(y % factor) / factor);
        for (uint32_t x = 0; x < m; ++x) {
            glm::dvec3 sum(0.0);
            for (int k = 0; k < 4; ++k) sum += w[k] * rows[size_t(clampIndex(y0 - 1 + k)) * m + x];
            fine.texels[size_t(y) * m + x] = glm::vec3(sum);
        }
    }
    return fine;
}

} // namespace

RestoredImages restoreFullResolution(const Asset& asset, AssetRestore restore, const NetworkWeights* network)
{
    RestoredImages images{storedPositions(asset), storedNormals(asset)};
    const GeometryImage stored = images.positions;
    for (uint32_t level = asset.storedLevel; level > 0; --level) {
        images.positions = upsampleNested(images.positions, false);
        images.normals = upsampleNested(images.normals, true);
    }
    const uint32_t factor = 1u << asset.storedLevel;
    if (restore == AssetRestore::Bicubic && factor > 1) images.positions = upsampleBicubic(stored, factor);
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
                                                             nn::featureMapFromGeometryImage(storedNormals(asset)));
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
