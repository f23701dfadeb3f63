// ngi engine: the adaptive LoD's tile selection on the GPU. Compute passes choose every
// instance's tiles, write their records and one indirect draw per (group, chart, level), so
// the CPU does no per-instance work in a frame. It is core's selectTiles (ngi/adaptive_lod.h,
// the CPU definition, CDLOD after Strugar 2009 with per-tile error bounds) restated as
// per-tile passes (shaders/tile_selection.glsl says how): the same tiles, levels, morphs and
// border states, crack-free across tiles and seams, and the same culling.
//
// Once per surface: the tile bounds of every chart (AdaptiveSurface::charts()), the tiles one
// level finer that share a vertex with each border tile across a seam, and the seam mates of
// every border sample go to GPU buffers (TileTree's bounds as their 16-byte codes, ngi/tile_bound_code.h:
// 20 bytes a tile with its chart and level).
// Per frame: recordSelect(jobs) records the passes for every job (an instance in a pass:
// its view, its world, the group whose draw it joins); recordDraw(group) draws a group's tiles
// in the host's pass with one vkCmdDrawIndirect per (chart, level) of the surface.
// Needs the drawIndirectFirstInstance feature (Context::drawIndirectFirstInstance); without
// it, the constructor throws and a host selects on the CPU (AdaptiveSurface::select).
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi_shared.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ngi::vk {

// One selection of a frame: an instance drawn in one pass.
struct GpuSelectionJob {
    AdaptiveView view;      // AdaptiveSurface::view() (or an object-space bound)
    glm::mat4 world{1.0f};  // object -> world, as DrawParams::world
    uint32_t group = 0;     // the draw it joins (recordDraw(group)): one pass's instances
};

// What the GPU selected for one job (read back after the frame: readStats).
struct GpuSelectionStats {
    uint32_t drawnTiles = 0;
    uint32_t culledFrustum = 0, culledBackface = 0;
    uint64_t triangles = 0;  // drawn, stitched borders counted (as TileSelection::triangles)
};

// One drawn tile as the GPU wrote it (readRecords: tests and tools).
struct GpuSelectedTile {
    uint32_t group = 0, chart = 0, level = 0, x = 0, y = 0;  // tile (x, y) of its level
    uint32_t instance = 0;                                   // the job
    float morph = 0.0f;
    uint16_t border[4 * kTileQuads] = {};  // the border vertices' states (NGI_TILE_COARSER_BIT | morph steps)
};

class GpuTileSelection {
public:
    // For `surface` (which must outlive this object): up to `maxJobs` jobs a frame in `groups`
    // groups, `tileCapacity` drawn tiles a frame over all jobs (a frame that selects more draws
    // what fits and reports the rest, Frame::overflow; recordSelect of a later frame grows the
    // records), `framesInFlight` sets of the per-frame buffers, so that a host selects a frame
    // while the GPU still draws the ones before it; the tile data is shared. `surface` must be
    // made for at least as many frames in flight (AdaptiveSurface's constructor: its level 0
    // residency keeps what frames in flight may draw). ngi::Error on failure, without the
    // drawIndirectFirstInstance feature, or for a zero count.
    GpuTileSelection(const Renderer& renderer, const AdaptiveSurface& surface, uint32_t maxJobs, uint32_t groups = 1,
                     uint32_t tileCapacity = 1u << 16, uint32_t framesInFlight = 1);
    GpuTileSelection(const GpuTileSelection&) = delete;
    GpuTileSelection& operator=(const GpuTileSelection&) = delete;

    // Records the selection of `jobs` (at most maxJobs, groups below `groups`, views valid:
    // validateAdaptiveView) into `cmd` with frame `frame`'s buffers (below framesInFlight),
    // outside any render pass, with the barriers that make its results visible to recordDraw's
    // indirect draws and vertex stage. The GPU must have finished the draws of the last frame
    // that used the same `frame` (a host cycles 0, 1, .., framesInFlight - 1 behind its fences).
    // A chart whose level 0 is not resident draws level 1 at the finest and is reported
    // (readFrame(frame).finestCharts). ngi::Error for bad jobs or a bad frame.
    void recordSelect(VkCommandBuffer cmd, std::span<const GpuSelectionJob> jobs, uint32_t frame = 0);

    // Records the draws of `group`'s tiles in the current pass (`pipeline` as
    // AdaptiveSurface::recordDraw's; null: the surface's own), params as there (viewProjection,
    // eye, mode, wireWidth, viewport; each tile uses its job's transforms). Returns the draw
    // calls recorded (one per chart and level; none before the first recordSelect with
    // `frame`). The draws are those of the last recordSelect with `frame` (its buffers): a host
    // draws a frame with the frame it selected it with. ngi::Error for a bad frame.
    uint32_t recordDraw(VkCommandBuffer cmd, uint32_t group, const DrawParams& params,
                        std::optional<VkExtent2D> extent = std::nullopt, const AdaptivePipeline* pipeline = nullptr,
                        uint32_t frame = 0);

    // After the GPU has run frame `frame` (the last recordSelect with it): what it selected.
    // ngi::Error for a bad frame.
    struct Frame {
        std::vector<GpuSelectionStats> jobs;  // per job of the last recordSelect
        uint32_t overflow = 0;                // tiles selected but not drawn (records full)
        // Charts whose level 0 a tile drew, or would have drawn had it been resident: what
        // AdaptiveSurface::recordResidency(cmd, finestCharts, ...) of the next frame needs.
        std::vector<size_t> finestCharts;
    };
    Frame readFrame(uint32_t frame = 0) const;
    // After the GPU has run frame `frame`: every drawn tile, bucket by bucket (in a bucket in no
    // particular order).
    std::vector<GpuSelectedTile> readRecords(uint32_t frame = 0) const;

    // Device memory: the static tile data, and the per-frame buffers (of every frame in flight).
    VkDeviceSize staticBytes() const;
    VkDeviceSize frameBytes() const;
    uint32_t tileCount() const { return tileCount_; }

private:
    // The buffers and sets of one frame in flight.
    struct FrameSet {
        UniqueBuffer charts, views, instances, bits, counters, countersRead, commands, records;
        VkDescriptorSet set = VK_NULL_HANDLE, drawSet = VK_NULL_HANDLE;
        uint32_t capacity = 0;  // records
        uint32_t lastJobs = 0;  // of its last recordSelect
        bool selected = false;  // a recordSelect was recorded with it
    };
    // Frame `frame`'s set; ngi::Error for a frame past those in flight.
    FrameSet& frameSet(uint32_t frame);
    const FrameSet& frameSet(uint32_t frame) const;
    void makeRecords(FrameSet& f, uint32_t capacity);
    void writeSet(const FrameSet& f);

    const Renderer* renderer_ = nullptr;
    const AdaptiveSurface* surface_ = nullptr;
    uint32_t maxJobs_ = 0, groups_ = 0;
    uint32_t tileCount_ = 0, wordsPerJob_ = 0, maxRoot_ = 0, bucketsPerGroup_ = 0, chartCount_ = 0;
    std::vector<FrameSet> frames_;
    uint32_t grownCapacity_ = 0;                     // the records every frame grows to (an overflow of any frame asks)
    std::vector<uint32_t> levelFirst_, levelCount_;  // [level]: its run of tiles
    UniqueBuffer tiles_, cross_, crossTiles_, perimeter_, mates_;
    std::vector<gpu::SelectionChart> chartRecords_;
    UniqueDescriptorSetLayout setLayout_, tilesLayout_;
    UniqueDescriptorPool pool_;
    UniquePipelineLayout layout_;
    UniquePipeline refine_, close_, count_, commandsPass_, write_;
};

}  // namespace ngi::vk
