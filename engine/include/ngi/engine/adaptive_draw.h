// ngi engine: the adaptive LoD draw of an asset: each tile of each chart's grid at its own
// level (ngi/adaptive_lod.h, the CPU definition; shaders/adaptive_surface.vert, its GPU
// mirror), chosen per view from the tile's projected error bound, crack-free across tiles and
// seams, geomorphed, tiles outside the frustum or facing away not drawn.
//
// Once per asset, after its build: every chart's restored levels are read back and their
// tile bounds measured on the CPU (TileTree; tens of milliseconds per 1025^2 chart). Per view:
// selectTiles on the CPU, then one instanced draw per (chart, level) of the selected tiles,
// each tile one 48-byte record (gpu::AdaptiveTile) in a host-written buffer.
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace ngi::vk {

struct AdaptiveDrawStats {
    uint32_t tiles = 0;        // selected
    uint32_t drawnTiles = 0;   // not culled
    uint32_t culled = 0;       // outside the frustum or facing away
    uint32_t forcedSplits = 0;
    uint32_t drawCalls = 0;
    uint64_t triangles = 0;    // drawn (stitched borders counted)
    uint64_t vertexInvocations = 0;
};

class AdaptiveSurface {
public:
    // `surface` built from `asset` (AssetSurface::build done and completed on the GPU; level 0
    // not released). Reads its levels back (waits for the GPU), measures the tile trees and
    // makes the draw pipeline for the renderer's own pass. `tileCapacity`: tile records one
    // frame may write (between two clear()s); `framesInFlight`: frames whose records the GPU
    // may still read while the next is recorded (each gets its own region of the buffer).
    // ngi::Error on failure.
    AdaptiveSurface(const Renderer& renderer, const AssetSurface& surface, const Asset& asset,
                    uint32_t tileCapacity = 1u << 15, uint32_t framesInFlight = 1);
    AdaptiveSurface(const AdaptiveSurface&) = delete;
    AdaptiveSurface& operator=(const AdaptiveSurface&) = delete;

    // The view of one instance: `viewProjection` world -> Vulkan clip space, `world` object ->
    // world (the asset's de-normalization is applied here), the eye in world space, the
    // viewport height in pixels and the budget in pixels. ngi::Error on bad values.
    AdaptiveView view(const glm::mat4& viewProjection, const glm::mat4& world, glm::vec3 eye, float viewportHeight,
                      float maxErrorPixels, bool cull = true) const;
    // The tiles for `view` (deterministic; the CPU definition).
    TileSelection select(const AdaptiveView& view) const;

    // Starts recording frame `frame`'s draws in its region (frame % framesInFlight) of the tile
    // buffer. Only once the GPU has finished the draws recorded into that region before.
    void clear(uint32_t frame = 0) { used_ = 0, region_ = frame % regions_; }
    // Records the draw of `selection`'s tiles that are not culled, inside the renderer's own
    // pass, with params.viewProjection, world, eye, mode, wireWidth and viewport as
    // Renderer::recordDraw (params.lod, gridSize and pipeline are not used: a host pipeline
    // is ngi::Error). ngi::Error when the tile records exceed the capacity.
    AdaptiveDrawStats recordDraw(VkCommandBuffer cmd, const TileSelection& selection, const DrawParams& params,
                                 std::optional<VkExtent2D> extent = std::nullopt);

    // The CPU mirror of chart c (its read-back pyramid and tile tree), for tests and tools.
    const std::vector<AdaptiveChart>& charts() const { return charts_; }
    const SurfaceMates& mates() const { return mates_; }
    // Device memory this object holds (the tile buffer), bytes.
    VkDeviceSize gpuBytes() const { return tiles_->size; }

private:
    const Renderer& renderer_;
    const AssetSurface& surface_;
    glm::mat4 objectFromNormalized_{1.0f};
    std::vector<SurfacePyramid> pyramids_;
    std::vector<TileTree> trees_;
    std::vector<AdaptiveChart> charts_;
    SurfaceMates mates_;
    uint32_t capacity_ = 0, used_ = 0, regions_ = 1, region_ = 0;
    UniqueBuffer tiles_;
    UniqueDescriptorSetLayout levelsLayout_;
    UniquePipelineLayout layout_;
    UniquePipeline pipeline_;
    UniqueDescriptorPool pool_;
    std::vector<std::vector<VkDescriptorSet>> levelSets_;  // [chart][level]: level, level + 1
    VkDescriptorSet tileSet_ = VK_NULL_HANDLE;
};

} // namespace ngi::vk
