// ngi-view: one asset opened in the viewer: the file's contents, its surface on the GPU
// (built and timed) and what the panel shows about it.
#pragma once

#include "ngi/asset.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace ngi::view {

struct LoadedAsset {
    std::filesystem::path path;
    Asset asset;
    std::unique_ptr<vk::AssetSurface> surface;  // every chart, finer levels restored without a network
    // Finer levels restored by the super-resolution network; built on first use.
    std::unique_ptr<vk::AssetSurface> restored;
    // The adaptive draw of `surface` and of `restored` (tile trees read back from the GPU),
    // made on first use by adaptiveFor.
    std::unique_ptr<vk::AdaptiveSurface> adaptive, adaptiveRestored;
    std::unique_ptr<vk::SuperResolution> ownNetwork;  // the asset's own weights (WGHT chunk), if any
    std::string ownNetworkError;                      // why the WGHT chunk cannot be used
    // The shipped network the asset names (HEAD networkId/networkHash, ngi/network_catalog.h),
    // loaded when the asset has no WGHT chunk; else why not ("" when it names none).
    std::unique_ptr<vk::SuperResolution> namedNetwork;
    std::string namedNetworkProblem;
    std::vector<std::string> skippedNetworkFiles;  // network files that do not read, skipped ("FILE: PROBLEM")
    double restoredBuildGpuMs = -1.0;              // GPU build with the network (< 0: not built / no timestamps)
    double superResolutionMs = -1.0;               // of that, the network's forward pass
    uint64_t fileBytes = 0;                        // bytes on disk
    double buildCpuMs = 0.0;                       // read + upload + GPU build, wall clock
    double buildGpuMs = -1.0;  // GPU build (upload, restore, mip chain, geomorph targets); < 0: no timestamps
    // Mean 3D length of one row/column of the geometry image (normalized units): a grid of
    // N vertices per side has edges of about surfaceSpan / (N - 1). Used by auto LoD.
    float surfaceSpan = 1.0f;
    std::string metadataPretty;  // the META chunk laid out by indentedMetadata (bounded)

    // CR as the paper defines it: full^2 / stored^2 (cells per side, summed over the charts).
    double compressionRatio() const;
};

// Reads `path`, builds its surface with `renderer` and waits for the GPU. ngi::Error with a
// message naming the file on any problem; nothing is kept then. When the asset names a network
// and carries no weights, the shipped network it names is looked up in `networkDirs`
// (findAssetNetwork) and loaded as namedNetwork; a miss is kept in namedNetworkProblem.
std::unique_ptr<LoadedAsset> loadAsset(const vk::Renderer& renderer, const std::filesystem::path& path,
                                       std::span<const std::filesystem::path> networkDirs = {});

// The network that restores this asset: its own (WGHT chunk), then `shared` (--weights), then
// the shipped network it names.
vk::SuperResolution* networkFor(const LoadedAsset& loaded, vk::SuperResolution* shared);

// Why super-resolution cannot be used for this asset ("" when it can): no network, or one
// whose scale factor takes no chart's stored level to its full resolution (charts of another
// factor are restored bicubically: AssetSurface::build).
std::string superResolutionProblem(const LoadedAsset& loaded, vk::SuperResolution* shared);

// The adaptive draw of `drawn` (loaded.surface or loaded.restored), made on first use with
// `framesInFlight` regions for its tile records. ngi::Error on failure.
vk::AdaptiveSurface& adaptiveFor(LoadedAsset& loaded, const vk::Renderer& renderer, const vk::AssetSurface& drawn,
                                 uint32_t framesInFlight);

// Builds loaded.restored with the network (waits for the GPU, times the forward pass).
// ngi::Error on failure; loaded.restored stays empty then.
void buildRestored(LoadedAsset& loaded, const vk::Renderer& renderer, vk::SuperResolution* shared);

// The continuous LoD at which the grid's triangle edges project to about `pixelsPerEdge`
// pixels, for a surface seen from `distance` with vertical field of view `fovYDegrees` in a
// viewport `viewportHeight` pixels tall; clamped to [0, levelCount - 1].
float autoLod(const LoadedAsset& loaded, float distance, float fovYDegrees, float viewportHeight, float pixelsPerEdge);

}  // namespace ngi::view
