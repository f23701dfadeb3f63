// ngi offline eval: the mesh the renderer draws for an asset (core's lod_grid.h definition),
// restored by bilinear or bicubic upsampling or by the super-resolution network, de-normalized.
#include "ngi/eval/asset_mesh.h"

#include "ngi/compact_texel.h"
#include "ngi/error.h"
#include "ngi/fitted_levels.h"
#include "ngi/mip_pyramid.h"
#include "ngi/network_catalog.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/stored_level.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <string>

namespace ngi {

SurfacePyramid restoredPyramidWithoutSR(const Asset& asset, size_t chart)
{
    const RestoredImages restored = restoreFullResolution(asset, AssetRestore::Bilinear, nullptr, chart);
    return buildSurfacePyramid(restored.positions, restored.normals);
}

RestoredImages restoreFullResolution(const Asset& asset, AssetRestore restore, const NetworkWeights* network,
                                     size_t chartIndex)
{
    if (chartIndex >= asset.charts.size())
        throw Error("the asset has " + std::to_string(asset.charts.size()) + " charts, not " +
                    std::to_string(chartIndex + 1));
    const AssetChart& chart = asset.charts[chartIndex];
    const GeometryImage stored = storedPositions(chart), storedNormalImage = storedNormals(chart);
    RestoredImages images{stored, storedNormalImage};
    // Mates made bitwise equal after every restored level the seam is aligned to (seam.h), as
    // the engine's seam_weld.comp does.
    auto weldTable = [&](uint32_t level) {
        return chart.seams.matched && level <= chart.seams.coarsestWatertightLevel
            ? seamWeldTable(chart.seams, chart.fullResolution, level)
            : std::vector<uint32_t>();
    };
    auto weld = [](GeometryImage& image, const std::vector<uint32_t>& table) {
        if (!table.empty()) weldSeams(image, table);
    };
    // Normals: bilinear for every method; positions: bilinear only when asked.
    for (uint32_t level = chart.storedLevel; level > 0; --level) {
        const std::vector<uint32_t> table = weldTable(level - 1);
        if (restore == AssetRestore::Bilinear) {
            images.positions = upsampleNested(images.positions, false);
            weld(images.positions, table);
        }
        images.normals = upsampleNested(images.normals, true);
        weld(images.normals, table);
    }
    const uint32_t factor = restoreFactor(chart.storedLevel);
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
                throw Error(
                    "super-resolution restore needs a network: the asset has no WGHT chunk (give --weights NET.ngiw)");
            own = parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
            network = &own;
        }
        if (network->scaleFactor != factor)
            throw Error("the network '" + network->name + "' upsamples x" + std::to_string(network->scaleFactor) +
                        " but the asset stores level " + std::to_string(chart.storedLevel) + " (needs x" +
                        std::to_string(factor) + ")");
        // s + alpha r with the chart's residual gain (1 before format 6: the network as trained).
        const nn::FeatureMap restored =
            nn::referenceForward(*network, nn::featureMapFromGeometryImage(stored),
                                 nn::featureMapFromGeometryImage(storedNormalImage), chart.residualGain);
        images.positions = nn::geometryImageFromFeatureMap(restored);
    }
    if (restore != AssetRestore::Bilinear) weld(images.positions, weldTable(0));
    return images;
}

std::vector<RestoredImages> restoreAsset(const Asset& asset, AssetRestore restore, const NetworkWeights* network)
{
    if (asset.charts.empty()) throw Error("the asset has no chart");
    // One network per asset: it restores the charts of its factor, the others are restored
    // bicubically (its skip without a residual); a network that restores no chart is the
    // first chart's error (restoreFullResolution).
    NetworkWeights own;
    if (restore == AssetRestore::Network && !network && !asset.weights.empty()) {
        own = parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
        network = &own;
    }
    std::vector<AssetRestore> restores(asset.charts.size(), restore);
    if (network && restore == AssetRestore::Network) {
        bool any = false;
        for (size_t c = 0; c < asset.charts.size(); ++c)
            if (!networkRestoresChart(*network, asset.charts[c]))
                restores[c] = AssetRestore::Bicubic;
            else
                any = true;
        if (!any) restores.assign(asset.charts.size(), AssetRestore::Network);
    }
    std::vector<RestoredImages> restored;
    for (size_t c = 0; c < asset.charts.size(); ++c)
        restored.push_back(restoreFullResolution(asset, restores[c], network, c));
    // Charts of a split component: their shared curves made bitwise equal at the full level;
    // every coarser level is its even samples, so it stays equal there (format 7, seam.h).
    if (!asset.crossSeams.empty()) {
        std::vector<GeometryImage*> positions, normals;
        std::vector<ChartSeams> seams;
        std::vector<uint32_t> resolutions;
        for (size_t c = 0; c < asset.charts.size(); ++c) {
            positions.push_back(&restored[c].positions);
            normals.push_back(&restored[c].normals);
            seams.push_back(asset.charts[c].seams);
            resolutions.push_back(asset.charts[c].fullResolution);
        }
        weldGroupSeams(positions, seams, resolutions, asset.crossSeams, 0);
        weldGroupSeams(normals, seams, resolutions, asset.crossSeams, 0);
    }
    return restored;
}

