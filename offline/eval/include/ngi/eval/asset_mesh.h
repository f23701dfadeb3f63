// ngi offline eval: the triangle mesh the renderer draws for an asset, in the input mesh's
// original coordinates, so it can be measured (CD/HD) and exported. The grid, the diagonal
// choice and the geomorph are core's one definition (ngi/lod_grid.h, mirrored by
// shaders/surface.vert); this file only restores the full-resolution image the way the
// engine does and de-normalizes.
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/asset.h"
#include "ngi/geometry_image.h"
#include "ngi/lod_grid.h"
#include "ngi/network_weights.h"
#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace ngi {

// How the full-resolution image is restored from the stored level.
//   Bilinear: upsampleNested level by level (the engine's mip_upsample.comp, ngi-render --no-sr);
//   Bicubic:  Catmull-Rom cubic convolution (Keys 1981, a = -1/2, third-order accurate) in one
//             step of factor 2^storedLevel: the network's CubicSkip with a zero residual
//             (ngi/network_weights.h), a comparison baseline;
//   Network:  the super-resolution network by its C++ reference forward (reference_forward.h)
//             with the chart's residual gain (skip + residualGain x residual, ngi/asset.h),
//             the specification the engine's GLSL matches within 1e-4 on the [0,1] position
//             scale for the whole network, 1e-5 per op (tests/engine/sr_network_test.cpp,
//             sr_ops_test.cpp).
enum class AssetRestore { Bilinear, Bicubic, Network };

struct AssetMeshOptions {
    float lod = 0.0f;                  // continuous LoD in [0, levelCount - 1], 0 = full
    std::optional<uint32_t> gridSize;  // instead of lod: a fixed N x N grid (ngi-render --grid)
    // Instead of lod and gridSize: the adaptive surface (ngi/adaptive_lod.h) for this view, in
    // the asset's normalized space (assetAdaptiveView builds one from object-space inputs).
    std::optional<AdaptiveView> adaptive;
    // The adaptive surface's coarse levels: fitted to the full surface (fitted_levels.h), as
    // the engine's AdaptiveSurface draws them, or the nested subsamples (for comparisons).
    // Either way every level is then made compact (compact_texel.h) as the engine keeps it.
    bool fittedLevels = true;
    AssetRestore restore = AssetRestore::Bilinear;
    // Network restore: these weights, or (null) the asset's own WGHT chunk.
    const NetworkWeights* network = nullptr;
};

// The full-resolution position and normal images of chart `chart` of `asset` restored by
// `restore`. Normals are the stored normals interpolated, bilinearly for every method
// (upsampleNested, renormalized); the engine does the same on its bilinear path and
// interpolates them by Catmull-Rom on its network path (shaders/sr_output.comp). Neither
// derives them from the restored positions, and the measured mesh (assetMesh) carries
// positions only.
// Throws ngi::Error for a chart the asset does not have, for Network without weights (none
// given, no WGHT chunk) or with a network whose scale factor is not 2^storedLevel.
struct RestoredImages {
    GeometryImage positions, normals;
};
RestoredImages restoreFullResolution(const Asset& asset, AssetRestore restore, const NetworkWeights* network = nullptr,
                                     size_t chart = 0);

struct AssetMesh {
    TriangleMesh mesh;                    // object space, every chart (largest first, vertices not welded)
    std::vector<glm::dvec3> normals;      // per vertex: the drawn normal, object space, unit
    std::vector<glm::dvec2> chartUVs;     // per vertex: its chart's grid uv in [0, 1]^2 (x right, y down the image)
    std::vector<uint32_t> triangleChart;  // per triangle: the index of its chart in asset.charts
    LodSelection selection;               // level, morph and grid size drawn for the largest chart
    uint32_t levelCount = 0;              // levels of the largest chart (max LoD = levelCount - 1)
    // Adaptive meshes: the selection (its tiles and figures; the border states are dropped).
    std::optional<TileSelection> adaptive;
};

