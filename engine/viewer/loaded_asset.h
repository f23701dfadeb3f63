// ngi-view: one asset opened in the viewer: the file's contents, its surface on the GPU
// (built and timed) and what the panel shows about it.
#pragma once

#include "ngi/asset.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/surface.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace ngi::view {

struct LoadedAsset {
    std::filesystem::path path;
    Asset asset;
    std::unique_ptr<vk::GeometryImageSurface> surface;
    uint64_t fileBytes = 0;        // bytes on disk
    double buildCpuMs = 0.0;       // read + upload + GPU build, wall clock
    double buildGpuMs = -1.0;      // GPU build (upload, restore, mip chain, geomorph targets); < 0: no timestamps
    // Mean 3D length of one row/column of the geometry image (normalized units): a grid of
    // N vertices per side has edges of about surfaceSpan / (N - 1). Used by auto LoD.
    float surfaceSpan = 1.0f;
    std::string metadataPretty;    // the META chunk, pretty-printed (or as stored if not JSON)

    // CR as the paper defines it: full^2 / stored^2 (cells per side).
    double compressionRatio() const;
};

// Reads `path`, builds its surface with `renderer` and waits for the GPU. ngi::Error with a
// message naming the file on any problem; nothing is kept then.
std::unique_ptr<LoadedAsset> loadAsset(const vk::Renderer& renderer, const std::filesystem::path& path);

// The continuous LoD at which the grid's triangle edges project to about `pixelsPerEdge`
// pixels, for a surface seen from `distance` with vertical field of view `fovYDegrees` in a
// viewport `viewportHeight` pixels tall; clamped to [0, levelCount - 1].
float autoLod(const LoadedAsset& loaded, float distance, float fovYDegrees, float viewportHeight, float pixelsPerEdge);

} // namespace ngi::view
