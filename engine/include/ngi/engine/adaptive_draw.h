// ngi engine: the adaptive LoD draw of an asset: each tile of each chart's grid at its own
// level (ngi/adaptive_lod.h, the CPU definition; shaders/adaptive_surface.vert, its GPU
// mirror), chosen per view from the tile's projected error bound, crack-free across tiles and
// seams, geomorphed, tiles outside the frustum or facing away not drawn.
//
// Once per asset, after its build: every chart's restored levels are read back, the coarse
// ones fitted to the full surface (ngi/fitted_levels.h: they approximate it instead of
// interpolating it, so a bound is met by coarser tiles), all made compact
// (ngi/compact_texel.h: 8 bytes per sample, 16-bit positions on one lattice per asset and 2 x
// 8-bit octahedral normals, half of the restore's 16) and uploaded as the draw's own copy, and
// their tile bounds measured on the CPU from the compact levels, which are exactly what the
// GPU draws (TileTree; seconds for a 1025^2 chart on a laptop CPU). The AssetSurface is not
// read again: a host that draws only adaptively destroys it then and keeps half the memory.
// Per instance per pass: selectTiles on the CPU (or every instance and pass of a frame at once
// on the GPU: gpu_tile_selection.h), then one instanced draw per (chart, level) of the selected
// tiles, each tile one 48-byte record (gpu::AdaptiveTile) and each draw one
// instance record (gpu::AdaptiveInstance: clip and world transforms) in a host-written buffer.
// A host draws in its own passes with its own fragment shader through an AdaptivePipeline,
// whose vertex stage (shaders/adaptive_surface.vert) writes the outputs of ngi's public vertex
// stage (surface.vert): a material written for DrawBatch shades adaptive draws unchanged.
// A chart's base colour (AssetChart::baseColor, ChartColorImages) is bound with its levels
// (set 0, binding NGI_DRAW_BINDING_BASE_COLOUR = 3, fragment stage, as in the uniform draw) and sampled at the chart uv (vertex output 6); ngi's own
// shading (adaptive_surface.frag) uses it, a host's material may.
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/color_images.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace ngi::vk {

// The adaptive draw's pipeline for one pass: sets 0 (levels: bindings 0, 1 and 3 the tile's
// level and the next two coarser ones, vertex stage; 2 the chart's base colour, sampler2D,
// fragment stage)
// and 1 (tiles, instances) are ngi's, sets 2.. (firstHostSet) the host's `hostSetLayouts`; push
// constants gpu::DrawPushConstants (pc.eye: the camera in world space, pc.mode, pc.wireWidth).
// `fragmentSpirv` empty: ngi's shading (adaptive_surface.frag) when the pass has a colour attachment,
// none for a depth-only pass. ngi::Error naming the pass on failure.
class AdaptivePipeline {
public:
    static constexpr uint32_t firstHostSet = 2;
    AdaptivePipeline(const Renderer& renderer, const PassDescription& pass,
                     std::span<const uint32_t> fragmentSpirv = {},
                     std::span<const VkDescriptorSetLayout> hostSetLayouts = {});
    // With ngi's own shading, without or with the base colour's alpha test (`cutOut`,
    // NGI_SPEC_CUT_OUT in ngi_shared.h: for an asset a chart of whose colour cutsOut()); a
    // host's fragment shader has one pipeline, whatever `cutOut` says.
    VkPipeline pipeline(bool cutOut = false) const
    {
        return (cutOut && cutOutPipeline_.get() ? cutOutPipeline_ : pipeline_).get();
    }
    VkPipelineLayout layout() const { return layout_.get(); }
    // Sets 0 and 1 as this pipeline declares them (AdaptiveSurface allocates its sets with
    // identically defined layouts, which Vulkan binds interchangeably).
    static UniqueDescriptorSetLayout createLevelsLayout(VkDevice device);
    static UniqueDescriptorSetLayout createTilesLayout(VkDevice device);

private:
    UniqueDescriptorSetLayout levelsLayout_, tilesLayout_;
    UniquePipelineLayout layout_;
    UniquePipeline pipeline_, cutOutPipeline_;  // the second with ngi's own shading only
};

struct AdaptiveDrawStats {
    uint32_t tiles = 0;       // selected
    uint32_t drawnTiles = 0;  // not culled
    uint32_t culled = 0;      // outside the frustum or facing away
    uint32_t forcedSplits = 0;
    uint32_t drawCalls = 0;
    uint64_t triangles = 0;  // drawn (stitched borders counted)
    uint64_t vertexInvocations = 0;
};

class AdaptiveSurface {
public:
    // `surface` built from `asset` (AssetSurface::build done and completed on the GPU; level 0
    // not released). Reads its levels back (waits for the GPU), uploads their compact copy,
    // measures the tile trees and makes the draw pipeline for the renderer's own pass; keeps no
    // reference to `surface`, which may be destroyed afterwards. `tileCapacity`: tile records of
    // the first record block (a frame, between two clear()s, that draws more gets more blocks,
    // kept for later frames: the records grow to the most one frame has drawn);
    // `framesInFlight`: frames whose records the GPU may still read while the next is recorded
    // (each gets its own region of every block).
    // `uploadFinest`: every chart's level 0 is uploaded now; false: it stays in the host
    // copy until recordResidency (or makeResident) uploads it for a selection that draws it
    // (charts of a single level keep it resident). ngi::Error on failure.
    AdaptiveSurface(const Renderer& renderer, const AssetSurface& surface, const Asset& asset,
                    uint32_t tileCapacity = 1u << 15, uint32_t framesInFlight = 1, bool uploadFinest = true);
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
    void clear(uint32_t frame = 0) { block_ = 0, used_ = 0, instancesUsed_ = 0, region_ = frame % regions_; }
    // Records the draw of `selection`'s tiles that are not culled (one instance: `selection`
    // made with view() of the same matrices), inside the pass `pipeline` was made for (null:
    // the renderer's own pass and shading), with params.viewProjection, world, eye, mode,
    // wireWidth and viewport as Renderer::recordDraw (params.lod, gridSize and pipeline are
    // not used). Binds the pipeline, sets 0 and 1 and the push constants; a host binds its
    // sets 2.. with pipeline->layout(). ngi::Error when the records exceed the capacity.
    AdaptiveDrawStats recordDraw(VkCommandBuffer cmd, const TileSelection& selection, const DrawParams& params,
                                 std::optional<VkExtent2D> extent = std::nullopt,
                                 const AdaptivePipeline* pipeline = nullptr);

    // The CPU mirror of chart c (its read-back pyramid and tile tree), for tests and tools.
    const std::vector<AdaptiveChart>& charts() const { return charts_; }
    const SurfaceMates& mates() const { return mates_; }
    // Normalized asset space -> the asset's object space.
    const glm::mat4& objectFromNormalized() const { return objectFromNormalized_; }
    // Set 0 of the draws of chart `chart`'s level `level` (its texels, the next two coarser
    // levels', its base colour); VK_NULL_HANDLE for a level 0 that is not resident.
    VkDescriptorSet levelSet(size_t chart, uint32_t level) const
    {
        return level == 0 && !finestResident(chart) ? VK_NULL_HANDLE : levelSets_.at(chart).at(level);
    }
    // The renderer's own pass and shading (null when the renderer has no pass of its own).
    const AdaptivePipeline* ownPipeline() const { return ownPipeline_ ? &*ownPipeline_ : nullptr; }
    // Whether a chart's base colour has an alpha below 1 (ChartColorImages::cutsOut): the draws
    // bind AdaptivePipeline::pipeline(cutsOut()), for every chart of the asset.
    bool cutsOut() const { return colors_->cutsOut(); }
    // Residency of each chart's level 0 (three quarters of its compact levels' memory; the
    // coarser levels stay resident). Every level is resident after construction (unless the
    // constructor left level 0 on the host: uploadFinest).
    // recordResidency: outside any render pass, before recording the draws of `selections`
    // (this frame's, every instance and pass), records into `cmd` the upload of each chart's
    // level 0 that one of them draws and that is not resident (from the host copy this object
    // keeps), and gives back the level 0 of each chart that none has drawn for
    // max(idleFrames, framesInFlight) frames (or, left on the host at construction, has not
    // drawn yet): freed framesInFlight frames later (a frame still in flight may draw it, as a
    // GPU selection reports its draws late; a selection that needs it before then takes it
    // back without an upload). `frame` numbers frames as clear()'s does, never
    // decreasing, under clear()'s rule (the GPU has finished frame - framesInFlight). Returns
    // the charts uploaded. recordDraw of a selection that draws a level 0 not resident is
    // ngi::Error.
    uint32_t recordResidency(VkCommandBuffer cmd, std::span<const TileSelection* const> selections, uint64_t frame,
                             uint32_t idleFrames = 60);
    // The same for the charts `finestCharts` whose level 0 this frame draws (a GPU selection's
    // report of the previous frame, GpuTileSelection::Frame::finestCharts). ngi::Error for a
    // chart that does not exist.
    uint32_t recordResidency(VkCommandBuffer cmd, std::span<const size_t> finestCharts, uint64_t frame,
                             uint32_t idleFrames = 60);
    // The uploads of recordResidency, submitted and waited for; gives nothing back (tools, tests).
    uint32_t makeResident(std::span<const TileSelection* const> selections);
    bool finestResident(size_t chart) const { return finestImages_.at(chart).size() > 0; }
    // The frames in flight this surface was made for (its constructor's framesInFlight).
    uint32_t framesInFlight() const { return regions_; }
    uint32_t residentFinestCount() const;

    // Device memory this object holds, bytes: the compact levels resident now, the base colour
    // images (shared with the AssetSurface it was made from, which counts them too while it
    // lives) and the tile and instance buffers.
    VkDeviceSize gpuBytes() const { return levelBytes() + colorBytes() + recordBytes(); }
    VkDeviceSize levelBytes() const;
    VkDeviceSize colorBytes() const { return colors_ ? colors_->bytes() : 0; }
    VkDeviceSize recordBytes() const;

private:
    glm::mat4 objectFromNormalized_{1.0f};
    std::vector<SurfacePyramid> pyramids_;
    std::vector<TileTree> trees_;
    std::vector<AdaptiveChart> charts_;
    SurfaceMates mates_;
    // The tile and instance records: blocks, each its own buffers and set 1; a frame fills
    // block 0, then 1, ... (used_ and instancesUsed_ count in block_).
    struct RecordBlock {
        UniqueBuffer tiles, instances;
        UniqueDescriptorPool pool;
        VkDescriptorSet set = VK_NULL_HANDLE;
        uint32_t capacity = 0;          // tile records per frame region
        uint32_t instanceCapacity = 0;  // instance records (draws) per frame region
    };
    std::vector<RecordBlock> blocks_;
    // A block of `capacity` tile records per region, and an eighth as many instance records
    // (16 to 4096).
    RecordBlock makeRecordBlock(uint32_t capacity) const;
    uint32_t capacity_ = 0, block_ = 0, used_ = 0, regions_ = 1, region_ = 0;
    uint32_t instancesUsed_ = 0;
    // Level l of chart c as the draw binds it (null for a level 0 not resident).
    VkImageView levelView(size_t chart, uint32_t level) const;
    // The charts whose level 0 `selections` draw (a tile not culled).
    std::vector<size_t> finestNeeds(std::span<const TileSelection* const> selections) const;
    // Records in finestLastUsed_ that `charts` draw their level 0; appends those not resident to `missing`.
    void noteNeeds(std::span<const size_t> charts, uint64_t frame, std::vector<size_t>& missing);
    // Moves back into place the retired level 0 of each chart of `missing` that has one, and
    // removes those charts from `missing`.
    void takeBackRetired(std::vector<size_t>& missing);
    // Makes level 0 of `charts` and records its upload from one staging buffer, returned (it
    // must live until the GPU has run `cmd`).
    UniqueBuffer recordFinestUploads(VkCommandBuffer cmd, std::span<const size_t> charts);
    // Points chart c's level-0 draw set at its (new) level 0.
    void writeFinestSet(size_t chart);
    const Context* context_ = nullptr;
    VkSampler sampler_ = VK_NULL_HANDLE;
    ImagePool levels_;                               // every chart's compact levels 1.., chart by chart
    std::vector<uint32_t> firstImage_;               // [chart]: its level 1's image in levels_
    std::vector<ImagePool> finestImages_;            // [chart]: its compact level 0 (empty: given back)
    std::vector<std::vector<glm::u16vec4>> finest_;  // [chart]: the host copy of its compact level 0
    std::vector<uint64_t> finestLastUsed_;           // [chart]: the last frame a selection drew its level 0
    uint64_t lastFrame_ = 0;
    struct PendingUpload {
        uint64_t frame;        // recorded for
        UniqueBuffer staging;  // freed once that frame has finished
    };
    std::vector<PendingUpload> pendingUploads_;
    // A level 0 given back: freed once the frames in flight at the time have finished (a GPU
    // selection reports its draws frames late, so one of them may still draw it); taken back
    // as it is if a selection needs it before (its descriptor set still points at it).
    struct RetiredFinest {
        size_t chart;
        uint64_t frame;  // given back at
        ImagePool images;
    };
    std::vector<RetiredFinest> retired_;
    UniqueDescriptorSetLayout levelsLayout_, tilesLayout_;
    std::optional<AdaptivePipeline> ownPipeline_;     // the renderer's own pass and shading
    std::shared_ptr<const ChartColorImages> colors_;  // each chart's base colour (or the default grey)
    UniqueDescriptorPool pool_;
    std::vector<std::vector<VkDescriptorSet>> levelSets_;  // [chart][level]: level, level + 1, base colour
};

}  // namespace ngi::vk