AdaptiveAsset buildAdaptiveAsset(const Asset& asset, const std::vector<RestoredImages>& restored, bool fittedLevels)
{
    if (restored.size() != asset.charts.size())
        throw Error("internal: " + std::to_string(restored.size()) + " restored images for " +
                    std::to_string(asset.charts.size()) + " charts");
    AdaptiveAsset adaptive;
    adaptive.pyramids.reserve(asset.charts.size());
    adaptive.trees.reserve(asset.charts.size());
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        const AssetChart& chart = asset.charts[c];
        SurfacePyramid& pyramid =
            adaptive.pyramids.emplace_back(buildSurfacePyramid(restored[c].positions, restored[c].normals));
        if (fittedLevels) fitCoarseLevels(pyramid);
        // As the engine keeps them (compact_texel.h): the mesh is exactly the one it draws.
        for (uint32_t l = 0; l < pyramid.levelCount(); ++l) makeLevelCompact(pyramid.positions[l], pyramid.normals[l]);
        const uint32_t coarsest = chart.coarsestDrawnLevel();
        adaptive.trees.push_back(
            buildTileTree(pyramid, coarsest, chart.seams.matched ? chart.seams.coarsestWatertightLevel : coarsest));
    }
    for (size_t c = 0; c < asset.charts.size(); ++c)
        adaptive.charts.push_back({&adaptive.pyramids[c], &adaptive.trees[c], asset.charts[c].seams});
    adaptive.mates = buildSurfaceMates(adaptive.charts, asset.crossSeams);
    return adaptive;
}