// Every chart of `asset` restored to its full resolution by `restore` (restoreFullResolution;
// with Network, charts whose stored level the network's factor does not take to their full
// size are restored Bicubic, one network per asset), the curves charts of a split component
// share welded bitwise equal. `network`: these weights, or (null) the asset's WGHT chunk.
// Throws ngi::Error as restoreFullResolution does, and for an asset without charts.
std::vector<RestoredImages> restoreAsset(const Asset& asset, AssetRestore restore,
                                         const NetworkWeights* network = nullptr);

// The adaptive surface of an asset on the CPU, as the engine's AdaptiveSurface keeps it: per
// chart its restored pyramid (coarse levels fitted, every level compact), its tile tree, and
// the seam mates. `charts` points into `pyramids` and `trees`: move it, never copy it.
struct AdaptiveAsset {
    std::vector<SurfacePyramid> pyramids;
    std::vector<TileTree> trees;
    std::vector<AdaptiveChart> charts;
    SurfaceMates mates;
    AdaptiveAsset() = default;
    AdaptiveAsset(AdaptiveAsset&&) = default;
    AdaptiveAsset& operator=(AdaptiveAsset&&) = default;
    AdaptiveAsset(const AdaptiveAsset&) = delete;
    AdaptiveAsset& operator=(const AdaptiveAsset&) = delete;
};
// Builds it from restoreAsset's images. `fittedLevels`: fit the coarse levels to the full
// surface (fitted_levels.h, what the engine draws), else keep the nested subsamples.
// ngi::Error if `restored` does not hold one image pair per chart, or as buildTileTree and
// buildSurfaceMates.
AdaptiveAsset buildAdaptiveAsset(const Asset& asset, const std::vector<RestoredImages>& restored,
                                 bool fittedLevels = true);

// An adaptive camera view for `asset` from object-space inputs (the input mesh's
// coordinates; a uniform bound needs none: AdaptiveView::maxError is already a fraction of
// the asset's longest side): a camera at `eye`
// looking at `lookAt` (up +y, or +z when looking along y), vertical field of view `fovDegrees`,
// a viewport of width x height pixels, `maxErrorPixels` on screen (Vulkan clip space, as the
// engine's cameras). ngi::Error on a degenerate camera (eye = lookAt) or bad values.
AdaptiveView assetAdaptiveView(const Asset& asset, glm::vec3 eye, glm::vec3 lookAt, float fovDegrees, uint32_t width,
                               uint32_t height, float maxErrorPixels);

// The full-resolution restored pyramid of one chart without the network: the stored level
// upsampled level by level with upsampleNested (bilinear; what the engine's
// mip_upsample.comp does), then its nested mip chain.
SurfacePyramid restoredPyramidWithoutSR(const Asset& asset, size_t chart = 0);

// The mesh drawn for `asset` at options.lod (or options.gridSize): for every chart exactly
// buildLodMesh (buildGridMesh) of its restored pyramid at the chart's own level for that
// LoD (chartLevelForAssetLevel: the same level index, the same density, clamped to the
// chart's levels; a grid size scales with the chart's resolution), de-normalized, with each
// vertex's normal, chart uv (grid vertex (i, j) of n per side: (i, j) / (n - 1); an adaptive
// tile's vertex: its full-resolution sample over the chart's resolution) and each triangle's chart.
// For one chart its triangle count is gridTriangleCount(selection.gridSize). With the
// Network restore, charts whose stored level the network's factor does not take to their full
// size are restored Bicubic (one network per asset); a network that restores no chart is
// restoreFullResolution's error. With options.adaptive, every chart's tiles are selected
// together (their seams and cross seams balanced, adaptive_lod.h) and drawn with their culled
// tiles (an exported mesh stays closed). Throws ngi::Error as restoreFullResolution does, if
// lod is not finite or outside [0, levelCount - 1], if gridSize is outside [2, full size], or
// for an invalid adaptive view.
AssetMesh assetMesh(const Asset& asset, const AssetMeshOptions& options = {});

}  // namespace ngi