AssetMesh assetMesh(const Asset& asset, const AssetMeshOptions& options)
{
    if (asset.charts.empty()) throw Error("the asset has no chart");
    const uint32_t fullSize = asset.fullResolution() + 1;
    // The levels drawn: down to the largest chart's coarsest watertight level (seam.h).
    const uint32_t levelCount = asset.charts.front().coarsestDrawnLevel() + 1;
    const float maxLod = float(levelCount - 1);
    if (!options.gridSize && (!std::isfinite(options.lod) || options.lod < 0.0f || options.lod > maxLod)) {
        char text[128];
        std::snprintf(text, sizeof text, "LoD %g is outside [0, %u] (this asset draws %u levels%s)",
                      double(options.lod), levelCount - 1, levelCount,
                      levelCount < mipLevelCount(fullSize) ? "; coarser ones would open its seams" : "");
        throw Error(text);
    }
    if (options.gridSize && (*options.gridSize < 2 || *options.gridSize > fullSize))
        throw Error("grid size " + std::to_string(*options.gridSize) + " is outside [2, " + std::to_string(fullSize) +
                    "]");

    AssetMesh result;
    result.levelCount = levelCount;
    const glm::dvec3 offset(asset.offset), scale(asset.scale);
    const std::vector<RestoredImages> restored = restoreAsset(asset, options.restore, options.network);
    // `gridSize`: vertices per side of a grid mesh (its uvs are not stored), 0 for an adaptive one.
    auto append = [&](const LodMesh& drawn, uint32_t chart, uint32_t gridSize) {
        const uint32_t base = uint32_t(result.mesh.positions.size());
        for (const glm::vec3& p : drawn.positions) result.mesh.positions.push_back(offset + scale * glm::dvec3(p));
        // Normals transform by the inverse transpose of the de-normalization (a diagonal scale).
        for (const glm::vec3& n : drawn.normals) {
            const glm::dvec3 m = glm::dvec3(n) / scale;
            const double length = glm::length(m);
            result.normals.push_back(length > 0.0 ? m / length : glm::dvec3(0.0, 0.0, 1.0));
        }
        if (gridSize != 0 && size_t(gridSize) * gridSize != drawn.positions.size())
            throw Error("internal: a drawn grid of " + std::to_string(drawn.positions.size()) + " vertices is not " +
                        std::to_string(gridSize) + " x " + std::to_string(gridSize));
        if (gridSize == 0)
            for (const glm::vec2& uv : drawn.uvs) result.chartUVs.push_back(glm::dvec2(uv));
        else
            for (uint32_t j = 0; j < gridSize; ++j)
                for (uint32_t i = 0; i < gridSize; ++i)
                    result.chartUVs.push_back(glm::dvec2(i, j) / double(gridSize - 1));
        for (const glm::uvec3& t : drawn.triangles) result.mesh.triangles.push_back(t + glm::uvec3(base));
        result.triangleChart.insert(result.triangleChart.end(), drawn.triangles.size(), chart);
    };
    if (options.adaptive) {
        validateAdaptiveView(*options.adaptive);
        const AdaptiveAsset adaptive = buildAdaptiveAsset(asset, restored, options.fittedLevels);
        const std::vector<AdaptiveChart>& charts = adaptive.charts;
        const SurfaceMates& mates = adaptive.mates;
        TileSelection selection = selectTiles(charts, mates, *options.adaptive);
        for (uint32_t c = 0; c < charts.size(); ++c) append(buildAdaptiveMesh(charts, mates, selection, c, true), c, 0);
        selection.perimeterStates.clear();
        selection.cover.clear();
        result.adaptive = std::move(selection);
        return result;
    }
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        const AssetChart& chart = asset.charts[c];
        const SurfacePyramid pyramid = buildSurfacePyramid(restored[c].positions, restored[c].normals);
        // One LoD for the asset: each chart at the same sample density (asset.h).
        const int shift = std::countr_zero(asset.fullResolution()) - std::countr_zero(chart.fullResolution);
        LodMesh drawn;
        LodSelection selection;
        if (options.gridSize) {
            const uint32_t n = std::max(2u, ((*options.gridSize - 1) >> shift) + 1);
            drawn = buildGridMesh(pyramid, n);
            selection.level = levelForGridSize(pyramid.fullSize(), n);
            selection.gridSize = n;
        } else {
            // The same level index as the largest chart (chartLevelForAssetLevel), clamped.
            const float lod = std::clamp(options.lod, 0.0f, float(chart.coarsestDrawnLevel()));
            drawn = buildLodMesh(pyramid, lod);
            selection = selectLod(chart.coarsestDrawnLevel() + 1, pyramid.fullSize(), lod);
        }
        if (c == 0) result.selection = selection;
        append(drawn, uint32_t(c), selection.gridSize);
    }
    return result;
}

AdaptiveView assetAdaptiveView(const Asset& asset, glm::vec3 eye, glm::vec3 lookAt, float fovDegrees, uint32_t width,
                               uint32_t height, float maxErrorPixels)
{
    const glm::vec3 forward = lookAt - eye;
    if (!(glm::length(forward) > 0.0f)) throw Error("the camera's eye and look-at point are the same");
    if (!(fovDegrees > 0.0f && fovDegrees < 180.0f)) throw Error("the field of view must be in (0, 180) degrees");
    if (width == 0 || height == 0) throw Error("the viewport must be at least 1 x 1 pixels");
    const glm::vec3 dir = glm::normalize(forward);
    const glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const float extent = glm::length(forward) + 2.0f * std::max({asset.scale.x, asset.scale.y, asset.scale.z});
    glm::mat4 projection =
        glm::perspectiveRH_ZO(glm::radians(fovDegrees), float(width) / float(height), extent * 1e-4f, extent * 4.0f);
    projection[1][1] *= -1.0f;  // Vulkan's y points down
    const glm::mat4 objectFromNormalized = glm::scale(glm::translate(glm::mat4(1.0f), asset.offset), asset.scale);
    AdaptiveView view;
    view.camera = true;
    view.clipFromNormalized = projection * glm::lookAtRH(eye, lookAt, up) * objectFromNormalized;
    view.eye = (eye - asset.offset) / asset.scale;
    view.viewportHeight = float(height);
    view.maxErrorPixels = maxErrorPixels;
    view.cull = true;
    validateAdaptiveView(view);
    return view;
}

}  // namespace ngi
